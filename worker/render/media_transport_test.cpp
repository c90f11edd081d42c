// Single scattering and attenuation in homogeneous media against closed forms (issue 15,
// acceptance 1): InScatter on its own in an infinite medium, and the whole integrator
// seeing a surface through fog.

#include "render/media_transport.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "media/henyey_greenstein.h"
#include "media/test_quadrature.h"
#include "render/test_images.h"
#include "render/tile_renderer.h"
#include "sampling/sobol.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// E1(x) = integral from x to infinity of e^-s / s ds = -Ei(-x).
double E1(double x) { return -std::expint(-x); }

// The mean of n single-scattering samples along `ray` through an infinite medium (no
// geometry: the light always reaches the scattering point, through the medium).
Rgb MeanInScatter(const HomogeneousMedium& m, const Ray& ray, const Light& light, int n) {
  const Medium medium{m};
  const MediumSegment segment{&medium, ray, 0, kInf};
  const ShadowTransmittance shadow = [&](const Vec3& x, const LightSample& ls) {
    return ls.radiance * m.Transmittance(Distance(x, ls.p));
  };
  Rgb sum;
  for (int i = 0; i < n; ++i) {
    const InScatterDimensions u{{SobolSample(i, 1, 7), SobolSample(i, 2, 8)}, SobolSample(i, 3, 9),
                                SobolSample(i, 0, 10)};
    sum += InScatter(segment, ray, light, 1, u, shadow);
  }
  return sum / float(n);
}

// A point light of intensity I at distance a behind the ray's origin, on its line, the ray
// leaving it: x(t) = o + t w lies s = a + t from the light, which lights it along w; the
// light scattered back along -w towards o turns by theta = pi, p = HG(-1, g) = (1 - g^2) /
// (4 pi (1 + g)^3). With both transmittances exp(-sigma_t t) and exp(-sigma_t s):
//
//   L = integral over t >= 0 of sigma_s p I e^(-sigma_t t) e^(-sigma_t (a + t)) / (a + t)^2 dt
//     = sigma_s p I e^(sigma_t a) integral over s >= a of e^(-2 sigma_t s) / s^2 ds
//     = sigma_s p I e^(sigma_t a) (e^(-k a) / a - k E1(k a)),   k = 2 sigma_t,
//
// integrating by parts (d(-1/s) e^(-k s)). Per channel, with its own sigmas.
TEST(SingleScattering, PointLightInAnInfiniteMediumMatchesTheClosedForm) {
  const HomogeneousMedium m = HomogeneousMedium::FromCoefficients({0.05f, 0.2f, 0.5f}, {0.3f, 0.1f, 0.5f}, 0.4f);
  const float a = 1.5f;
  const Rgb intensity(10, 20, 5);
  const Light light = PointLight{{0, 0, -a}, intensity};
  const Ray ray{{0, 0, 0}, {0, 0, 1}};
  const Rgb got = MeanInScatter(m, ray, light, 1 << 16);
  const double p = HenyeyGreenstein(-1.0f, m.g);
  const auto closed = [&](double sigma_s, double sigma_t, double i) {
    const double k = 2 * sigma_t;
    return sigma_s * p * i * std::exp(sigma_t * a) * (std::exp(-k * a) / a - k * E1(k * a));
  };
  EXPECT_NEAR(got.r, closed(0.3, 0.35, 10), 0.02 * closed(0.3, 0.35, 10)) << got;
  EXPECT_NEAR(got.g, closed(0.1, 0.3, 20), 0.02 * closed(0.1, 0.3, 20)) << got;
  EXPECT_NEAR(got.b, closed(0.5, 1.0, 5), 0.02 * closed(0.5, 1.0, 5)) << got;
}

// Off the line (the general equiangular case) and from a sun (the free-flight case),
// against the same integral by quadrature in double.
TEST(SingleScattering, OffTheLineAndFromTheSunMatchQuadrature) {
  const HomogeneousMedium m = HomogeneousMedium::FromCoefficients({0.1f, 0.1f, 0.1f}, {0.4f, 0.4f, 0.4f}, -0.3f);
  const double sigma_t = 0.5, sigma_s = 0.4;
  const Ray ray{{0, 0, 0}, Normalize(Vec3(1, 0, 1))};
  const Vec3 at(1, 2, 0.5f);
  const Light point = PointLight{at, Rgb(8)};
  const double want_point = testing::Simpson(
      [&](double t) {
        const Vec3 x = ray.At(float(t));
        const double d = Distance(x, at);
        const Vec3 wi = (at - x) / float(d);
        return std::exp(-sigma_t * (t + d)) * sigma_s * HenyeyGreenstein(-ray.direction, wi, m.g) * 8 / (d * d);
      },
      0, 80);
  EXPECT_NEAR(MeanInScatter(m, ray, point, 1 << 16).g, want_point, 0.02 * want_point);

  // A delta sun: irradiance E along -z everywhere, each point's light attenuated over a
  // fixed 3 units (the shadow functor's Distance to the sample's far point is what the
  // integrator clips to the medium's ball; here the infinite medium makes it the same
  // for every point), so L = E e^(-sigma_t 3) sigma_s p / sigma_t.
  const Light sun = SunLight::Make({0, 0, -1}, Rgb(2), 0, BoundingSphere{{0, 0, 0}, 1});
  const Medium medium{m};
  const MediumSegment segment{&medium, ray, 0, kInf};
  const ShadowTransmittance fixed = [&](const Vec3&, const LightSample& ls) { return ls.radiance * m.Transmittance(3); };
  Rgb sum;
  const int n = 1 << 14;
  for (int i = 0; i < n; ++i)
    sum += InScatter(segment, ray, sun, 1, {{0.5f, 0.5f}, SobolSample(i, 1, 3), SobolSample(i, 0, 4)}, fixed);
  const double p = HenyeyGreenstein(-ray.direction, Vec3(0, 0, 1), m.g);
  const double want_sun = 2 * std::exp(-sigma_t * 3) * sigma_s * p / sigma_t;
  EXPECT_NEAR(sum.g / n, want_sun, 0.02 * want_sun);
}

// An emissive wall of radiance 2 seen through a purely absorbing fog from distance d (the
// wall is wide enough that its medium ball holds the camera): the pixel is 2 exp(-sigma_a d)
// per channel, with nothing scattered in.
TEST(MediaTransport, SurfaceSeenThroughFogIsAttenuatedByBeerLambert) {
  namespace pb = renderfarm::v1;
  const double d = 10;
  pb::Scene s = testing::MakeScene(1, 1, {0, 0, d}, {0, 0, 0}, {0, 1, 0}, 0.02, 4, 3);
  testing::AddEmissive(s, "wall", Rgb(2));
  testing::AddQuad(s, "wall", {-100, -100, 0}, {200, 0, 0}, {0, 200, 0});
  pb::MediumCoefficients* c = s.mutable_medium()->mutable_sigma();
  testing::Set(c->mutable_sigma_a(), Rgb(0.01f, 0.1f, 0.3f));
  testing::Set(c->mutable_sigma_s(), Rgb(0, 0, 0));
  const Scene scene = Scene::Build(s, testing::NoBlobs());
  const Image image = RenderTile(scene, nullptr, {0, 0, 1, 1});
  const float* px = image.pixel(0, 0);
  EXPECT_NEAR(px[0], 2 * std::exp(-0.01 * d), 1e-5);
  EXPECT_NEAR(px[1], 2 * std::exp(-0.1 * d), 1e-5);
  EXPECT_NEAR(px[2], 2 * std::exp(-0.3 * d), 1e-6);
}

// A wall at height h under x cuts the ball of radius r: the probes find the part above it,
// the seen volume's share is the sphere's cap above the plane (within the probes' error),
// and points beyond the wall are not seen while points above it are.
TEST(MediaTransport, SeenBallStopsAtAWall) {
  namespace pb = renderfarm::v1;
  pb::Scene s = testing::MakeScene(1, 1, {0, 5, 0}, {0, 0, 0}, {0, 0, 1}, 40, 1, 1);
  testing::AddLambert(s, "floor", Rgb(0.5f));
  testing::AddQuad(s, "floor", {-50, 0, 50}, {100, 0, 0}, {0, 0, -100});
  testing::AddPointLight(s, {0, 3, 0}, Rgb(1));  // a scene needs a light
  const Scene scene = Scene::Build(s, testing::NoBlobs());
  const float r = 1, h = 0.5f;
  const Vec3 x(0, h, 0);
  const SeenBall ball = SeenBall::Probe(scene.data(), x, r, {0.3f, 0.6f});
  // The ball less the cap below the plane: 1 - (r - h)^2 (2 r + h) / (4 r^3).
  const double cut = double(r - h) * (r - h) * (2 * r + h) / (4.0 * r * r * r);
  EXPECT_NEAR(ball.fraction, 1 - cut, 0.05);
  EXPECT_TRUE(ball.Sees({0.3f, 0.2f, 0.1f}));
  EXPECT_TRUE(ball.Sees({0, -0.4f, 0}));
  EXPECT_FALSE(ball.Sees({0, -0.7f, 0}));
  EXPECT_FALSE(ball.Sees({0.2f, -0.8f, -0.1f}));
}

// A room in fog with a point light and a murky glass ball (no photon maps: direct light
// and media only): tiles stitch into the whole
// image's bytes (every random number from the sample's own dimensions), every value is
// finite, and the fog glows where the camera looks past the room's open side into the
// dark (nothing but single scattering lights those pixels).
TEST(MediaTransport, FoggyTilesEqualTheWholeImageBitForBit) {
  namespace pb = renderfarm::v1;
  pb::Scene s = testing::MakeScene(16, 12, {0, 1, 6}, {0, 1, 0}, {0, 1, 0}, 60, 2, 11);
  testing::AddLambert(s, "white", Rgb(0.7f));
  s.add_materials()->set_name("glass");
  s.mutable_materials(1)->mutable_dielectric()->set_ior(1.5);
  testing::AddQuad(s, "white", {-3, 0, 3}, {6, 0, 0}, {0, 0, -6});  // floor, front +y
  testing::AddQuad(s, "white", {-3, 0, -3}, {6, 0, 0}, {0, 3, 0});  // back wall, front +z
  pb::Shape* ball = testing::AddSphere(s, "glass", {0.8, 0.6, 0}, 0.6);
  pb::MediumAlbedo* murk = ball->mutable_interior_medium()->mutable_albedo();
  testing::Set(murk->mutable_albedo(), Rgb(0.9f, 0.6f, 0.3f));
  murk->set_density(1.5);
  testing::AddPointLight(s, {-1, 2.5, 1}, Rgb(6));
  pb::MediumAlbedo* fog = s.mutable_medium()->mutable_albedo();
  testing::Set(fog->mutable_albedo(), Rgb(0.8f));
  fog->set_density(0.05);
  s.mutable_medium()->set_g(0.5);
  const Scene scene = Scene::Build(s, testing::NoBlobs());
  const Image whole = RenderTile(scene, nullptr, {0, 0, 16, 12});
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < whole.channel_count(); ++c) ASSERT_TRUE(std::isfinite(whole.pixel(x, y)[c]));
  // The top row looks over the back wall (3 high, 3 behind the look-at point) into the dark.
  EXPECT_GT(whole.pixel(8, 0)[1], 0.0f) << "single scattering lights the fog above the wall";
  for (const PixelRect& tile : {PixelRect{0, 0, 7, 5}, PixelRect{7, 0, 9, 5}, PixelRect{0, 5, 16, 7}}) {
    const Image part = RenderTile(scene, nullptr, tile);
    testing::ExpectSamePixels(whole, part);
  }
}

}  // namespace
}  // namespace farm
