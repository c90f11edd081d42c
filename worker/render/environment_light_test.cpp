// The environment against closed forms and numerical integration: a white Lambertian sphere
// under a constant white environment is a white furnace (radiance 1 everywhere) whether
// light comes from light samples alone, from light samples and gather rays weighted by
// multiple importance sampling, or from photons; and the irradiance on a plane under a
// non-uniform map is the map's cosine-weighted integral.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "photon/trace_photons.h"
#include "photonmap/memory_photon_map.h"
#include "render/integrator.h"
#include "render/test_integrator.h"
#include "scene/test_environment.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr double kPiD = std::numbers::pi;

// A white Lambertian sphere of radius 1 in a constant white environment, seen whole.
pb::Scene FurnaceScene() {
  pb::Scene s = MakeScene(32, 32, {0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40, 1, 11);
  AddLambert(s, "white", Rgb(1));
  AddSphere(s, "white", {0, 0, 0}, 1);
  AddConstantEnvironment(s, Rgb(1));
  s.mutable_sampling()->set_light_samples(64);
  return s;
}

TEST(EnvironmentLight, WhiteFurnaceByLightSamples) {
  const Scene scene = Scene::Build(FurnaceScene(), NoBlobs());
  const SceneData& data = scene.data();
  const PhotonMappingIntegrator integrator(data, MapsOf(data, nullptr));
  ASSERT_FALSE(integrator.final_gathering());
  const SampleResult r = MeanOverCentre(data, integrator, 8, 4);
  std::printf("furnace, light samples: L = %.5f\n", r.radiance.g);
  EXPECT_NEAR(r.radiance.r, 1, 0.01);
  EXPECT_NEAR(r.radiance.g, 1, 0.01);
  EXPECT_NEAR(r.radiance.b, 1, 0.01);
  EXPECT_EQ(r.radiance.g, r.direct.g);  // all of it is direct light
  // The background is the environment, and covers its pixels.
  PixelSampler sampler(1, 1);
  std::vector<PhotonNeighbour> scratch;
  sampler.StartPixelSample(0, 0);
  const SampleResult corner = integrator.Li(data.camera.GenerateRay({0.5f, 0.5f}), sampler, scratch);
  EXPECT_EQ(corner.radiance, Rgb(1));
  EXPECT_EQ(corner.alpha, 1);
  EXPECT_FALSE(corner.hit);
}

TEST(EnvironmentLight, WhiteFurnaceByLightSamplesAndGatherRays) {
  const Scene scene = Scene::Build(FurnaceScene(), NoBlobs());
  const SceneData& data = scene.data();
  const MemoryPhotonMap no_photons({});  // a convex sphere stores none
  const PhotonMappingIntegrator integrator(data, MapsOf(data, &no_photons));
  ASSERT_TRUE(integrator.final_gathering()) << integrator.ToString();
  const SampleResult r = MeanOverCentre(data, integrator, 8, 4);
  std::printf("furnace, light samples and gather rays (MIS): L = %.5f (direct %.5f)\n", r.radiance.g, r.direct.g);
  EXPECT_NEAR(r.radiance.r, 1, 0.01);
  EXPECT_NEAR(r.radiance.g, 1, 0.01);
  EXPECT_NEAR(r.radiance.b, 1, 0.01);
  EXPECT_EQ(r.indirect.g, 0);  // the escaping gather rays' light is direct
}

TEST(EnvironmentLight, WhiteFurnaceByPhotons) {
  // Photons from the environment (stored at their first hit, as Jensen's original global
  // map does) give the sphere the irradiance pi L everywhere, so its radiance rho E / pi = 1:
  // checked on each half of the sphere.
  const Scene scene = Scene::Build(FurnaceScene(), NoBlobs());
  const uint64_t paths = 400'000;
  const std::vector<ShardPhoton> photons =
      TracePhotons(scene, {PhotonMapKind::kGlobal, 0, paths, paths}, PhotonTraceOptions{true});
  double upper = 0, lower = 0, front = 0;
  for (const ShardPhoton& p : photons) {
    EXPECT_NEAR(Length(p.position), 1, 1e-4);
    (p.position.y > 0 ? upper : lower) += p.power.g;
    if (p.position.z > 0) front += p.power.g;
  }
  const double half_area = 2 * kPiD;  // of the unit sphere
  std::printf("furnace, photons: E = %.4f, %.4f, %.4f (pi = %.4f)\n", upper / half_area, lower / half_area,
              front / half_area, kPiD);
  EXPECT_NEAR(upper / half_area / kPiD, 1, 0.01);
  EXPECT_NEAR(lower / half_area / kPiD, 1, 0.01);
  EXPECT_NEAR(front / half_area / kPiD, 1, 0.01);
}

TEST(EnvironmentLight, HiddenFromTheCameraTheBackgroundIsBlackButStillLights) {
  pb::Scene s = FurnaceScene();
  s.mutable_environment()->set_hidden_from_camera(true);
  const Scene scene = Scene::Build(s, NoBlobs());
  const SceneData& data = scene.data();
  const PhotonMappingIntegrator integrator(data, MapsOf(data, nullptr));
  PixelSampler sampler(1, 1);
  std::vector<PhotonNeighbour> scratch;
  sampler.StartPixelSample(0, 0);
  const SampleResult corner = integrator.Li(data.camera.GenerateRay({0.5f, 0.5f}), sampler, scratch);
  EXPECT_EQ(corner.radiance, Rgb());
  EXPECT_EQ(corner.alpha, 0);
  EXPECT_NEAR(MeanOverCentre(data, integrator, 4, 4).radiance.g, 1, 0.01);
}

// A 32 x 16 map: a sky brighter towards the zenith and bluer, a small hot sun, a black
// band, all rotated about +Y.
std::vector<Rgb> SkyTexels() {
  std::vector<Rgb> texels;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) {
      const float sky = 0.3f + 0.1f * float(16 - y);
      Rgb c(sky * 0.6f, sky * 0.8f, sky);
      if (x >= 20 && x <= 21 && y == 4) c = Rgb(60, 50, 40);
      if (x >= 4 && x <= 7) c = Rgb();
      texels.push_back(c);
    }
  return texels;
}

TEST(EnvironmentLight, IrradianceOnAPlaneMatchesTheMapsIntegral) {
  const std::string digest = FakeDigest("sky");
  pb::Scene s = MakeScene(16, 16, {0, 3, 0.01}, {0, 0, 0}, {0, 0, -1}, 10, 1, 3);
  AddLambert(s, "grey", Rgb(0.5f));
  AddQuad(s, "grey", {-2, 0, 2}, {4, 0, 0}, {0, 0, -4});  // facing +y
  AddEnvironmentMap(s, digest, Rgb(1, 0.9f, 0.8f), 30);
  s.mutable_sampling()->set_light_samples(256);
  const Scene scene = Scene::Build(s, MapLoader({{digest, EncodeRadianceHdr(32, 16, SkyTexels())}}));
  const SceneData& data = scene.data();
  ASSERT_TRUE(data.environment);

  // E = integral over the upper hemisphere of L cos, by the midpoint rule in (cos, phi).
  double e[3] = {0, 0, 0};
  const int n = 1000;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 4 * n; ++j) {
      const double c = (i + 0.5) / n, phi = 2 * kPiD * (j + 0.5) / (4 * n), r = std::sqrt(1 - c * c);
      const Rgb l = data.environment->Radiance(Vec3(Vec3d(r * std::cos(phi), c, r * std::sin(phi))));
      const double weight = c * (1.0 / n) * (2 * kPiD / (4 * n));
      e[0] += l.r * weight;
      e[1] += l.g * weight;
      e[2] += l.b * weight;
    }
  const double expected[3] = {0.5 * e[0] / kPiD, 0.5 * e[1] / kPiD, 0.5 * e[2] / kPiD};

  const MemoryPhotonMap no_photons({});
  for (const bool gather : {false, true}) {
    const PhotonMappingIntegrator integrator(data, MapsOf(data, gather ? &no_photons : nullptr));
    ASSERT_EQ(integrator.final_gathering(), gather);
    const SampleResult r = MeanOverCentre(data, integrator, 4, 16);
    std::printf("map irradiance (%s): L = %.5f %.5f %.5f, integral %.5f %.5f %.5f\n",
                gather ? "light samples and gather rays" : "light samples", r.radiance.r, r.radiance.g,
                r.radiance.b, expected[0], expected[1], expected[2]);
    EXPECT_NEAR(r.radiance.r, expected[0], 0.02 * expected[0]);
    EXPECT_NEAR(r.radiance.g, expected[1], 0.02 * expected[1]);
    EXPECT_NEAR(r.radiance.b, expected[2], 0.02 * expected[2]);
  }
}

TEST(EnvironmentLight, ABlackEnvironmentIsNoLight) {
  pb::Scene s = FurnaceScene();
  Set(s.mutable_environment()->mutable_radiance(), Rgb());
  AddPointLight(s, {0, 3, 0}, Rgb(1));
  const Scene scene = Scene::Build(s, NoBlobs());
  EXPECT_EQ(scene.data().environment_light, -1);
  EXPECT_EQ(scene.data().lights.size(), 1u);
  ASSERT_TRUE(scene.data().environment);
  EXPECT_TRUE(scene.data().environment_visible);
}

}  // namespace
}  // namespace farm
