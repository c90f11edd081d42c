// A sun with a disc casts a penumbra whose width follows from its angular diameter: the
// straight edge of an occluder at height h over a floor, the sun overhead with angular
// radius alpha, shades the floor from x = -h tan(alpha) (umbra) to x = +h tan(alpha) (full
// sun), where the visible part of the sun's disc is the part on one side of a chord.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "render/integrator.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr double kPiD = std::numbers::pi;

// The share of a disc of unit radius on one side of a chord at signed offset d.
double DiscShare(double d) {
  if (d <= -1) return 0;
  if (d >= 1) return 1;
  return 0.5 + (d * std::sqrt(1 - d * d) + std::asin(d)) / kPiD;
}

TEST(SunPenumbra, WidthFollowsTheAngularDiameter) {
  const double h = 1, diameter_degrees = 6, alpha = diameter_degrees / 2 * kPiD / 180;
  pb::Scene s = MakeScene(8, 8, {0, 0.5, 0}, {0, 0, 0}, {0, 0, -1}, 10, 1, 17);
  AddLambert(s, "white", Rgb(1));
  AddLambert(s, "black", Rgb(0));
  AddQuad(s, "white", {-5, 0, 5}, {10, 0, 0}, {0, 0, -10});    // the floor, facing up
  AddQuad(s, "black", {-20, h, 20}, {20, 0, 0}, {0, 0, -40});  // the occluder over x < 0
  pb::Light* sun = s.add_lights();
  Set(sun->mutable_sun()->mutable_direction(), {0, -1, 0});
  Set(sun->mutable_sun()->mutable_irradiance(), Rgb(float(kPiD)));  // so that L = the visible share
  sun->mutable_sun()->set_angular_diameter_degrees(diameter_degrees);
  s.mutable_sampling()->set_light_samples(1024);
  const Scene scene = Scene::Build(s, NoBlobs());
  const SceneData& data = scene.data();
  const PhotonMappingIntegrator integrator(data, PhotonMaps{});

  const double half_width = h * std::tan(alpha);
  std::vector<double> xs, measured;
  PixelSampler sampler(8, data.seed);
  std::vector<PhotonNeighbour> scratch;
  for (int i = -40; i <= 40; ++i) {
    const double x = half_width * 1.25 * i / 40;
    double sum = 0;
    for (uint32_t k = 0; k < 8; ++k) {
      sampler.StartPixelSample(uint64_t(i + 40), k);
      const Ray down{{float(x), 0.5f, 0}, {0, -1, 0}};  // between the occluder and the floor
      sum += integrator.Li(down, sampler, scratch).radiance.g / 8;
    }
    // The edge is seen at atan(x / h) from the zenith; the disc's angular radius is alpha.
    const double expected = DiscShare(std::atan(x / h) / alpha);
    EXPECT_NEAR(sum, expected, 0.02) << "x " << x;
    xs.push_back(x);
    measured.push_back(sum);
  }
  // The penumbra's 10%-90% width, measured and from the disc's chord (d from -0.687 to
  // +0.687 of the radius).
  const auto crossing = [&](double level) {
    for (std::size_t i = 1; i < xs.size(); ++i)
      if (measured[i - 1] < level && measured[i] >= level)
        return xs[i - 1] + (xs[i] - xs[i - 1]) * (level - measured[i - 1]) / (measured[i] - measured[i - 1]);
    return std::nan("");
  };
  double d90 = 0;  // DiscShare(d90) = 0.9, by bisection
  for (double lo = 0, hi = 1, k = 0; k < 60; ++k) (DiscShare(d90 = (lo + hi) / 2) < 0.9 ? lo : hi) = d90;
  const double expected_width = 2 * h * std::tan(d90 * alpha);
  const double width = crossing(0.9) - crossing(0.1);
  std::printf("penumbra 10%%-90%%: %.5f (expected %.5f, umbra to full sun %.5f)\n", width, expected_width,
              2 * half_width);
  EXPECT_NEAR(width, expected_width, 0.05 * expected_width);
  EXPECT_EQ(measured.front(), 0);  // umbra
  EXPECT_NEAR(measured.back(), 1, 0.005);
}

TEST(SunPenumbra, ADeltaSunCastsAHardShadow) {
  pb::Scene s = MakeScene(8, 8, {0, 0.5, 0}, {0, 0, 0}, {0, 0, -1}, 10, 1, 17);
  AddLambert(s, "white", Rgb(1));
  AddQuad(s, "white", {-5, 0, 5}, {10, 0, 0}, {0, 0, -10});
  AddQuad(s, "white", {-20, 1, 20}, {20, 0, 0}, {0, 0, -40});
  pb::Light* sun = s.add_lights();
  Set(sun->mutable_sun()->mutable_direction(), {0, -1, 0});
  Set(sun->mutable_sun()->mutable_irradiance(), Rgb(float(kPiD)));
  const Scene scene = Scene::Build(s, NoBlobs());
  const PhotonMappingIntegrator integrator(scene.data(), PhotonMaps{});
  PixelSampler sampler(1, 1);
  std::vector<PhotonNeighbour> scratch;
  sampler.StartPixelSample(0, 0);
  EXPECT_EQ(integrator.Li(Ray{{-0.001f, 0.5f, 0}, {0, -1, 0}}, sampler, scratch).radiance.g, 0);
  sampler.StartPixelSample(1, 0);
  EXPECT_NEAR(integrator.Li(Ray{{0.001f, 0.5f, 0}, {0, -1, 0}}, sampler, scratch).radiance.g, 1, 1e-5);
}

}  // namespace
}  // namespace farm
