// A camera sample's effort (PhotonMappingIntegrator::Li): the share of the scene's light
// samples and gather rays its shading points take. The extra samples of an edge pixel take
// a small one, and draw their rays as one stratified set over the pixel; their estimate
// must stay unbiased, and sixteen of them no noisier than a full sample. Measured on the Cornell
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
#include "sampling/hash.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

struct Spread {
  double mean = 0, variance = 0;
};

Spread Of(const std::vector<double>& x) {
  double sum = 0, sum2 = 0;
  for (double v : x) {
    sum += v;
    sum2 += v * v;
  }
  const double n = double(x.size()), mean = sum / n;
  return {mean, (sum2 / n - mean * mean) * n / (n - 1)};
}

// `groups` means of `size` samples each of the green radiance along ray at effort share,
// the samples of a group drawing their rays as one shared set (SampleEffort) if strata.
std::vector<double> GroupMeans(const SceneData& data, const PhotonMappingIntegrator& integrator, const Ray& ray,
                               uint32_t groups, uint32_t size, float share, bool strata) {
  PixelSampler sampler(groups * size, data.seed);
  std::vector<PhotonNeighbour> scratch;
  std::vector<double> means;
  for (uint32_t g = 0; g < groups; ++g) {
    double sum = 0;
    for (uint32_t j = 0; j < size; ++j) {
      sampler.StartPixelSample(0, g * size + j);
      sampler.Get2D();  // the film position's dimensions, which the fixed ray leaves unused
      SampleEffort effort{share};
      if (strata) effort = {share, uint32_t(Hash(uint64_t(g), 77u)), j, size};
      sum += integrator.Li(ray, sampler, scratch, effort).radiance.g;
    }
    means.push_back(sum / size);
  }
  return means;
}

// The mean and variance of `samples` samples of the green radiance along ray at effort share.
Spread SamplesAlong(const SceneData& data, const PhotonMappingIntegrator& integrator, const Ray& ray,
                    uint32_t samples, float share) {
  return Of(GroupMeans(data, integrator, ray, samples, 1, share, false));
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
  maps.global = maps.irradiance = global.get();
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

    // Sixteen such samples drawing their rays as one set over the pixel (an edge pixel's
    // extra samples) stratify as a full sample's rays do: their mean is about as noisy as
    // one full sample, and less than sixteen independent sets' mean.
    constexpr uint32_t kGroups = 100, kSize = 16;
    const Spread shared = Of(GroupMeans(data, integrator, ray, kGroups, kSize, effort, true));
    const Spread apart = Of(GroupMeans(data, integrator, ray, kGroups, kSize, effort, false));
    std::printf("  16 samples at 1/16: one shared set: mean %.5f, variance %.3g; sets apart: mean %.5f, "
                "variance %.3g\n",
                shared.mean, shared.variance, apart.mean, apart.variance);
    EXPECT_NEAR(shared.mean, full.mean, 4 * std::sqrt((full.variance / kSamples + shared.variance / kGroups)));
    EXPECT_LT(shared.variance, 0.75 * apart.variance) << "pixel " << pixel.x << ", " << pixel.y;
    EXPECT_LT(shared.variance, 2 * full.variance) << "pixel " << pixel.x << ", " << pixel.y;
  }
}

}  // namespace
}  // namespace farm
