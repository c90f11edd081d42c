// Caustic emission (issue 17): a glass ball's caustic among metal balls, under lamps and
// under the sun, against the emission before issue 17 (each point's own solid angles,
// every cone summed: photon/every_cone_emission.h), path for path from the same random
// numbers. Aiming by ownership (photon_emission.h) must give the same caustic in
// expectation.

#include "photon/photon_emission.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "math/math.h"
#include "photon/every_cone_emission.h"
#include "photon/trace_photons.h"
#include "sampling/hash.h"
#include "sampling/sobol.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

double Unit(uint64_t seed, uint64_t i) { return FractionToFloat(static_cast<uint32_t>(Hash(seed, i))); }

// A floor and a field of `n` metal balls of assorted sizes and a glass ball under a quad
// lamp, a sphere lamp and a point light (or no light).
pb::Scene BallField(int n, bool lamps = true) {
  pb::Scene s = MakeScene(4, 4, {0, -30, 10}, {0, 0, 0}, {0, 0, 1}, 40);
  AddLambert(s, "white", Rgb(0.5f));
  AddEmissive(s, "lamp", Rgb(4));
  pb::Material* metal = s.add_materials();
  metal->set_name("metal");
  Set(metal->mutable_mirror()->mutable_reflectance(), Rgb(0.9f));
  pb::Material* glass = s.add_materials();
  glass->set_name("glass");
  glass->mutable_dielectric()->set_ior(1.5);
  AddQuad(s, "white", {-20, -20, 0}, {40, 0, 0}, {0, 40, 0});
  if (lamps) {
    AddQuad(s, "lamp", {-1, -1, 8}, {0, 2, 0}, {2, 0, 0});  // facing down
    AddSphere(s, "lamp", {6, 4, 7}, 0.5);
    AddPointLight(s, {-5, 3, 7.5}, Rgb(20));
  }
  AddSphere(s, "glass", {0, 0, 2}, 1);
  // Four small balls under the glass one, hidden behind it from the lights: photons aimed
  // at them mostly hit the glass first (counted twice if aiming lost track of ownership).
  for (const double x : {-0.4, 0.4})
    for (const double y : {-0.4, 0.4}) AddSphere(s, "metal", {x, y, 0.6}, 0.25);
  for (int i = 0; i < n; ++i) {
    const double r = 0.05 + 0.6 * Sqr(Unit(1, i));
    AddSphere(s, "metal", {-15 + 30 * Unit(2, i), -15 + 30 * Unit(3, i), r + 5 * Unit(4, i)}, r);
  }
  return s;
}

struct PerPath {
  double sum = 0, sum2 = 0;
  void Add(double x) {
    sum += x;
    sum2 += x * x;
  }
};

// The mean caustic irradiance on the floor within 1.5 of the glass ball's foot, path by
// path, with this emission and with EmitByEveryCone from the same random numbers: the
// paired difference's mean is 0 within 4 of its standard errors.
void ExpectTheSameCausticAsEveryCone(const pb::Scene& description, int paths) {
  const Scene built = Scene::Build(description, NoBlobs());
  const SceneData& scene = built.data();
  const float radius = 1.5f;
  const auto irradiance = [&](const std::vector<ShardPhoton>& photons) {
    double e = 0;
    for (const ShardPhoton& p : photons)
      if (Sqr(p.position.x) + Sqr(p.position.y) <= radius * radius && p.position.z < 1e-3f) e += p.power.g;
    return e / (kPi * radius * radius);
  };
  PerPath now, before, difference;
  std::vector<ShardPhoton> out;
  for (int i = 0; i < paths; ++i) {
    out.clear();
    TracePhotonPath(scene, PhotonMapKind::kCaustic, i, 1, {}, out);
    const double a = irradiance(out);
    out.clear();
    PhotonRandom random(scene.seed, PhotonMapKind::kCaustic, i);
    if (const std::optional<PhotonRay> e = EmitByEveryCone(scene, random))
      ContinuePhotonPath(scene, PhotonMapKind::kCaustic, *e, random, 1, {}, out);
    const double b = irradiance(out);
    now.Add(a);
    before.Add(b);
    difference.Add(a - b);
  }
  const auto mean = [&](const PerPath& p) { return p.sum / paths; };
  const auto error = [&](const PerPath& p) { return std::sqrt((p.sum2 / paths - Sqr(mean(p))) / paths); };
  EXPECT_GT(mean(before), 20 * error(before)) << "the caustic is well resolved";
  EXPECT_LT(error(difference), 0.03 * mean(before)) << "the bound is tight enough to see a 10% bias";
  EXPECT_NEAR(mean(now), mean(before), 4 * error(difference))
      << "now " << mean(now) << " +- " << error(now) << ", before " << mean(before) << " +- " << error(before);
}

TEST(CausticEmission, AGlassBallsCausticUnderLampsIsTheSameAsWithEveryConeSummed) {
  ExpectTheSameCausticAsEveryCone(BallField(60), 400'000);
}

TEST(CausticEmission, AGlassBallsCausticUnderTheSunIsTheSameAsWithEveryShadowSummed) {
  pb::Scene s = BallField(60, false);
  auto* sun = s.add_lights()->mutable_sun();
  Set(sun->mutable_direction(), {0.2, 0.1, -1});
  Set(sun->mutable_irradiance(), Rgb(1));
  ExpectTheSameCausticAsEveryCone(s, 200'000);
}

}  // namespace
}  // namespace farm
