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

bool InsideSomeTarget(const SceneData& scene, const Vec3& p) {
  for (const BoundingSphere& t : scene.specular_targets)
    if (LengthSquared(t.center - p) <= t.radius * t.radius) return true;
  return false;
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

// The caustic emission before issue 17, from the same random numbers: spheres chosen by
// the solid angle each subtends from the emission point itself, the density summed over
// every cone (for the sun, every shadow on its disc).
std::optional<PhotonRay> EmitByEveryCone(const SceneData& scene, PhotonRandom& random) {
  const float u_light = random.Get1D();
  const Vec2 u_origin = random.Get2D();
  const float u_target = random.Get1D();
  const Vec2 u_direction = random.Get2D();
  const auto pick = scene.light_power.Sample(u_light);
  const Light& light = scene.lights[pick.index];
  const std::vector<BoundingSphere>& targets = scene.specular_targets;
  std::vector<float> weights;
  std::optional<PhotonRay> photon;
  if (const auto* sun = std::get_if<SunLight>(&light)) {
    const std::optional<DistantDirection> d = SampleDistantDirection(*sun, u_direction);
    const Vec3 disc_center = sun->disc.CenterFor(d->w);
    auto project = [&](const Vec3& c) { return c - d->w * Dot(c - disc_center, d->w); };
    for (const BoundingSphere& t : targets) weights.push_back(t.radius * t.radius);
    const DiscreteDistribution choose(weights);
    const BoundingSphere& t = targets[choose.Sample(u_target).index];
    const Frame frame = Frame::FromZ(d->w);
    const Vec2 q = SampleUniformDiskConcentric(u_origin);
    const Vec3 p = project(t.center) + (frame.x * q.x + frame.y * q.y) * t.radius;
    float pdf_area = 0;
    for (std::size_t k = 0; k < targets.size(); ++k)
      if (LengthSquared(p - project(targets[k].center)) <= Sqr(targets[k].radius))
        pdf_area += choose.Pmf(static_cast<int>(k)) / (kPi * Sqr(targets[k].radius));
    photon = PhotonRay{Ray{p, d->w}, d->weight / pdf_area};
  } else {
    const std::optional<LightOrigin> o = SampleLightOrigin(light, u_origin);
    if (InsideSomeTarget(scene, o->p)) return std::nullopt;  // none in these scenes
    for (const BoundingSphere& t : targets) {
      const float sin2 = Sqr(t.radius) / LengthSquared(t.center - o->p);
      weights.push_back(2 * kPi * (sin2 < 1e-3f ? sin2 / 2 : 1 - std::sqrt(1 - sin2)));
    }
    const DiscreteDistribution choose(weights);
    const BoundingSphere& t = targets[choose.Sample(u_target).index];
    const Vec3 w = Normalize(SampleSphereFromPoint(t.center, t.radius, o->p, u_direction).p - o->p);
    float pdf = 0;
    for (std::size_t k = 0; k < targets.size(); ++k)
      pdf += choose.Pmf(static_cast<int>(k)) * SphereFromPointPdf(targets[k].center, targets[k].radius, o->p, w);
    const float cos_light = o->is_point ? 1 : Dot(o->n, w);
    if (!(pdf > 0) || !(cos_light > 0)) return std::nullopt;
    const Vec3 start = o->is_point ? o->p : OffsetRayOrigin(o->p, o->n, w, scene.ray_epsilon);
    photon = PhotonRay{Ray{start, w}, o->emission * (cos_light / (o->pdf_area * pdf))};
  }
  photon->power = photon->power / pick.pmf;
  return photon;
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
