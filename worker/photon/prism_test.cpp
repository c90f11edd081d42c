// A BK7 prism disperses sunlight: where caustic photons land, against Snell's law with the
// glass's Sellmeier index (issue 18, acceptance 3).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "math/math.h"
#include "photon/photon_tracer.h"
#include "photon/trace_photons.h"
#include "photonmap/shard_format.h"
#include "scene/dispersion.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr double kDegree = std::numbers::pi / 180;
constexpr double kApex = 60 * kDegree;    // an equilateral prism
constexpr double kElevation = 20 * kDegree;  // the sun's rays climb at this angle: incidence 50°

// The prism: its edge along y, base on z = 0 from x = -1 to 1, apex at z = sqrt(3), of
// BK7 (ior its n_d, dispersion its Sellmeier fit), on a black stand; sunlight travelling
// +x and up by kElevation; a white wall at x = 6 catching what leaves the far face.
pb::Scene PrismScene() {
  pb::Scene s = MakeScene(4, 4, {0, -10, 1}, {0, 0, 1}, {0, 0, 1}, 40);
  AddLambert(s, "white", Rgb(0.8f));
  pb::Material* glass = s.add_materials();
  glass->set_name("bk7");
  glass->mutable_dielectric()->set_ior(IndexAt(*NamedGlass("BK7"), kFraunhoferD));
  glass->mutable_dielectric()->mutable_dispersion()->set_glass(pb::GLASS_BK7);
  const double h = std::sqrt(3.0);
  AddQuad(s, "bk7", {-1, -2, 0}, {1, 0, h}, {0, 4, 0});  // the near face, normal (-sqrt3, 0, 1) / 2
  AddQuad(s, "bk7", {1, -2, 0}, {0, 4, 0}, {-1, 0, h});  // the far face, normal (sqrt3, 0, 1) / 2
  AddQuad(s, "bk7", {-1, -2, 0}, {0, 4, 0}, {2, 0, 0});  // the base, normal -z
  // A black stand just under the base: sunlight climbing onto the base from below would
  // be reflected to the wall at exactly twice the elevation, among the dispersed light.
  AddLambert(s, "black", Rgb(0));
  AddQuad(s, "black", {-1, -2, -0.01}, {0, 4, 0}, {2, 0, 0});
  AddQuad(s, "white", {6, -3, -12}, {0, 0, 16}, {0, 6, 0});
  auto* sun = s.add_lights()->mutable_sun();
  Set(sun->mutable_direction(), {std::cos(kElevation), 0, std::sin(kElevation)});
  Set(sun->mutable_irradiance(), Rgb(1));
  return s;
}

// The deviation of a ray through the prism by Snell's law at index n: in at theta1 on the
// near face, out at theta4 on the far one, turned by theta1 + theta4 - apex.
double SnellDeviation(double n) {
  const double theta1 = kElevation + 30 * kDegree;
  const double theta2 = std::asin(std::sin(theta1) / n);
  const double theta4 = std::asin(n * std::sin(kApex - theta2));
  return theta1 + theta4 - kApex;
}

// The deviation of a photon stored on the wall: the angle from the sun's rays down to the
// way it came (-wi), in the x-z plane.
double Deviation(const ShardPhoton& p) { return kElevation - std::atan2(-p.wi.z, -p.wi.x); }

std::vector<ShardPhoton> WallPhotons(double wavelength_nm, uint64_t paths) {
  PhotonTraceOptions options;
  options.wavelength_nm = wavelength_nm;
  const Scene scene = Scene::Build(PrismScene(), NoBlobs());
  std::vector<ShardPhoton> photons = TracePhotons(scene, {PhotonMapKind::kCaustic, 0, paths, paths}, options);
  // Through both faces once: the photons of paths reflected inside the glass arrive from
  // elsewhere (or not at all); those are left out by their deviation's distance below.
  std::erase_if(photons, [](const ShardPhoton& p) { return std::abs(p.position.x - 6) > 1e-3; });
  return photons;
}

TEST(Prism, DeviationAtTheFraunhoferLinesIsSnellsWithTheSellmeierIndex) {
  const Dispersion bk7 = *NamedGlass("BK7");
  for (const double lambda : {kFraunhoferF, kFraunhoferD, kFraunhoferC}) {
    const double want = SnellDeviation(IndexAt(bk7, lambda));
    const std::vector<ShardPhoton> photons = WallPhotons(lambda, 20000);
    int through = 0;
    double sum = 0;
    for (const ShardPhoton& p : photons) {
      const double d = Deviation(p);
      if (std::abs(d - want) > 5 * kDegree) continue;
      sum += d;
      ++through;
    }
    ASSERT_GT(through, 1000) << lambda << " nm: " << photons.size() << " photons on the wall";
    const double mean = sum / through;
    EXPECT_NEAR(mean / kDegree, want / kDegree, 0.1) << lambda << " nm, " << through << " photons";
    std::printf("prism deviation at %.2f nm: %.4f° (Snell with BK7's Sellmeier index %.5f: %.4f°), %d photons\n",
                lambda, mean / kDegree, IndexAt(bk7, lambda), want / kDegree, through);
  }
}

TEST(Prism, WhiteLightFansOutRedLeastDeviatedVioletMost) {
  // Drawn wavelengths: every deviation lies between the ends of the visible range's, and
  // reddish photons are deviated less than bluish ones.
  const std::vector<ShardPhoton> photons = WallPhotons(0, 100000);
  const Dispersion bk7 = *NamedGlass("BK7");
  const double least = SnellDeviation(IndexAt(bk7, 830)), most = SnellDeviation(IndexAt(bk7, 360));
  double red_sum = 0, blue_sum = 0;
  int red = 0, blue = 0, through = 0;
  for (const ShardPhoton& p : photons) {
    const double d = Deviation(p);
    if (d < least - 1e-4 || d > most + 1e-4) continue;  // not straight through both faces
    ++through;
    EXPECT_TRUE(p.power.IsFinite());
    EXPECT_GE(std::min({p.power.r, p.power.g, p.power.b}), 0);
    if (p.power.r > 2 * (p.power.g + p.power.b)) red_sum += d, ++red;
    if (p.power.b > 2 * (p.power.r + p.power.g)) blue_sum += d, ++blue;
  }
  ASSERT_GT(through, 5000);
  ASSERT_GT(red, 500);
  ASSERT_GT(blue, 500);
  EXPECT_LT(red_sum / red + 0.5 * kDegree, blue_sum / blue)
      << "red " << red_sum / red / kDegree << "°, blue " << blue_sum / blue / kDegree << "°";
  std::printf("white light: %d photons between %.3f° and %.3f°; red ones at %.3f° on average, blue ones at %.3f°\n",
              through, least / kDegree, most / kDegree, red_sum / red / kDegree, blue_sum / blue / kDegree);
}

}  // namespace
}  // namespace farm
