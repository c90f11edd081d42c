#include "scene/lights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "math/math.h"
#include "sampling/sobol.h"

namespace farm {
namespace {

constexpr double kPiD = std::numbers::pi;

// Differential form factor from a point to an a x b rectangle parallel to its tangent plane,
// the point on the normal through one corner at distance c (Howell's catalogue, C-11).
double CornerFormFactor(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * kPiD);
}

// Monte Carlo irradiance at `ref` with normal +z: E = integral of L cos over the light,
// estimated with the light's own samples (no visibility).
double EstimateIrradiance(const Light& light, const Vec3& ref, int n = 1 << 14) {
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const Vec2 u{SobolSample(i, 0, 3), SobolSample(i, 1, 4)};
    const auto s = SampleLi(light, ref, u);
    if (!s) continue;
    EXPECT_GT(s->pdf, 0);
    EXPECT_NEAR(Length(s->wi), 1, 1e-5);
    sum += s->radiance.g * std::max(0.0f, s->wi.z) / s->pdf;
  }
  return sum / n;
}

TEST(Lights, SphereLightIrradianceOnItsAxis) {
  // E = pi L (R / d)^2 for a point facing a sphere of radius R at centre distance d.
  const float radius = 1, d = 4, radiance = 2;
  const Light light = SphereLight{{{0, 0, d}, radius}, Rgb(radiance)};
  SCOPED_TRACE(ToString(light));
  const double expected = kPiD * radiance * (radius / d) * (radius / d);
  EXPECT_NEAR(EstimateIrradiance(light, {0, 0, 0}), expected, 2e-3 * expected);
}

TEST(Lights, QuadLightIrradianceMatchesTheFormFactor) {
  // A 2 x 3 rectangle 1.5 above the point, centred on its normal, facing down.
  const float a = 2, b = 3, c = 1.5f, radiance = 1.5f;
  const Light light =
      QuadLight{QuadShape::Make({-a / 2, -b / 2, c}, {0, b, 0}, {a, 0, 0}), Rgb(radiance)};
  ASSERT_EQ(std::get<QuadLight>(light).quad.normal, Vec3(0, 0, -1));
  const double expected = kPiD * radiance * 4 * CornerFormFactor(a / 2, b / 2, c);
  EXPECT_NEAR(EstimateIrradiance(light, {0, 0, 0}), expected, 5e-3 * expected);
}

TEST(Lights, MeshLightIrradianceMatchesTheFormFactor) {
  // The same rectangle as two triangles of different sizes (area sampling by CDF), facing
  // down, plus a tiny triangle far away that must not bias the estimate.
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->positions = {{-1, -1.5f, 1.5f}, {1, -1.5f, 1.5f}, {1, 1.5f, 1.5f}, {-1, 1.5f, 1.5f},
                     {50, 50, 1.5f},    {50.01f, 50, 1.5f}, {50, 50.01f, 1.5f}};
  mesh->indices = {0, 2, 1, 0, 3, 2, 4, 6, 5};  // clockwise from above: front is -z
  const Light light = TriangleMeshLight::Make(mesh, Rgb(1.5f));
  SCOPED_TRACE(ToString(light));
  const double expected = kPiD * 1.5 * 4 * CornerFormFactor(1, 1.5, 1.5);
  EXPECT_NEAR(EstimateIrradiance(light, {0, 0, 0}, 1 << 16), expected, 1e-2 * expected);
  EXPECT_NEAR(std::get<TriangleMeshLight>(light).area, 6 + 0.5e-4, 1e-4);
}

TEST(Lights, EmitOnlyFromTheFront) {
  const Light up_facing = QuadLight{QuadShape::Make({-1, -1, 1}, {2, 0, 0}, {0, 2, 0}), Rgb(1)};
  EXPECT_FALSE(SampleLi(up_facing, {0, 0, 0}, {0.5f, 0.5f}));
  EXPECT_TRUE(SampleLi(up_facing, {0, 0, 2}, {0.5f, 0.5f}));
  // Inside a sphere light, its outward front faces away: no light.
  const Light sphere = SphereLight{{{0, 0, 0}, 2}, Rgb(1)};
  EXPECT_FALSE(SampleLi(sphere, {0.5f, 0, 0}, {0.3f, 0.6f}));
}

TEST(Lights, PowerIsPiTimesAreaTimesRadiance) {
  const Light sphere = SphereLight{{{0, 0, 0}, 2}, Rgb(3)};
  EXPECT_NEAR(Power(sphere).r, kPiD * 4 * kPiD * 4 * 3, 1e-3);
}

}  // namespace
}  // namespace farm

namespace farm {
namespace {

TEST(Lights, PointLightIrradianceIsIntensityOverDistanceSquared) {
  const Light light = PointLight{{0, 0, 4}, Rgb(8)};
  const auto s = SampleLi(light, {3, 0, 0}, {0.3f, 0.7f});
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->delta);
  EXPECT_FLOAT_EQ(s->distance, 5);
  EXPECT_FLOAT_EQ(s->radiance.g, 8.0f / 25);
  EXPECT_NEAR(Distance(s->wi, Vec3(-0.6f, 0, 0.8f)), 0, 1e-6);
  EXPECT_NEAR(Power(light).r, 4 * kPiD * 8, 1e-4);
}

TEST(Lights, SunComesFromOneDirectionAndItsDiscCoversTheScene) {
  const BoundingSphere scene{{1, 2, 3}, 10};
  const Light light = SunLight::Make(Normalize(Vec3(0, -1, 0)), Rgb(2), scene);
  SCOPED_TRACE(ToString(light));
  const auto s = SampleLi(light, {5, 2, 3}, {0.1f, 0.9f});
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->delta);
  EXPECT_EQ(s->wi, Vec3(0, 1, 0));
  EXPECT_EQ(s->radiance, Rgb(2));
  EXPECT_GT(Distance(s->p, scene.center), scene.radius);  // the shadow ray leaves the scene
  const SunLight& sun = std::get<SunLight>(light);
  EXPECT_GE(sun.disc_radius, 10);
  EXPECT_GE(sun.disc_center.y - scene.center.y, 10);
  // Every photon starts outside the scene's sphere, travelling along the direction, and all
  // photons together carry E * disc area.
  for (int i = 0; i < 64; ++i) {
    const auto e = SampleLe(light, {SobolSample(i, 0, 1), SobolSample(i, 1, 2)}, {0.5f, 0.5f});
    ASSERT_TRUE(e);
    EXPECT_EQ(e->w, sun.direction);
    EXPECT_GE(e->p.y - scene.center.y, scene.radius);
    EXPECT_NEAR(e->power.r, 2 * kPiD * sun.disc_radius * sun.disc_radius, 1e-2);
  }
}

TEST(Lights, EveryPhotonOfALightCarriesItsPower) {
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->positions = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {5, 5, 5}, {6, 5, 5}, {5, 6, 5}};
  mesh->indices = {0, 1, 2, 3, 4, 5};
  const Light lights[] = {SphereLight{{{0, 0, 0}, 2}, Rgb(3)},
                          QuadLight{QuadShape::Make({0, 0, 0}, {2, 0, 0}, {0, 3, 0}), Rgb(1)},
                          TriangleMeshLight::Make(mesh, Rgb(2)), PointLight{{1, 1, 1}, Rgb(5)}};
  for (const Light& light : lights) {
    SCOPED_TRACE(ToString(light));
    for (int i = 0; i < 256; ++i) {
      const auto e = SampleLe(light, {SobolSample(i, 0, 1), SobolSample(i, 1, 2)},
                              {SobolSample(i, 0, 3), SobolSample(i, 1, 4)});
      ASSERT_TRUE(e);
      EXPECT_NEAR(Length(e->w), 1, 1e-5);
      EXPECT_NEAR(e->power.r, Power(light).r, 1e-3 * Power(light).r);
      if (!IsDeltaLight(light)) {
        EXPECT_GT(Dot(e->w, e->n), 0);  // leaves the front
      }
    }
  }
}

}  // namespace
}  // namespace farm
