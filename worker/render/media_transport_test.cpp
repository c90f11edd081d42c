// Single scattering and attenuation against closed forms and quadrature (issue 15,
// acceptance 1): InScatter on its own in an infinite homogeneous medium, the whole
// integrator seeing a surface through fog, and single scattering by light and
// phase-function samples weighed by MIS, in fog and in grid smoke.

#include "render/media_transport.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "media/henyey_greenstein.h"
#include "media/test_quadrature.h"
#include "render/test_images.h"
#include "render/tile_renderer.h"
#include "sampling/pixel_sampler.h"
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

// A floor at y = 0 reaching 50 each way, lit from above (a scene needs a light).
Scene FloorAtHeightZero() {
  namespace pb = renderfarm::v1;
  pb::Scene s = testing::MakeScene(1, 1, {0, 5, 0}, {0, 0, 0}, {0, 0, 1}, 40, 1, 1);
  testing::AddLambert(s, "floor", Rgb(0.5f));
  testing::AddQuad(s, "floor", {-50, 0, 50}, {100, 0, 0}, {0, 0, -100});
  testing::AddPointLight(s, {0, 3, 0}, Rgb(1));
  return Scene::Build(s, testing::NoBlobs());
}

// A wall at height h under x cuts the ball of radius r: the probes find the part above it,
// the seen volume's share is the sphere's cap above the plane (within the probes' error),
// and points beyond the wall are not seen while points above it are.
TEST(MediaTransport, SeenBallStopsAtAWall) {
  const Scene scene = FloorAtHeightZero();
  const float r = 1, h = 0.5f;
  const Vec3 x(0, h, 0);
  const SeenBall ball = SeenBall::Probe(scene.data(), x, r, {0.3f, 0.6f});
  // The ball less the cap below the plane: 1 - (r - h)^2 (2 r + h) / (4 r^3).
  const double cut = double(r - h) * (r - h) * (2 * r + h) / (4.0 * r * r * r);
  EXPECT_NEAR(ball.fraction, 1 - cut, 0.05);
  EXPECT_TRUE(ball.Sees(scene.data(), x, {0.3f, 0.2f, 0.1f}));
  EXPECT_TRUE(ball.Sees(scene.data(), x, {0, -0.4f, 0}));
  EXPECT_FALSE(ball.Sees(scene.data(), x, {0, -0.7f, 0}));
  EXPECT_FALSE(ball.Sees(scene.data(), x, {0.2f, -0.8f, -0.1f}));
}

// What the volume estimate counts over what it divides by, near a wall: photons of one
// density fill the ball in front of a floor and none lie behind it (the dim fog outside a
// lit room). Over the probes' turns and the heights of the point, the photons counted as
// seen over those the seen volume would hold average 1, and almost no photon beyond the
// wall counts (only where no probe met the wall, a cap too thin for the probes that the
// volume counts too). Judged by the probe nearest its direction, a photon near the wall's
// plane counted behind the wall where that probe passed the wall's edge and not in front
// where the probe met the wall short of it: 3% of the count lay behind, 3% too few.
TEST(MediaTransport, SeenBallCountsWhatItsVolumeHolds) {
  const Scene scene = FloorAtHeightZero();
  constexpr float r = 1;
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> unit(-1, 1), u01(0, 1);
  std::vector<Vec3> ball;  // uniform in the ball: the density the estimate should find
  while (ball.size() < 20000) {
    const Vec3 o(unit(rng), unit(rng), unit(rng));
    if (LengthSquared(o) <= 1) ball.push_back(o * r);
  }
  double counted = 0, expected = 0, beyond = 0;
  for (int turn = 0; turn < 400; ++turn) {
    const Vec3 x(0, r * (float(turn % 20) + 0.5f) / 20, 0);  // heights through the ball
    const SeenBall seen = SeenBall::Probe(scene.data(), x, r, {u01(rng), u01(rng)});
    for (const Vec3& o : ball) {
      if (!seen.Sees(scene.data(), x, o)) continue;
      if (x.y + o.y < 0) ++beyond; else ++counted;
    }
    expected += double(ball.size()) * seen.fraction;
  }
  EXPECT_LT(beyond / counted, 1e-4);  // 3% judged by the nearest probe
  EXPECT_NEAR(counted / expected, 1.0, 0.01);
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

// What a test adds to a scene: a light, a medium.
using SceneChange = std::function<void(renderfarm::v1::Scene&)>;

// The fog of FogOverAFloor: homogeneous, sigma_a 0.1 and sigma_s 0.4 (sigma_t 0.5).
void HomogeneousFog(renderfarm::v1::Scene& s) {
  renderfarm::v1::MediumCoefficients* c = s.mutable_medium()->mutable_sigma();
  testing::Set(c->mutable_sigma_a(), Rgb(0.1f));
  testing::Set(c->mutable_sigma_s(), Rgb(0.4f));
}

// Scenes for single scattering by MIS: a black floor (it reflects nothing; it makes the
// scene's ball, which the fog fills, wide enough to hold the rays) and `light`, in `fog`
// (its blobs from `blobs`) of asymmetry g.
Scene FogOverAFloor(float g, const SceneChange& light, const SceneChange& fog = HomogeneousFog,
                    const BlobLoader& blobs = testing::NoBlobs()) {
  namespace pb = renderfarm::v1;
  pb::Scene s = testing::MakeScene(1, 1, {0, 1, 4}, {0, 1, 0}, {0, 1, 0}, 40, 1, 1);
  testing::AddLambert(s, "black", Rgb(0));
  testing::AddEmissive(s, "lamp", Rgb(2));
  testing::AddQuad(s, "black", {-4, 0, 4}, {8, 0, 0}, {0, 0, -8});  // front +y
  light(s);
  fog(s);
  s.mutable_medium()->set_g(g);
  return Scene::Build(s, blobs);
}

// A 2 x 2 quad light at height 2 facing down.
void QuadLamp(renderfarm::v1::Scene& s) { testing::AddQuad(s, "lamp", {-1, 2, -1}, {2, 0, 0}, {0, 0, 2}); }

// The transmittance between two points of a medium.
using Transmittance = std::function<double(const Vec3& a, const Vec3& b)>;

// FogOverAFloor's homogeneous fog's: exp(-sigma_t d), sigma_t 0.5.
double HomogeneousTransmittance(const Vec3& a, const Vec3& b) { return std::exp(-0.5 * double(Distance(a, b))); }

// The light of QuadLamp (radiance 2) scattered once at x towards wo per unit sigma_s,
// through the fog: the integral over the quad of p(wo, wi) Le T cos / d^2, by quadrature
// in double (intervals along each side).
double QuadLampAt(const Vec3& x, const Vec3& wo, float g, int intervals,
                  const Transmittance& transmittance = HomogeneousTransmittance) {
  return testing::Simpson(
      [&](double px) {
        return testing::Simpson(
            [&](double pz) {
              const Vec3 y(float(px), 2, float(pz));
              const double dist = Distance(x, y);
              const Vec3 wi = (y - x) / float(dist);  // the quad's front faces down: cos = wi.y
              return HenyeyGreenstein(wo, wi, g) * 2 * transmittance(x, y) * wi.y / (dist * dist);
            },
            -1, 1, intervals);
      },
      -1, 1, intervals);
}

// The light strategy alone, the phase strategy alone, and both weighed by MIS: three
// unbiased estimates of the same single scattering along `ray` (its segment in the fog),
// each the mean of n samples (green channel) with its standard error.
struct Estimate {
  double mean = 0, error = 0;
};
struct ThreeWays {
  Estimate light, phase, mis;
};
ThreeWays SingleScatteringThreeWays(const SceneData& d, const Ray& ray, int n) {
  const std::optional<SurfaceHit> hit = d.Intersect(ray);
  const MediumSegment segment = SegmentIn(d, &*d.medium, ray, hit ? hit->t : kInf);
  const ShadowTransmittance shadow = [&](const Vec3& x, const LightSample& ls) {
    return d.Visible(x, Vec3(), ls.p, ls.n) ? ls.radiance * TransmittanceBetween(d, segment.medium, x, ls.p) : Rgb();
  };
  double sum[3] = {}, squares[3] = {};
  const auto add = [&](int k, double x) {
    sum[k] += x;
    squares[k] += x * x;
  };
  PixelSampler sampler(n, 21);
  for (int i = 0; i < n; ++i) {
    sampler.StartPixelSample(0, i);
    const auto pick = d.light_power.Sample(sampler.Get1D());
    const InScatterDimensions u{sampler.Get2D(), sampler.Get1D(), sampler.Get1D()};
    const Light& light = d.lights[pick.index];
    const float u_channel = sampler.Get1D(), u_distance = sampler.Get1D();
    const Vec2 u_direction = sampler.Get2D();
    const auto phase = [&](Weighting w) {
      const auto s = PhaseInScatter(d, segment, ray, u_channel, u_distance, u_direction, w);
      return s ? s->single.g : 0.0f;
    };
    add(0, InScatter(segment, ray, light, pick.pmf, u, shadow, Weighting::kAlone).g);
    add(1, phase(Weighting::kAlone));
    add(2, InScatter(segment, ray, light, pick.pmf, u, shadow).g + phase(Weighting::kMis));
  }
  Estimate e[3];
  for (int k = 0; k < 3; ++k) {
    e[k].mean = sum[k] / n;
    e[k].error = std::sqrt(std::max(0.0, squares[k] / n - e[k].mean * e[k].mean) / n);
  }
  return {e[0], e[1], e[2]};
}

// got within four standard errors of want, give or take `slack` of want (the quadrature's
// own error).
void ExpectWithin(const Estimate& got, double want, double slack, const char* what) {
  EXPECT_NEAR(got.mean, want, 4 * got.error + slack * want) << what << ": standard error " << got.error;
}

// Each strategy alone and both by MIS match want (ExpectWithin), the MIS estimate precise
// enough for the check to bite.
void ExpectEachAndBothMatch(const ThreeWays& got, double want, double slack) {
  ExpectWithin(got.light, want, slack, "light sampling alone");
  ExpectWithin(got.phase, want, slack, "phase sampling alone");
  ExpectWithin(got.mis, want, slack, "both, by MIS");
  EXPECT_LT(got.mis.error, 0.005 * want) << "so that the check above bites";
}

// Independent estimates of the same integral, where no quadrature gives it: each
// strategy's difference from MIS within four standard errors of that difference.
void ExpectTheThreeAgree(const ThreeWays& got) {
  EXPECT_LT(got.mis.error, 0.005 * got.mis.mean);
  for (const auto& [alone, what] : {std::pair{got.light, "light sampling alone"}, {got.phase, "phase sampling alone"}})
    EXPECT_NEAR(alone.mean, got.mis.mean, 4 * std::hypot(alone.error, got.mis.error)) << what;
}

// Single scattering from a quad light (distances equiangular towards its points) against
// the integral over the segment and the quad by quadrature in double; each strategy alone
// and both by MIS agree with it. With the MIS weights wrong (not summing to 1 for the
// same distance and direction: a strategy's density computed unlike the other's sampler)
// the MIS estimate would not.
TEST(SingleScatteringMis, QuadLightMatchesQuadratureByEachStrategyAndByBoth) {
  for (const float g : {0.0f, 0.7f, -0.9f}) {
    SCOPED_TRACE("g = " + std::to_string(g));
    const Scene scene = FogOverAFloor(g, QuadLamp);
    const SceneData& d = scene.data();
    const Ray ray{{-3, 0.5f, 0.3f}, Normalize(Vec3(1, 0.1f, -0.05f))};
    const MediumSegment segment = SegmentIn(d, &*d.medium, ray, kInf);
    ASSERT_FALSE(segment.empty());
    // Along the segment: its transmittance from t0 times sigma_s (0.4) times the light at t.
    const double want = testing::Simpson(
        [&](double t) {
          return std::exp(-0.5 * (t - segment.t0)) * 0.4 * QuadLampAt(ray.At(float(t)), -ray.direction, g, 60);
        },
        segment.t0, segment.t1, 400);
    ExpectEachAndBothMatch(SingleScatteringThreeWays(d, ray, 1 << 17), want, 0.002);
  }
}

// A sphere light (its cone sampled, distances by the medium's free flight) and a sun with
// a 20 degree disc in the forward lobe (found by rays that escape), each alone over the
// floor in `fog` (its blobs from `blobs`) of g 0.6: along a ray through it, the three
// estimates of n samples agree.
void ExpectSphereLightAndSunDiscAgree(const SceneChange& fog, const BlobLoader& blobs, int n) {
  const auto sphere = [](renderfarm::v1::Scene& s) { testing::AddSphere(s, "lamp", {0.5, 2, 0}, 0.5); };
  const auto sun = [](renderfarm::v1::Scene& s) {
    renderfarm::v1::SunLight* sun = s.add_lights()->mutable_sun();
    testing::Set(sun->mutable_direction(), Vec3d(-1, -0.5, 0));
    testing::Set(sun->mutable_irradiance(), Rgb(3));
    sun->set_angular_diameter_degrees(20);
  };
  for (const auto& [name, light] : {std::pair{"sphere", SceneChange(sphere)}, std::pair{"sun", SceneChange(sun)}}) {
    SCOPED_TRACE(name);
    const Scene scene = FogOverAFloor(0.6f, light, fog, blobs);
    ExpectTheThreeAgree(SingleScatteringThreeWays(scene.data(), Ray{{-3, 0.5f, 0.3f}, Vec3(1, 0, 0)}, n));
  }
}

TEST(SingleScatteringMis, SphereLightAndSunDiscAgreeByEachStrategyAndByBoth) {
  ExpectSphereLightAndSunDiscAgree(HomogeneousFog, testing::NoBlobs(), 1 << 18);
}

// Smoke over the floor instead of fog: a farm grid file of 16 x 8 x 16 cells over
// [-4, 4] x [-0.5, 3.5] x [-4, 4] (2 x 1 x 2 bricks), empty where x < -2 (the test rays
// start in empty cells and cross into smoke, and equiangular distances land where nothing
// scatters), elsewhere a density swirling between 0.2 and 1.4; density scale 0.6 (sigma_t
// up to 0.84), albedo 0.8.
const std::string kSmoke = testing::FakeDigest("smoke");

void GridSmoke(renderfarm::v1::Scene& s) { testing::SetGridMedium(s.mutable_medium(), kSmoke, Rgb(0.8f), 0.6f, 0); }

BlobLoader SmokeBlob() {
  const int nx = 16, ny = 8, nz = 16;
  std::vector<float> densities;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const float px = -4 + (float(x) + 0.5f) / 2, py = -0.5f + (float(y) + 0.5f) / 2, pz = -4 + (float(z) + 0.5f) / 2;
        densities.push_back(px < -2 ? 0 : 0.2f + 0.6f * (1 + std::sin(1.3f * px + 0.9f * pz + 0.7f * py)));
      }
  return testing::MapLoader(
      {{kSmoke, testing::FarmGridBytes(nx, ny, nz, Bounds3{{-4, -0.5f, -4}, {4, 3.5f, 4}}, densities)}});
}

// Single scattering from the quad light through grid smoke, where sigma_s and the
// transmittance vary along the ray and towards the light: the phase strategy draws its
// distances by inverting the grid's exact optical depth, the light strategy equiangularly,
// and each weighs a sample by the other's density for it (MediumSegment::DistancePdf,
// EquiangularPdf). Each alone and both by MIS match the integral over the segment and the
// quad by quadrature (the grid's transmittances by its exact optical depth, checked
// against quadrature in dense_grid_test.cpp). MIS weights computed from a density other
// than the grid's sampler's would not sum to 1, and the MIS estimate would miss: with the
// homogeneous formula at the segment's mean density it was 2.2% high at g = 0.
TEST(SingleScatteringMis, GridSmokeQuadLightMatchesQuadratureByEachStrategyAndByBoth) {
  for (const float g : {0.0f, 0.7f}) {
    SCOPED_TRACE("g = " + std::to_string(g));
    const Scene scene = FogOverAFloor(g, QuadLamp, GridSmoke, SmokeBlob());
    const SceneData& d = scene.data();
    const Ray ray{{-3, 0.5f, 0.3f}, Normalize(Vec3(1, 0.1f, -0.05f))};
    const MediumSegment segment = SegmentIn(d, &*d.medium, ray, kInf);
    ASSERT_FALSE(segment.empty());
    ASSERT_TRUE(segment.ScatteringAt(segment.t0).IsBlack()) << "the ray starts in empty cells";
    const Transmittance through_smoke = [&](const Vec3& a, const Vec3& b) {
      return double(TransmittanceBetween(d, &*d.medium, a, b).g);
    };
    const double want = testing::Simpson(
        [&](double t) {
          return double(segment.TransmittanceTo(float(t)).g) * segment.ScatteringAt(float(t)).g *
                 QuadLampAt(ray.At(float(t)), -ray.direction, g, 40, through_smoke);
        },
        segment.t0, segment.t1, 200);  // within 2e-5 of 400 intervals and 60 a side
    ExpectEachAndBothMatch(SingleScatteringThreeWays(d, ray, 1 << 17), want, 0.001);
  }
}

// The sphere light and the sun through the same smoke: the light strategy draws its
// distances as the phase strategy does (the grid's truncated flight), so the weights rest
// on that density at both ends; the three estimates agree.
TEST(SingleScatteringMis, GridSmokeSphereLightAndSunDiscAgreeByEachStrategyAndByBoth) {
  ExpectSphereLightAndSunDiscAgree(GridSmoke, SmokeBlob(), 1 << 16);
}

// A camera ray grazing an emitter (here 1e-4 under the quad light): light sampling alone
// draws distances towards a point on the light and its samples go as 1 / h, h the
// distance from the ray to that point (infinite variance: a pixel of the glowing cube's
// edge spikes). Under MIS no sample exceeds what a phase sample can bring, Le albedo (1 -
// T) over the segment (the phase function over its density is 1, T sigma_s over the
// truncated flight's density at most albedo (1 - T)), and a light sample's weighted value
// is at most half of the phase sample's for the same point: the energy bound holds for
// every sample, not just on average.
TEST(SingleScatteringMis, AGrazingRayStaysBelowTheLightsRadiance) {
  const Scene scene = FogOverAFloor(0, QuadLamp);
  const SceneData& d = scene.data();
  const Ray ray{{-3, 2 - 1e-4f, 0.3f}, Vec3(1, 0, 0)};
  const MediumSegment segment = SegmentIn(d, &*d.medium, ray, kInf);
  const ShadowTransmittance shadow = [&](const Vec3& x, const LightSample& ls) {
    return d.Visible(x, Vec3(), ls.p, ls.n) ? ls.radiance * TransmittanceBetween(d, segment.medium, x, ls.p) : Rgb();
  };
  const double bound = 2 * 0.8 * (1 - std::exp(-0.5 * (segment.t1 - segment.t0)));
  float worst_alone = 0, worst_light = 0, worst_phase = 0;
  const int n = 1 << 14;
  PixelSampler sampler(n, 32);
  for (int i = 0; i < n; ++i) {
    sampler.StartPixelSample(0, i);
    const InScatterDimensions u{sampler.Get2D(), sampler.Get1D(), sampler.Get1D()};
    worst_alone = std::max(worst_alone, InScatter(segment, ray, d.lights[0], 1, u, shadow, Weighting::kAlone).g);
    worst_light = std::max(worst_light, InScatter(segment, ray, d.lights[0], 1, u, shadow).g);
    const float u_channel = sampler.Get1D(), u_distance = sampler.Get1D();
    if (const auto s = PhaseInScatter(d, segment, ray, u_channel, u_distance, sampler.Get2D()))
      worst_phase = std::max(worst_phase, s->single.g);
  }
  EXPECT_GT(worst_alone, 10 * bound) << "light sampling alone spikes (what MIS is for)";
  EXPECT_LE(worst_light, 0.5 * bound * (1 + 1e-4));
  EXPECT_LE(worst_phase, bound * (1 + 1e-4));
  EXPECT_GT(worst_phase, 0.1 * bound);
}

// Single scattering at a fixed point of a volumetric path (ScatterAt: a light sample and a
// phase sample over directions, weighed by MIS) against the integral over the quad light.
TEST(SingleScatteringMis, AtAPointMatchesQuadrature) {
  for (const float g : {0.0f, 0.8f, -0.99f}) {
    SCOPED_TRACE("g = " + std::to_string(g));
    const Scene scene = FogOverAFloor(g, QuadLamp);
    const SceneData& d = scene.data();
    const Vec3 x(-1.5f, 1.2f, 0.4f), wo = Normalize(Vec3(-1, 0.3f, 0.2f));
    const double want = QuadLampAt(x, wo, g, 200);
    const ShadowTransmittance shadow = [&](const Vec3& p, const LightSample& ls) {
      return d.Visible(p, Vec3(), ls.p, ls.n) ? ls.radiance * TransmittanceBetween(d, &*d.medium, p, ls.p) : Rgb();
    };
    const int n = 1 << 17;
    PixelSampler sampler(n, 41);
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      sampler.StartPixelSample(0, i);
      const Vec2 u_light = sampler.Get2D();
      sum += ScatterAt(d, &*d.medium, x, wo, 0.5f, u_light, sampler.Get2D(), shadow).single.g;
    }
    EXPECT_NEAR(sum / n, want, 0.02 * want);
  }
}

TEST(SingleScatteringMis, PowerHeuristicWeightsSumToOneAndSurviveHugeDensities) {
  for (const auto& [a, b] : {std::pair{1.0f, 1.0f}, {0.3f, 7.0f}, {1e30f, 3e29f}, {1e-30f, 2e-31f}}) {
    EXPECT_NEAR(PowerHeuristic(a, b) + PowerHeuristic(b, a), 1, 1e-6) << a << " " << b;
  }
  EXPECT_EQ(PowerHeuristic(2, 0), 1);
  EXPECT_EQ(PowerHeuristic(0, 2), 0);
  EXPECT_EQ(PowerHeuristic(1, std::numeric_limits<float>::infinity()), 0);
  EXPECT_NEAR(PowerHeuristic(1, 3), 0.1f, 1e-7);
}

}  // namespace
}  // namespace farm
