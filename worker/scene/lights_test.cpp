#include "scene/lights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

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

// Single scattering draws its distance towards the point SampleLightOrigin picks on a quad
// or mesh light, then asks SampleLi for the same point (render/media_transport.cpp): by
// area, the point must not depend on where it is seen from.
TEST(Lights, AreaLightsSampleThePointOfTheirOriginWhereverTheShadingPoint) {
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->positions = {{-1, -1, 2}, {1, -1, 2}, {0, 1, 2.5f}};
  mesh->indices = {0, 2, 1};
  const std::vector<Light> lights = {QuadLight{QuadShape::Make({-1, -1, 2}, {0, 2, 0}, {2, 0, 0}), Rgb(1)},
                                     TriangleMeshLight::Make(mesh, Rgb(1))};
  for (const Light& light : lights)
    for (int i = 0; i < 64; ++i) {
      const Vec2 u{SobolSample(i, 0, 5), SobolSample(i, 1, 6)};
      const std::optional<LightOrigin> origin = SampleLightOrigin(light, u);
      ASSERT_TRUE(origin);
      for (const Vec3& ref : {Vec3(0, 0, 0), Vec3(3, -2, 0.5f), Vec3(0.1f, 0.2f, 1.9f)}) {
        const std::optional<LightSample> s = SampleLi(light, ref, u);
        ASSERT_TRUE(s) << ToString(light);
        EXPECT_EQ(s->p, origin->p) << ToString(light);
      }
    }
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
  const Light light = SunLight::Make(Normalize(Vec3(0, -1, 0)), Rgb(2), 0, scene);
  SCOPED_TRACE(ToString(light));
  const auto s = SampleLi(light, {5, 2, 3}, {0.1f, 0.9f});
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->delta);
  EXPECT_EQ(s->wi, Vec3(0, 1, 0));
  EXPECT_EQ(s->radiance, Rgb(2));
  EXPECT_GT(Distance(s->p, scene.center), scene.radius);  // the shadow ray leaves the scene
  const SunLight& sun = std::get<SunLight>(light);
  EXPECT_GE(sun.disc.radius, 10);
  EXPECT_GE(sun.disc.CenterFor(sun.direction).y - scene.center.y, 10);
  // Every photon starts outside the scene's sphere, travelling along the direction, and all
  // photons together carry E * disc area.
  for (int i = 0; i < 64; ++i) {
    const auto e = SampleLe(light, {SobolSample(i, 0, 1), SobolSample(i, 1, 2)}, {0.5f, 0.5f});
    ASSERT_TRUE(e);
    EXPECT_EQ(e->w, sun.direction);
    EXPECT_GE(e->p.y - scene.center.y, scene.radius);
    EXPECT_NEAR(e->power.r, 2 * kPiD * sun.disc.radius * sun.disc.radius, 1e-2);
  }
}

// LightSampleAlong inverts SampleLi: for each direction SampleLi draws (a ray from ref
// along it meets the light where SampleLi put the point), it gives the same radiance and
// density, which is what MIS weighs a ray traced some other way against. Delta lights and
// directions SampleLi never draws give nothing.
TEST(Lights, LightSampleAlongInvertsSampleLi) {
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->positions = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {5, 5, 5}, {6, 5, 5}, {5, 6, 5}};
  mesh->indices = {0, 1, 2, 3, 4, 5};
  EnvironmentImage sky{4, 2, {Rgb(1), Rgb(2), Rgb(3), Rgb(4), Rgb(0.5f), Rgb(6), Rgb(7), Rgb(0.1f)}};
  const BoundingSphere scene{{0, 0, 0}, 10};
  const Light lights[] = {
      SphereLight{{{3, 1, 8}, 2}, Rgb(3)},
      SphereLight{{{0, 0, 0}, 0.01f}, Rgb(3)},  // tiny: a narrow cone
      QuadLight{QuadShape::Make({0, 0, 4}, {0, 3, 0}, {2, 0, 0}), Rgb(1)},  // its front faces -z
      TriangleMeshLight::Make(mesh, Rgb(2)),
      SunLight::Make(Normalize(Vec3(0.3f, -1, 0.2f)), Rgb(4), 0.53, scene),
      EnvironmentLight{std::make_shared<Environment>(Environment::Map(sky, Rgb(1), 30)), DistantDisc::Around(scene)},
  };
  const Vec3 ref(0.5f, -3, 1);
  for (const Light& light : lights) {
    SCOPED_TRACE(ToString(light));
    int found = 0;
    for (int i = 0; i < 256; ++i) {
      const std::optional<LightSample> s = SampleLi(light, ref, {SobolSample(i, 0, 5), SobolSample(i, 1, 6)});
      if (!s) continue;
      ++found;
      const std::optional<LightSample> back = LightSampleAlong(light, ref, s->wi, s->p, s->n);
      ASSERT_TRUE(back) << "wi " << s->wi;
      EXPECT_NEAR(back->pdf / s->pdf, 1, 1e-3) << "wi " << s->wi;
      EXPECT_NEAR(back->radiance.g / s->radiance.g, 1, 1e-3) << "wi " << s->wi;
      EXPECT_NEAR(back->distance / s->distance, 1, 1e-3);
    }
    EXPECT_GT(found, 128);
  }
  // The back of a quad, beside the sun's disc, and delta lights: never drawn.
  const Light quad = QuadLight{QuadShape::Make({0, 0, 4}, {0, 3, 0}, {2, 0, 0}), Rgb(1)};
  EXPECT_TRUE(LightSampleAlong(quad, Vec3(1, 1, 2), Vec3(0, 0, 1), Vec3(1, 1, 4), Vec3(0, 0, -1)));
  EXPECT_FALSE(LightSampleAlong(quad, Vec3(1, 1, 6), Vec3(0, 0, -1), Vec3(1, 1, 4), Vec3(0, 0, -1)));
  const Light sun = SunLight::Make(Vec3(0, -1, 0), Rgb(4), 0.53, scene);
  EXPECT_TRUE(LightSampleAlong(sun, ref, Vec3(0, 1, 0), Vec3(), Vec3()));
  EXPECT_FALSE(LightSampleAlong(sun, ref, Normalize(Vec3(0.01f, 1, 0)), Vec3(), Vec3())) << "0.57 degrees off";
  EXPECT_FALSE(LightSampleAlong(SunLight::Make(Vec3(0, -1, 0), Rgb(4), 0, scene), ref, Vec3(0, 1, 0), Vec3(), Vec3()));
  EXPECT_FALSE(LightSampleAlong(PointLight{{1, 1, 1}, Rgb(5)}, ref, Vec3(0, 1, 0), Vec3(1, 1, 1), Vec3()));
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

namespace farm {
namespace {

// KHR_lights_punctual's falloff, written out: the square of a ramp in cos between the
// outer and the inner cone.
double SpotFalloff(double cos_angle, double inner_degrees, double outer_degrees) {
  const double ci = std::cos(inner_degrees * kPiD / 180), co = std::cos(outer_degrees * kPiD / 180);
  const double t = std::clamp((cos_angle - co) / (ci - co), 0.0, 1.0);
  return t * t;
}

TEST(Lights, SpotFalloffMatchesTheFormulaInDirectLight) {
  const double inner = 20, outer = 35;
  const Light light = SpotLight{{0, 0, 2}, Rgb(5),
                                SpotCone{{0, 0, -1}, float(std::cos(inner * kPiD / 180)),
                                         float(std::cos(outer * kPiD / 180))}};
  SCOPED_TRACE(ToString(light));
  // Points on the plane z = 0 at growing distance from the axis.
  for (double x = 0; x < 2; x += 0.05) {
    const double d2 = x * x + 4, cos_angle = 2 / std::sqrt(d2);
    const double expected = 5 * SpotFalloff(cos_angle, inner, outer) / d2;
    const std::optional<LightSample> s = SampleLi(light, {float(x), 0, 0}, {0.5f, 0.5f});
    if (expected == 0) {
      EXPECT_FALSE(s) << "x " << x;
      continue;
    }
    ASSERT_TRUE(s) << "x " << x;
    EXPECT_TRUE(s->delta);
    EXPECT_NEAR(s->radiance.g, expected, 1e-5 * expected + 1e-7) << "x " << x;
  }
}

TEST(Lights, SpotPhotonsFollowTheFalloffAndCarryItsPower) {
  const double inner = 10, outer = 40;
  const SpotCone cone{{0, 0, 1}, float(std::cos(inner * kPiD / 180)), float(std::cos(outer * kPiD / 180))};
  const Light light = SpotLight{{1, 2, 3}, Rgb(2), cone};
  // The power is the intensity times the integral of the falloff over the sphere.
  double integral = 0;
  const int steps = 100000;
  for (int i = 0; i < steps; ++i) {
    const double c = -1 + 2 * (i + 0.5) / steps;
    integral += 2 * kPiD * SpotFalloff(c, inner, outer) * (2.0 / steps);
  }
  EXPECT_NEAR(Power(light).g, 2 * integral, 1e-4 * Power(light).g);
  // Photons' directions by cos: a histogram against the falloff's share of each bin.
  constexpr int kBins = 20;
  const double co = std::cos(outer * kPiD / 180);
  std::vector<int> hist(kBins, 0);
  const int n = 1 << 16;
  for (int i = 0; i < n; ++i) {
    const auto e = SampleLe(light, {0.5f, 0.5f}, {SobolSample(i, 0, 7), SobolSample(i, 1, 8)});
    ASSERT_TRUE(e);
    EXPECT_NEAR(e->power.g, Power(light).g, 1e-4 * Power(light).g);
    EXPECT_EQ(e->p, Vec3(1, 2, 3));
    const double c = Dot(e->w, cone.axis);
    ASSERT_GE(c, co - 1e-5);
    ++hist[std::min(kBins - 1, int((c - co) / (1 - co) * kBins))];
  }
  for (int b = 0; b < kBins; ++b) {
    double share = 0;
    for (int k = 0; k < 100; ++k) {
      const double c = co + (1 - co) * (b + (k + 0.5) / 100) / kBins;
      share += 2 * kPiD * SpotFalloff(c, inner, outer) * (1 - co) / kBins / 100;
    }
    share /= integral;
    EXPECT_NEAR(hist[b] / double(n), share, 2e-3) << "bin " << b;
  }
}

TEST(Lights, SpotWithEqualConesHasAHardEdge) {
  const float c = float(std::cos(30 * kPiD / 180));
  const SpotCone cone{{0, 0, 1}, c, c};
  EXPECT_EQ(cone.Falloff(Normalize(Vec3(0.5f, 0, 1))), 1.0f);  // 26.6 degrees
  EXPECT_EQ(cone.Falloff(Normalize(Vec3(0.6f, 0, 1))), 0.0f);  // 31 degrees
  EXPECT_NEAR(cone.SolidAngle(), 2 * kPiD * (1 - c), 1e-5);
}

TEST(Lights, SunDiscGivesItsIrradianceToAFacingSurface) {
  const BoundingSphere scene{{0, 0, 0}, 5};
  for (const double diameter : {0.53, 5.0, 20.0}) {
    const Light light = SunLight::Make({0, 0, -1}, Rgb(3), diameter, scene);
    SCOPED_TRACE(ToString(light));
    EXPECT_FALSE(IsDeltaLight(light));
    const double cos_max = std::cos(diameter / 2 * kPiD / 180);
    const int n = 1 << 12;
    for (int i = 0; i < n; ++i) {
      const auto s = SampleLi(light, {0, 0, 0}, {SobolSample(i, 0, 1), SobolSample(i, 1, 2)});
      ASSERT_TRUE(s);
      EXPECT_FALSE(s->delta);
      EXPECT_GE(s->wi.z, cos_max - 1e-6);  // within the disc
      EXPECT_GT(Length(s->p), scene.radius);
    }
    EXPECT_NEAR(EstimateIrradiance(light, {0, 0, 0}), 3, 3e-3);
    // Photons: every one carries the light's power.
    for (int i = 0; i < 64; ++i) {
      const auto e = SampleLe(light, {SobolSample(i, 0, 3), SobolSample(i, 1, 4)}, {SobolSample(i, 0, 5), SobolSample(i, 1, 6)});
      ASSERT_TRUE(e);
      EXPECT_LE(e->w.z, -cos_max + 1e-6);
      EXPECT_NEAR(e->power.g, Power(light).g, 1e-3 * Power(light).g);
    }
  }
  EXPECT_TRUE(IsDeltaLight(SunLight::Make({0, 0, -1}, Rgb(3), 0, scene)));
}

TEST(Lights, ConstantEnvironmentGivesPiLToAnyPlane) {
  const Light light = EnvironmentLight{std::make_shared<const Environment>(Environment::Constant(Rgb(0.5f))),
                                       DistantDisc::Around({{0, 0, 0}, 2})};
  SCOPED_TRACE(ToString(light));
  EXPECT_FALSE(IsDeltaLight(light));
  EXPECT_NEAR(EstimateIrradiance(light, {0.5f, 0, 0}), kPiD * 0.5, 5e-3);
  const DistantDisc& disc = std::get<EnvironmentLight>(light).disc;
  EXPECT_NEAR(Power(light).g, 4 * kPiD * 0.5 * disc.Area(), 1e-3 * Power(light).g);
  for (int i = 0; i < 256; ++i) {
    const auto e = SampleLe(light, {SobolSample(i, 0, 3), SobolSample(i, 1, 4)}, {SobolSample(i, 0, 5), SobolSample(i, 1, 6)});
    ASSERT_TRUE(e);
    EXPECT_NEAR(e->power.g, Power(light).g, 1e-3 * Power(light).g);
    // It starts outside the scene's sphere, and its line passes within the disc's radius.
    EXPECT_GT(Length(e->p), 2);
    EXPECT_LT(Dot(e->p, e->w), 0);
    EXPECT_LE(Length(e->p - e->w * Dot(e->p, e->w)), disc.radius * 1.0001f);
  }
}

}  // namespace
}  // namespace farm
