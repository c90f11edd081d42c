// Photon tracing against closed forms: direct irradiance from a point and a sphere light,
// a glass ball's focal point, and the determinism and storage rules of the maps.

#include "photon/photon_tracer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <initializer_list>
#include <numbers>
#include <string>

#include "contract/failure.h"
#include "math/math.h"
#include "photon/trace_photons.h"
#include "photonmap/shard_format.h"
#include "scene/test_scenes.h"
#include "util/test_progress.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr double kPiD = std::numbers::pi;

// A black (absorbing) floor at z = 0, 40 x 40, and a camera that is never used.
pb::Scene FloorScene() {
  pb::Scene s = MakeScene(4, 4, {0, -10, 5}, {0, 0, 0}, {0, 0, 1}, 40);
  AddLambert(s, "black", Rgb(0));
  AddQuad(s, "black", {-20, -20, 0}, {40, 0, 0}, {0, 40, 0});
  return s;
}

std::vector<ShardPhoton> Trace(const pb::Scene& s, PhotonMapKind kind, uint64_t n,
                               PhotonTraceOptions options = {}) {
  const Scene scene = Scene::Build(s, NoBlobs());
  return TracePhotons(scene, {kind, 0, n, n}, options);
}

// Photon power (green) landing within radius r of `center` on the floor, per unit area.
double DiscIrradiance(const std::vector<ShardPhoton>& photons, const Vec3& center, float r) {
  double sum = 0;
  for (const ShardPhoton& p : photons)
    if (LengthSquared(p.position - center) <= r * r) sum += p.power.g;
  return sum / (kPiD * r * r);
}

// The average of E over the same disc, by numeric integration on a polar grid.
double DiscAverage(const std::function<double(double, double)>& E, double cx, double cy,
                   double r) {
  const int rings = 200, sectors = 64;
  double sum = 0, weight = 0;
  for (int i = 0; i < rings; ++i) {
    const double rho = (i + 0.5) * r / rings;
    for (int j = 0; j < sectors; ++j) {
      const double phi = 2 * kPiD * (j + 0.5) / sectors;
      sum += E(cx + rho * std::cos(phi), cy + rho * std::sin(phi)) * rho;
      weight += rho;
    }
  }
  return sum / weight;
}

// E(x) = I cos(theta) / d^2 = I h / (h^2 + x^2)^(3/2) on the floor of s under a point light
// at height h: the photons stored at the first hit (store_direct) within discs of radius
// 0.15 at x on the floor, from 1M photons (~5000 a disc: 1.4% noise, 1 sigma). Returns s
// with the light.
pb::Scene ExpectPointLightIrradiance(pb::Scene s, std::initializer_list<double> xs) {
  const double I = 3, h = 1;
  auto* light = s.add_lights()->mutable_point();
  Set(light->mutable_position(), {0, 0, h});
  Set(light->mutable_intensity(), Rgb(static_cast<float>(I)));
  PhotonTraceOptions direct;
  direct.store_direct = true;
  const auto photons = Trace(s, PhotonMapKind::kGlobal, 1'000'000, direct);
  const auto E = [&](double x, double y) { return I * h / std::pow(h * h + x * x + y * y, 1.5); };
  for (double x : xs) {
    const double expected = DiscAverage(E, x, 0, 0.15);
    EXPECT_NEAR(DiscIrradiance(photons, Vec3(float(x), 0, 0), 0.15f), expected, 0.06 * expected)
        << "x = " << x;
  }
  return s;
}

// A principled metal of base colour `base` (roughness 0: smooth, its lobe a delta).
void AddMetal(pb::Scene& s, const std::string& name, float base, float roughness) {
  pb::Material* m = s.add_materials();
  m->set_name(name);
  Set(m->mutable_principled()->mutable_base_color(), Rgb(base));
  m->mutable_principled()->set_metallic(1);
  m->mutable_principled()->set_roughness(roughness);
}

TEST(PhotonTracer, PointLightPhotonsGiveIntensityCosOverDistanceSquared) {
  const pb::Scene s = ExpectPointLightIrradiance(FloorScene(), {0.0, 0.5, 1.0, 2.0});
  // Without store_direct the global map holds indirect light only: none on a black floor.
  EXPECT_TRUE(Trace(s, PhotonMapKind::kGlobal, 10'000).empty());
}

TEST(PhotonTracer, ARoughMetalKeepsPhotonsOfTheIrradianceArrivingOnIt) {
  // The floor above made a rough principled metal, which has no diffuse share: it still
  // keeps photons (final gathering reads the irradiance where a gather ray lands, a metal
  // included), fewer of them carrying more power, so that they give the same E(x).
  pb::Scene s = FloorScene();
  AddMetal(s, "metal", 0.8f, 0.5f);
  s.mutable_shapes(0)->set_material("metal");
  ExpectPointLightIrradiance(s, {0.0, 1.0});
}

TEST(PhotonTracer, SpotLightPhotonsCarryTheConesClosedFormPowerWithItsFalloff) {
  // A spot at height h shining straight down, cones of 15 and 40 degrees (half-angles, as
  // KHR_lights_punctual's). Its power is I times the falloff's solid angle,
  // 2 pi I ((1 - cos inner) + (cos inner - cos outer) / 3), all of which lands on the floor;
  // the floor's irradiance is E = I s^2 cos / d^2 with s = (cos - cos outer) / (cos inner -
  // cos outer) clamped to [0, 1], nothing beyond the outer cone. 1M photons; the discs of
  // radius 0.1 below hold 10,000 to 50,000 photons (at most 1% noise, 1 sigma).
  pb::Scene s = FloorScene();
  const double I = 3, h = 1, inner = 15, outer = 40;
  auto* light = s.add_lights()->mutable_spot();
  Set(light->mutable_position(), {0, 0, h});
  Set(light->mutable_direction(), {0, 0, -1});
  Set(light->mutable_intensity(), Rgb(static_cast<float>(I)));
  light->set_inner_cone_degrees(inner);
  light->set_outer_cone_degrees(outer);
  PhotonTraceOptions direct;
  direct.store_direct = true;
  const auto photons = Trace(s, PhotonMapKind::kGlobal, 1'000'000, direct);

  const double ci = std::cos(inner * kPiD / 180), co = std::cos(outer * kPiD / 180);
  const double power = 2 * kPiD * I * ((1 - ci) + (ci - co) / 3);
  double total = 0;
  for (const ShardPhoton& p : photons) total += p.power.g;
  std::printf("spot: %zu photons, power %.6f, closed form %.6f\n", photons.size(), total, power);
  EXPECT_NEAR(total, power, 1e-4 * power);

  const auto E = [&](double x, double y) {
    const double d2 = x * x + y * y + h * h, c = h / std::sqrt(d2);
    const double t = std::clamp((c - co) / (ci - co), 0.0, 1.0);
    return I * t * t * c / d2;
  };
  for (double x : {0.0, 0.2, 0.4, 0.55}) {
    const double expected = DiscAverage(E, x, 0, 0.1);
    EXPECT_NEAR(DiscIrradiance(photons, Vec3(float(x), 0, 0), 0.1f), expected, 0.04 * expected)
        << "x = " << x;
  }
  // Nothing lands beyond the outer cone.
  for (const ShardPhoton& p : photons) ASSERT_LT(std::hypot(p.position.x, p.position.y), std::tan(outer * kPiD / 180) * h + 1e-3);
}

TEST(PhotonTracer, SphereLightPhotonsGivePiLTimesRadiusOverDistanceSquared) {
  // On the axis E = pi L (R / d)^2; off the axis, with the sphere above the horizon,
  // E = pi L R^2 cos(theta) / D^2 (a uniform sphere acts as a point of intensity pi R^2 L).
  pb::Scene s = FloorScene();
  const double L = 2, R = 0.5, d = 2;
  AddEmissive(s, "lamp", Rgb(static_cast<float>(L)));
  AddSphere(s, "lamp", {0, 0, d}, R);
  PhotonTraceOptions direct;
  direct.store_direct = true;
  const auto photons = Trace(s, PhotonMapKind::kGlobal, 1'000'000, direct);
  const auto E = [&](double x, double y) {
    const double D2 = x * x + y * y + d * d;
    return kPiD * L * R * R * (d / std::sqrt(D2)) / D2;
  };
  EXPECT_NEAR(E(0, 0), kPiD * L * (R / d) * (R / d), 1e-12);
  for (double x : {0.0, 1.0}) {
    const double expected = DiscAverage(E, x, 0, 0.2);
    EXPECT_NEAR(DiscIrradiance(photons, Vec3(float(x), 0, 0), 0.2f), expected, 0.06 * expected)
        << "x = " << x;
  }
}

// A square mirror of side `side` at height h over the floor of FloorScene, a point light
// of intensity 5 at height 1 under it, and its material "mirror" (reflectance 0.8).
pb::Scene MirrorOverPointLight(double side, double h) {
  pb::Scene s = FloorScene();
  pb::Material* m = s.add_materials();
  m->set_name("mirror");
  Set(m->mutable_mirror()->mutable_reflectance(), Rgb(0.8f));
  AddQuad(s, "mirror", {-side / 2, -side / 2, h}, {side, 0, 0}, {0, side, 0});
  auto* light = s.add_lights()->mutable_point();
  Set(light->mutable_position(), {0, 0, 1});
  Set(light->mutable_intensity(), Rgb(5));
  return s;
}

// The caustic of MirrorOverPointLight's mirror at height h on the floor, at each x of xs
// (within the mirror's reflection): that of an image light at height 2h - 1 with
// intensity rho_mirror * I.
void ExpectTheImageLightsCaustic(const pb::Scene& s, double h, std::initializer_list<double> xs) {
  const auto photons = Trace(s, PhotonMapKind::kCaustic, 400'000);
  const double image = 2 * h - 1;
  const auto E = [&](double x, double y) { return 0.8 * 5 * image / std::pow(image * image + x * x + y * y, 1.5); };
  for (double x : xs) {
    const double expected = DiscAverage(E, x, 0, 0.3);
    EXPECT_NEAR(DiscIrradiance(photons, Vec3(float(x), 0, 0), 0.3f), expected, 0.06 * expected)
        << "x = " << x;
  }
}

TEST(PhotonTracer, MirrorCausticMatchesTheMirrorImageOfAPointLight) {
  // A point light at height 1 over a white floor... reflected by a mirror ceiling at height
  // 2: the caustic map holds light -> mirror -> floor. The light is inside the mirror's
  // bounding sphere, so its photons leave as it emits.
  ExpectTheImageLightsCaustic(MirrorOverPointLight(12, 2), 2, {0.0, 1.5});
}

TEST(PhotonTracer, AMirrorCausticCountsEachPathForTheTargetItHitsFirst) {
  // A 2 x 2 mirror at height 4, the light outside its bounding sphere (so caustic photons
  // are aimed, not emitted plainly), and 25 small mirror balls above it, which it hides
  // from the light. Photons are aimed at 26 targets and a path counts only for the target
  // whose surface it hits first (photon_emission.h): those aimed at the hidden balls meet
  // the mirror first and must not add to its caustic (within |x| < 7/3 on the floor).
  pb::Scene s = MirrorOverPointLight(2, 4);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) AddSphere(s, "mirror", {-0.8 + 0.4 * i, -0.8 + 0.4 * j, 4.5}, 0.1);
  ExpectTheImageLightsCaustic(s, 4, {0.0, 1.2});
}

TEST(PhotonTracer, ASmoothPrincipledMetalCausticIsTheImageLightTimesSchlicksFresnel) {
  // As above with a smooth principled metal ceiling (base colour 0.8): its lobe counts as
  // a delta, so light -> ceiling -> floor is a caustic, weighted by Schlick's Fresnel at
  // the angle the image light's ray meets the floor at (the angle of reflection).
  pb::Scene s = FloorScene();
  AddMetal(s, "metal", 0.8f, 0);
  AddQuad(s, "metal", {-6, -6, 2}, {12, 0, 0}, {0, 12, 0});
  auto* light = s.add_lights()->mutable_point();
  Set(light->mutable_position(), {0, 0, 1});
  Set(light->mutable_intensity(), Rgb(5));
  const auto photons = Trace(s, PhotonMapKind::kCaustic, 400'000);
  const auto E = [&](double x, double y) {
    const double r2 = 9 + x * x + y * y, cos = 3 / std::sqrt(r2);
    return (0.8 + 0.2 * std::pow(1 - cos, 5)) * 5 * 3 / std::pow(r2, 1.5);
  };
  for (double x : {0.0, 1.5}) {
    const double expected = DiscAverage(E, x, 0, 0.3);
    EXPECT_NEAR(DiscIrradiance(photons, Vec3(float(x), 0, 0), 0.3f), expected, 0.06 * expected)
        << "x = " << x;
  }
  for (const ShardPhoton& p : photons) ASSERT_LT(p.position.z, 1) << "no photon on the ceiling";
}

TEST(PhotonTracer, GlassBallFocusesSunlightNearTheParaxialFocus) {
  // A ball lens of radius R and index n focuses paraxial rays at f = n R / (2 (n - 1)) from
  // its centre: 1.5 for R = 1, n = 1.5. Caustic photons of a sun straight down land on a
  // floor at twice that distance; each photon's incoming ray (position, wi) is followed back to
  // where it passes closest to the axis. Paraxial rays leave the ball at small angles to the
  // axis (below ~3 degrees: entry heights below ~0.08 R, where spherical aberration moves
  // the crossing by well under 1%), so their mean crossing is the paraxial focus.
  pb::Scene s = MakeScene(4, 4, {0, -10, 5}, {0, 0, 0}, {0, 0, 1}, 40);
  AddLambert(s, "white", Rgb(0.5f));
  pb::Material* glass = s.add_materials();
  glass->set_name("glass");
  glass->mutable_dielectric()->set_ior(1.5);
  AddSphere(s, "glass", {0, 0, 0}, 1);
  AddQuad(s, "white", {-4, -4, -3}, {8, 0, 0}, {0, 8, 0});
  auto* sun = s.add_lights()->mutable_sun();
  Set(sun->mutable_direction(), {0, 0, -1});
  Set(sun->mutable_irradiance(), Rgb(1));
  const auto photons = Trace(s, PhotonMapKind::kCaustic, 400'000);
  double sum_z = 0, sum_z2 = 0;
  int paraxial = 0;
  for (const ShardPhoton& p : photons) {
    const double wx = p.wi.x, wy = p.wi.y, wz = p.wi.z;
    const double sin2 = wx * wx + wy * wy;
    // Paraxial rays land near the axis too (radius ~ h at twice the focal distance); this
    // leaves out rays that left the ball steeply after internal reflections.
    const double r2 = Sqr(double(p.position.x)) + Sqr(double(p.position.y));
    if (wz <= 0 || sin2 > 0.05 * 0.05 || sin2 < 1e-12 || r2 > 0.1 * 0.1) continue;
    const double t = -(p.position.x * wx + p.position.y * wy) / sin2;
    const double z = p.position.z + t * wz;
    sum_z += z;
    sum_z2 += z * z;
    ++paraxial;
  }
  ASSERT_GT(paraxial, 1000);
  const double mean = sum_z / paraxial;
  const double spread = std::sqrt(std::max(0.0, sum_z2 / paraxial - mean * mean));
  const double f = 1.5 * 1 / (2 * (1.5 - 1));
  EXPECT_NEAR(-mean, f, 0.02 * f) << "spread " << spread << " over " << paraxial << " photons";
  // Energy: the caustic carries at most the sun's power through the ball's cross-section
  // (E pi R^2 = pi), and most of it (two interfaces of ~4-10% reflection each, more at the rim).
  double total = 0;
  for (const ShardPhoton& p : photons) total += p.power.g;
  EXPECT_LT(total, kPiD);
  EXPECT_GT(total, 0.7 * kPiD);
}

// A scene with every material kind: a Cornell-like box with a mirror ball, a glass ball, a
// glossy ball and a metal ball under a quad light.
pb::Scene MixedScene() {
  pb::Scene s = MakeScene(4, 4, {278, 273, -800}, {278, 273, 0}, {0, 1, 0}, 40, 1, 9);
  AddLambert(s, "white", Rgb(0.75f));
  AddLambert(s, "red", Rgb(0.6f, 0.05f, 0.05f));
  AddEmissive(s, "lamp", Rgb(15));
  pb::Material* m = s.add_materials();
  m->set_name("mirror");
  Set(m->mutable_mirror()->mutable_reflectance(), Rgb(0.9f));
  m = s.add_materials();
  m->set_name("glass");
  m->mutable_dielectric()->set_ior(1.5);
  m = s.add_materials();
  m->set_name("glossy");
  Set(m->mutable_glossy()->mutable_diffuse(), Rgb(0.3f));
  Set(m->mutable_glossy()->mutable_specular(), Rgb(0.5f));
  m->mutable_glossy()->set_exponent(50);
  m = s.add_materials();
  m->set_name("gold");
  Set(m->mutable_conductor()->mutable_eta(), Rgb(0.143f, 0.374f, 1.442f));
  Set(m->mutable_conductor()->mutable_k(), Rgb(3.983f, 2.385f, 1.603f));
  AddQuad(s, "white", {0, 0, 0}, {0, 0, 559}, {556, 0, 0});
  AddQuad(s, "white", {0, 0, 559}, {0, 548, 0}, {556, 0, 0});
  AddQuad(s, "red", {556, 0, 0}, {0, 0, 559}, {0, 548, 0});
  AddQuad(s, "white", {0, 548, 0}, {556, 0, 0}, {0, 0, 559});  // ceiling, facing down
  AddQuad(s, "lamp", {213, 547, 227}, {130, 0, 0}, {0, 0, 105});
  AddSphere(s, "mirror", {400, 100, 380}, 100);
  AddSphere(s, "glass", {170, 100, 200}, 100);
  AddSphere(s, "glossy", {420, 60, 120}, 60);
  AddSphere(s, "gold", {150, 60, 420}, 60);
  return s;
}

TEST(PhotonTracer, SplittingTheRangeIntoShardsGivesTheSamePhotonsBitForBit) {
  const Scene scene = Scene::Build(MixedScene(), NoBlobs());
  for (PhotonMapKind kind : {PhotonMapKind::kGlobal, PhotonMapKind::kCaustic}) {
    const uint64_t total = 30'000;
    const DecodedShard whole = DecodeShard(TracePhotonShard(scene, {kind, 0, total, total}));
    ASSERT_FALSE(whole.records.empty());
    std::vector<ShardRecord> parts;
    for (auto [first, count] : {std::pair<uint64_t, uint64_t>{0, 7'001}, {7'001, 1}, {7'002, 22'998}}) {
      const DecodedShard part = DecodeShard(TracePhotonShard(scene, {kind, first, count, total}));
      EXPECT_EQ(part.first_photon, first);
      EXPECT_EQ(part.photon_count, count);
      parts.insert(parts.end(), part.records.begin(), part.records.end());
    }
    ASSERT_EQ(parts.size(), whole.records.size());
    EXPECT_EQ(std::memcmp(parts.data(), whole.records.data(), parts.size() * sizeof(ShardRecord)), 0);
  }
}

// Round 2 of N paths per round traces absolute paths [N, 2N): its photons are those paths'
// (the second half of a 2N-path trace), fresh against round 1, and the shard's header counts
// from the round's start as the builder expects.
TEST(PhotonTracer, RoundOffsetTracesFreshPathsCountedFromTheRoundsStart) {
  const Scene scene = Scene::Build(MixedScene(), NoBlobs());
  const uint64_t n = 10'000;
  const DecodedShard round1 = DecodeShard(TracePhotonShard(scene, {PhotonMapKind::kGlobal, 0, n, n}));
  PhotonShardRequest second{PhotonMapKind::kGlobal, 0, n, n};
  second.round_offset = n;
  const DecodedShard round2 = DecodeShard(TracePhotonShard(scene, second));
  EXPECT_EQ(round2.first_photon, 0u);
  EXPECT_EQ(round2.photon_count, n);
  ASSERT_FALSE(round2.records.empty());
  ASSERT_FALSE(round1.records.empty());
  EXPECT_NE(std::memcmp(round1.records.data(), round2.records.data(), sizeof(ShardRecord)), 0);

  // The same absolute paths traced in one 2N-path run, with power scaled back to N paths.
  const DecodedShard both = DecodeShard(TracePhotonShard(scene, {PhotonMapKind::kGlobal, n, n, 2 * n}));
  ASSERT_EQ(both.records.size(), round2.records.size());
  for (std::size_t i = 0; i < both.records.size(); ++i) {
    EXPECT_EQ(both.records[i].position.x, round2.records[i].position.x);
    EXPECT_FLOAT_EQ(both.records[i].power.r * 2, round2.records[i].power.r);
  }
}

TEST(PhotonTracer, BytesDoNotDependOnTheThreadCount) {
  const Scene scene = Scene::Build(MixedScene(), NoBlobs());
  const PhotonShardRequest request{PhotonMapKind::kGlobal, 1000, 20'000, 50'000};
  const std::string parallel = TracePhotonShard(scene, request);
  std::string serial;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    serial = TracePhotonShard(scene, request);
  }
  EXPECT_EQ(parallel, serial);
}

TEST(PhotonTracer, NoPhotonOnASpecularSurfaceAndCausticsOnlyOnDiffuse) {
  const pb::Scene description = MixedScene();
  const Scene scene = Scene::Build(description, NoBlobs());
  const SceneData& data = scene.data();
  for (PhotonMapKind kind : {PhotonMapKind::kGlobal, PhotonMapKind::kCaustic}) {
    const auto photons = TracePhotons(scene, {kind, 0, 50'000, 50'000});
    EXPECT_GT(photons.size(), 1000u) << "kind " << int(kind);
    for (const ShardPhoton& p : photons) {
      ASSERT_TRUE(p.power.IsFinite());
      ASSERT_GE(Dot(p.wi, p.normal), 0);
      // A photon on a diffuse wall may lie close to a sphere where the sphere touches it.
      const bool on_diffuse_wall = std::any_of(data.shapes.begin(), data.shapes.end(), [&](const ShapeRecord& shape) {
        const auto* quad = std::get_if<QuadShape>(&shape.geometry);
        if (!quad || data.capabilities[shape.material].specular) return false;
        return std::abs(Dot(p.position - quad->origin, quad->normal)) < 1e-3f;
      });
      if (on_diffuse_wall) continue;
      for (const ShapeRecord& shape : data.shapes) {
        const auto* sphere = std::get_if<SphereShape>(&shape.geometry);
        if (!sphere || !data.capabilities[shape.material].specular) continue;
        ASSERT_GT(std::abs(Distance(p.position, sphere->center) - sphere->radius), 1e-2f)
            << "photon on " << shape.label << " at " << p.position;
      }
    }
  }
}

TEST(PhotonTracer, CausticMapIsEmptyWithoutSpecularSurfacesAndBadRequestsThrow) {
  pb::Scene s = FloorScene();
  auto* light = s.add_lights()->mutable_point();
  Set(light->mutable_position(), {0, 0, 1});
  Set(light->mutable_intensity(), Rgb(1));
  const Scene scene = Scene::Build(s, NoBlobs());
  EXPECT_TRUE(TracePhotons(scene, {PhotonMapKind::kCaustic, 0, 1000, 1000}).empty());
  EXPECT_THROW(TracePhotonShard(scene, {PhotonMapKind::kGlobal, 900, 200, 1000}),
               std::invalid_argument);
  EXPECT_THROW(TracePhotonShard(scene, {PhotonMapKind::kGlobal, 0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(TracePhotonShard(scene, {static_cast<PhotonMapKind>(7), 0, 1, 1}),
               std::invalid_argument);
}

// A shard that stores more photons than a shard may hold would hold the worker's memory:
// tracing stops and says which setting to lower. The closed box of MixedScene stores
// several photons a path.
TEST(PhotonTracer, AShardStoringMoreThanAShardMayHoldIsBadInput) {
  const Scene scene = Scene::Build(MixedScene(), NoBlobs());
  PhotonTraceOptions options;
  options.max_photons = 1000;
  const std::vector<ShardPhoton> few = TracePhotons(scene, {PhotonMapKind::kGlobal, 0, 100, 100'000}, options);
  ASSERT_LT(few.size(), 1000u);
  try {
    TracePhotons(scene, {PhotonMapKind::kGlobal, 0, 100'000, 100'000}, options);
    FAIL() << "traced a shard over the limit";
  } catch (const BadInputError& e) {
    EXPECT_STREQ(e.what(),
                 "photons.photons_per_shard: the global map's paths 0+100000 store more than the 1000 photons a "
                 "shard may hold (scene_limits.max_shard_photons); lower photons.photons_per_shard");
  }
}

// Progress counts photon paths traced, chunk by chunk, whatever they store: a shard of n
// paths adds n (the range spans several chunks and a partial last one).
TEST(PhotonTracer, ProgressCountsEveryPathOfTheShard) {
  const Scene scene = Scene::Build(MixedScene(), NoBlobs());
  for (const PhotonMapKind kind : {PhotonMapKind::kGlobal, PhotonMapKind::kCaustic}) {
    ProgressCounter counter{0};
    TracePhotonShard(scene, {kind, 1'000, 9'000, 20'000}, {}, Progress(counter));
    EXPECT_EQ(counter.load(), 9'000u);
  }
}

// Read from another thread while TBB traces, as the heartbeat does: it never goes back.
TEST(PhotonTracer, ProgressReadFromAnotherThreadOnlyGrows) {
  const Scene scene = Scene::Build(MixedScene(), NoBlobs());
  ProgressCounter counter{0};
  const auto seen = ProgressSeenDuring(counter, [&](Progress progress) {
    TracePhotons(scene, {PhotonMapKind::kGlobal, 0, 100'000, 100'000}, {}, {}, progress);
  });
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_EQ(counter.load(), 100'000u);
}

}  // namespace
}  // namespace farm
