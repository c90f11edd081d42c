// A camera sample's effort (PhotonMappingIntegrator::Li): the share of the scene's light
// samples and gather rays its shading points take. The extra samples of an edge pixel take
// a small one; their estimate must stay unbiased, only noisier. Measured on the Cornell
// box of scenes/ with one camera ray repeated, so that the spread between samples is the
// shading's alone.

#include <gtest/gtest.h>

#include <google/protobuf/util/json_util.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "photon/irradiance_precompute.h"
#include "photon/test_photons.h"
#include "render/integrator.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

struct Spread {
  double mean = 0, variance = 0;
};

// The mean and variance of `samples` samples of the green radiance along ray at effort.
Spread SamplesAlong(const SceneData& data, const PhotonMappingIntegrator& integrator, const Ray& ray,
                    uint32_t samples, float effort) {
  PixelSampler sampler(samples, data.seed);
  std::vector<PhotonNeighbour> scratch;
  double sum = 0, sum2 = 0;
  for (uint32_t s = 0; s < samples; ++s) {
    sampler.StartPixelSample(0, s);
    sampler.Get2D();  // the film position's dimensions, which the fixed ray leaves unused
    const double g = integrator.Li(ray, sampler, scratch, effort).radiance.g;
    sum += g;
    sum2 += g * g;
  }
  const double mean = sum / samples;
  return {mean, (sum2 / samples - mean * mean) * samples / (samples - 1)};
}

TEST(ShadingEffort, ALowerEffortIsUnbiasedAndNoisierByItsShare) {
  std::ifstream in(std::string(SCENES_DIR) + "/cornell-box.json");
  std::stringstream text;
  text << in.rdbuf();
  pb::Scene s;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(text.str(), &s).ok());
  s.mutable_film()->set_width(16);
  s.mutable_film()->set_height(16);
  const Scene scene = Scene::Build(s, NoBlobs());
  const SceneData& data = scene.data();
  auto global = TraceIntoMemory(scene, PhotonMapKind::kGlobal, 50'000);
  global->set_irradiance(ComputeIrradiance(data, *global, nullptr, 0, global->size(), 1.0));
  PhotonMaps maps;
  maps.global = global.get();
  maps.global_estimate = ToRadianceEstimate(data.photons.global_estimate);
  const PhotonMappingIntegrator integrator(data, maps);
  ASSERT_TRUE(integrator.final_gathering());

  // The back wall, the floor by the left wall, the ceiling's corner: light direct and
  // indirect in different measures.
  constexpr uint32_t kSamples = 400;
  const float effort = 1.0f / 16;
  for (const Vec2 pixel : {Vec2{8.5f, 6.5f}, Vec2{2.5f, 14.5f}, Vec2{14.5f, 1.5f}}) {
    const Ray ray = data.camera.GenerateRay(pixel);
    const Spread full = SamplesAlong(data, integrator, ray, kSamples, 1);
    const Spread low = SamplesAlong(data, integrator, ray, kSamples, effort);
    const double error = std::sqrt((full.variance + low.variance) / kSamples);
    std::printf("pixel (%.1f, %.1f): effort 1 mean %.5f, variance %.3g; effort 1/16 mean %.5f, variance %.3g (%.1fx)\n",
                pixel.x, pixel.y, full.mean, full.variance, low.mean, low.variance, low.variance / full.variance);
    EXPECT_GT(full.mean, 0);
    // The same light on average (four standard errors of the difference) ...
    EXPECT_NEAR(low.mean, full.mean, 4 * error) << "pixel " << pixel.x << ", " << pixel.y;
    // ... from a sixteenth of the shadow and gather rays: about 16 times the variance,
    // more than 4 whatever the draw.
    EXPECT_GT(low.variance, 4 * full.variance) << "pixel " << pixel.x << ", " << pixel.y;
  }
}

}  // namespace
}  // namespace farm
