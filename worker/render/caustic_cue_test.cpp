// Edge anti-aliasing's light cue (SampleResult::light_irradiance) holds the light focused
// by specular surfaces as well as the direct light, so that a caustic's sharp rim is
// supersampled like a shadow's edge: a textured floor under a point light, with a disc of
// caustic photons laid on it by hand, evenly, whose irradiance is known.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "photonmap/memory_photon_map.h"
#include "render/integrator.h"
#include "sampling/pixel_sampler.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr int kPhotons = 20'000;
constexpr double kDiscRadius = 1;
constexpr double kCausticIrradiance = 8;  // over the disc: its photons' power / its area
constexpr double kLightHeight = 4, kIntensity = 16;  // the point light above the disc's centre

// Photons evenly over the disc (Vogel's sunflower spiral), arriving from straight above onto
// the floor y = 0.
MemoryPhotonMap CausticDisc() {
  const double power = kCausticIrradiance * std::numbers::pi * kDiscRadius * kDiscRadius / kPhotons;
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  std::vector<DecodedPhoton> photons;
  for (int i = 0; i < kPhotons; ++i) {
    const double r = kDiscRadius * std::sqrt((i + 0.5) / kPhotons), a = golden * i;
    photons.push_back({Vec3(float(r * std::cos(a)), 0, float(r * std::sin(a))), Rgb(float(power)), Vec3(0, 1, 0),
                       Vec3(0, 1, 0)});
  }
  return MemoryPhotonMap(std::move(photons));
}

TEST(CausticCue, TheLightCueHoldsTheCausticsIrradianceAndNotTheFloorsColour) {
  pb::Scene s = MakeScene(16, 16, {0, 6, 0}, {0, 0, 0}, {0, 0, 1}, 60, 1);
  s.mutable_indirect()->set_mode(pb::INDIRECT_MODE_PHOTON_MAP);
  AddLambert(s, "floor", Rgb(0.6f, 0.3f, 0.15f));  // a colour the cue must not carry
  AddQuad(s, "floor", {-10, 0, 10}, {20, 0, 0}, {0, 0, -20});
  AddPointLight(s, {0, kLightHeight, 0}, Rgb(float(kIntensity)));
  const Scene scene = Scene::Build(s, NoBlobs());
  const SceneData& data = scene.data();
  const MemoryPhotonMap caustic = CausticDisc();
  PhotonMaps maps;
  maps.caustic = &caustic;
  maps.caustic_estimate = ToRadianceEstimate(data.photons.caustic_estimate);
  maps.global_estimate = ToRadianceEstimate(data.photons.global_estimate);
  const PhotonMappingIntegrator integrator(data, maps);

  PixelSampler sampler(1, data.seed);
  std::vector<PhotonNeighbour> scratch;
  // The floor at the disc's centre, and at x = 3, twice the disc's radius beyond its rim.
  for (const double x : {0.0, 3.0}) {
    const Vec3 target(float(x), 0, 0), eye(0, 6, 0);
    sampler.StartPixelSample(0, 0);
    const SampleResult r = integrator.Li(Ray{eye, Normalize(target - eye)}, sampler, scratch);
    const double d2 = x * x + kLightHeight * kLightHeight;
    const double direct = kIntensity * (kLightHeight / std::sqrt(d2)) / d2;
    const double expected = direct + (x < kDiscRadius ? kCausticIrradiance : 0);
    std::printf("floor at x = %.0f: cue (%.4f, %.4f, %.4f), expected %.4f (direct %.4f)\n", x, r.light_irradiance.r,
                r.light_irradiance.g, r.light_irradiance.b, expected, direct);
    // Each channel the same (the floor's colour divided out), the caustic's within 3%
    // (its estimate over evenly spread photons), the direct light's exactly (a point light).
    for (const float c : {r.light_irradiance.r, r.light_irradiance.g, r.light_irradiance.b})
      EXPECT_NEAR(c, expected, 0.03 * kCausticIrradiance * (x < kDiscRadius) + 1e-4 * expected) << "x = " << x;
    // The caustic term itself: inside the disc and nowhere else.
    EXPECT_EQ(r.caustic.IsBlack(), x >= kDiscRadius) << "x = " << x;
  }
}

}  // namespace
}  // namespace farm
