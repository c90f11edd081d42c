// Caustic emission (issue 17): the aim's density against a pass over every cone, its
// integral over all directions, and a glass ball's caustic against the emission it
// replaced (each point's own solid angles, every cone summed), path for path.

#include "photon/photon_emission.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <variant>
#include <vector>

#include "math/frame.h"
#include "math/math.h"
#include "photon/every_cone_emission.h"
#include "photon/trace_photons.h"
#include "sampling/hash.h"
#include "sampling/sobol.h"
#include "sampling/warps.h"
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
  for (int i = 0; i < n; ++i) {
    const double r = 0.05 + 0.6 * Sqr(Unit(1, i));
    AddSphere(s, "metal", {-15 + 30 * Unit(2, i), -15 + 30 * Unit(3, i), r + 5 * Unit(4, i)}, r);
  }
  return s;
}

float EveryConePdf(const SceneData& scene, int light, const Vec3& o, const Vec3& w) {
  const CausticTargets& targets = scene.caustic_targets;
  float pdf = 0;
  for (int k = 0; k < targets.size(); ++k)
    pdf += targets.ForLight(light).Pmf(k) * SphereFromPointPdf(targets.sphere(k).center, targets.sphere(k).radius, o, w);
  return pdf;
}

TEST(CausticEmission, TheAimsDensityIsTheSumOverEveryCone) {
  const Scene built = Scene::Build(BallField(400), NoBlobs());
  const SceneData& scene = built.data();
  const CausticTargets& targets = scene.caustic_targets;
  ASSERT_EQ(targets.size(), 401);
  int checked = 0, rims = 0, lights_checked = 0;
  for (int light = 0; light < static_cast<int>(scene.lights.size()); ++light) {
    if (std::holds_alternative<SunLight>(scene.lights[light]) ||
        std::holds_alternative<EnvironmentLight>(scene.lights[light]))
      continue;
    ++lights_checked;
    for (uint64_t i = 0; i < 4000; ++i) {
      const std::optional<LightOrigin> o =
          SampleLightOrigin(scene.lights[light], {float(Unit(10 + light, i)), float(Unit(20 + light, i))});
      ASSERT_TRUE(o);
      ASSERT_FALSE(InsideSomeTarget(scene, o->p));
      // Directions sampled in one sphere's cone, a third of them at its very rim (where the
      // hierarchy's slack matters), and a quarter of them uniform over all directions.
      const int k = static_cast<int>(Unit(30, i) * targets.size()) % targets.size();
      const bool rim = i % 3 == 0;
      const Vec2 u{rim ? 1 - 1e-7f * float(Unit(40, i)) : float(Unit(41, i)), float(Unit(42, i))};
      Vec3 w = SampleUniformSphere({float(Unit(43, i)), float(Unit(44, i))});
      if (i % 4 != 0) w = Normalize(SampleSphereFromPoint(targets.sphere(k).center, targets.sphere(k).radius, o->p, u).p - o->p);
      const float expected = EveryConePdf(scene, light, o->p, w);
      const float got = CausticAimPdf(scene, light, o->p, w);
      ASSERT_NEAR(got, expected, 1e-5f * expected) << "light " << light << " path " << i;
      if (expected > 0) ++checked;
      if (rim && expected > 0 && i % 4 != 0) ++rims;
    }
  }
  EXPECT_EQ(lights_checked, 3);
  EXPECT_GT(checked, 7000);
  EXPECT_GT(rims, 2000);
}

TEST(CausticEmission, APointLightsTableIsEachSpheresSolidAngleFromIt) {
  const Scene built = Scene::Build(BallField(50), NoBlobs());
  const SceneData& scene = built.data();
  const int light = static_cast<int>(scene.lights.size()) - 1;  // Scene.lights come last
  const auto* point = std::get_if<PointLight>(&scene.lights[light]);
  ASSERT_TRUE(point);
  const CausticTargets& targets = scene.caustic_targets;
  std::vector<double> solid_angle;
  double sum = 0;
  for (int k = 0; k < targets.size(); ++k) {
    const double d = Length(Vec3d(targets.sphere(k).center - point->position)), r = targets.sphere(k).radius;
    sum += solid_angle.emplace_back(2 * std::numbers::pi * (1 - std::sqrt(1 - r * r / (d * d))));
  }
  for (int k = 0; k < targets.size(); ++k)
    EXPECT_NEAR(targets.ForLight(light).Pmf(k), solid_angle[k] / sum, 1e-4 * solid_angle[k] / sum) << k;
}

TEST(CausticEmission, TheAimsDensityIntegratesToOneOverAllDirections) {
  // The mean of 4 pi pdf(w) over uniform directions w is 1, within 5 standard errors.
  const Scene built = Scene::Build(BallField(400), NoBlobs());
  const SceneData& scene = built.data();
  const int n = 400'000;
  for (int light = 0; light < static_cast<int>(scene.lights.size()); ++light) {
    const std::optional<LightOrigin> o = SampleLightOrigin(scene.lights[light], {0.3f, 0.6f});
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
      const Vec3 w = SampleUniformSphere({float(Unit(50 + light, i)), float(Unit(60 + light, i))});
      const double x = 4 * std::numbers::pi * CausticAimPdf(scene, light, o->p, w);
      sum += x;
      sum2 += x * x;
    }
    const double mean = sum / n, error = std::sqrt((sum2 / n - mean * mean) / n);
    EXPECT_LT(error, 0.02) << "light " << light;
    EXPECT_NEAR(mean, 1, 5 * error) << "light " << light;
  }
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
