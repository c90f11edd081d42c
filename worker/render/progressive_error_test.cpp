// The error estimate of progressive rounds (image/error_estimate.h) on real renders of a
// scene whose converged image is known in closed form: a caustic whose kernel bias is as
// large as its noise, rendered round after round over several seeds as the farm renders
// it (fresh photons and camera samples each round, the radius shrinking by
// progressive.alpha, the bias layer from the integrator's companions, the rounds folded by
// the round accumulator).
//
// The truth. A white floor (z = 0) under a square mirror ceiling at height 2, a point light
// of intensity I at height 1 between them. The floor's radiance is rho / pi times the
// irradiance of the light itself (I / (1 + r^2)^1.5, r the distance from below it) and of
// its image in the mirror, a light of intensity 0.8 I at height 3 (0.8 I 3 / (9 + r^2)^1.5)
// wherever the mirror reflects it (all of the floor the camera sees). The renderer is given
// the caustic map only (light -> mirror -> floor), not the global map, so that what it
// converges to is exactly those two terms: direct light by its shadow ray (exact for a
// point light), the image light by the caustic map's kernel estimate (biased: the
// estimate blurs 1 / (9 + r^2)^1.5 over its disc). Each pixel's truth is that radiance
// averaged over the pixel's footprint on the floor, by a 16 x 16 grid of rays: a closed
// form, independent of any photon or estimator of the renderer.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "image/round_accumulator.h"
#include "image/tile_exr.h"
#include "photon/test_photons.h"
#include "render/integrator.h"
#include "render/test_integrator.h"
#include "sampling/hash.h"
#include "sampling/pixel_sampler.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr int kSide = 24;
constexpr double kIntensity = 5, kFloor = 0.5, kMirror = 0.8;
constexpr int kRounds = 8, kSeeds = 6;
constexpr uint64_t kCausticPaths = 20'000;
constexpr double kAlpha = 0.7;  // progressive.alpha's default

pb::Scene CausticUnderAMirror(uint64_t seed) {
  pb::Scene s = MakeScene(kSide, kSide, {0, -2.5, 1.6}, {0, 0.5, 0}, {0, 0, 1}, 40, 4, seed);
  AddLambert(s, "white", Rgb(float(kFloor)));
  AddQuad(s, "white", {-20, -20, 0}, {40, 0, 0}, {0, 40, 0});
  pb::Material* m = s.add_materials();
  m->set_name("mirror");
  Set(m->mutable_mirror()->mutable_reflectance(), Rgb(float(kMirror)));
  AddQuad(s, "mirror", {-6, -6, 2}, {12, 0, 0}, {0, 12, 0});
  AddPointLight(s, {0, 0, 1}, Rgb(float(kIntensity)));
  // Many neighbours over a wide bound: a kernel of about a unit's radius on a caustic that
  // varies over three, so that its bias is of the order of its noise.
  s.mutable_photons()->mutable_caustic_estimate()->set_neighbours(400);
  s.mutable_photons()->mutable_caustic_estimate()->set_max_radius(4);
  return s;
}

// The floor's radiance at (x, y): rho / pi times the light's and its mirror image's
// irradiance.
double FloorRadiance(double x, double y) {
  const double r2 = x * x + y * y;
  return kFloor / std::numbers::pi *
         (kIntensity / std::pow(1 + r2, 1.5) + kMirror * kIntensity * 3 / std::pow(9 + r2, 1.5));
}

// Each pixel's closed-form value, row-major: the mean over a 16 x 16 grid of camera rays.
std::vector<double> Truth(const SceneData& data) {
  std::vector<double> truth;
  for (int y = 0; y < data.height; ++y)
    for (int x = 0; x < data.width; ++x) {
      double sum = 0;
      for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) {
          const Ray ray = data.camera.GenerateRay({x + (i + 0.5f) / 16, y + (j + 0.5f) / 16});
          const float t = -ray.origin.z / ray.direction.z;  // onto the floor
          sum += FloorRadiance(ray.origin.x + t * ray.direction.x, ray.origin.y + t * ray.direction.y);
        }
      truth.push_back(sum / 256);
    }
  return truth;
}

// Round r's radius scale (RoundSettings, as the coordinator makes it).
double RadiusScale(int round) {
  double area = 1;
  for (int i = 1; i < round; ++i) area *= (i + kAlpha) / (i + 1);
  return std::sqrt(area);
}

// Round r of a render: fresh caustic photons (a path range of the round's own) and camera
// samples (a sample set keyed by the round), the kernel at the round's radius; the beauty
// and the bias layer as a whole-image tile.
Image RenderRound(const Scene& scene, int round) {
  const SceneData& data = scene.data();
  const auto caustic = TraceIntoMemory(scene, PhotonMapKind::kCaustic, kCausticPaths, kCausticPaths * (round - 1));
  PhotonMaps maps = MapsOf(data, nullptr);
  maps.caustic = caustic.get();
  const PhotonMappingIntegrator integrator(data, maps, RadiusScale(round), /*bias_layer=*/true);
  std::vector<std::string> channels = {"R", "G", "B", "A"};
  for (const std::string& c : BiasChannels()) channels.push_back(c);
  Image image({0, 0, data.width, data.height}, channels);
  PixelSampler sampler(data.samples_per_pixel, Hash(data.seed, uint64_t(round)));
  std::vector<PhotonNeighbour> scratch;
  for (int y = 0; y < data.height; ++y)
    for (int x = 0; x < data.width; ++x) {
      Rgb radiance, bias;
      for (uint32_t s = 0; s < data.samples_per_pixel; ++s) {
        sampler.StartPixelSample(uint64_t(y) * uint64_t(data.width) + uint64_t(x), s);
        const Vec2 u = sampler.Get2D();
        const SampleResult r = integrator.Li(data.camera.GenerateRay({x + u.x, y + u.y}), sampler, scratch);
        radiance += r.radiance;
        bias += r.bias;
      }
      radiance = radiance / float(data.samples_per_pixel);
      bias = bias / float(data.samples_per_pixel);
      float* p = image.pixel(x, y);
      const float values[] = {radiance.r, radiance.g, radiance.b, 1, bias.r, bias.g, bias.b};
      std::copy(std::begin(values), std::end(values), p);
    }
  return image;
}

// One seed's rounds: each round's estimate and the mean image's actual RMSE against the
// truth, and the mean image after the last round.
struct SeedRun {
  std::vector<ErrorEstimate> estimates;  // rounds 2..kRounds
  std::vector<double> actual;            // rounds 2..kRounds
  std::vector<double> mean;              // after kRounds, row-major, R only (grey scene)
};

SeedRun RenderSeed(uint64_t seed, const std::vector<double>& truth) {
  const Scene scene = Scene::Build(CausticUnderAMirror(seed), NoBlobs());
  const ImageSize size{kSide, kSide};
  SeedRun run;
  std::vector<double> sum(truth.size());
  std::optional<std::string> accumulation;
  for (int r = 1; r <= kRounds; ++r) {
    const Image round = RenderRound(scene, r);
    const std::vector<EncodedTile> tiles = {{round.rect(), EncodeTileExr(round, size)}};
    RoundInputs in{size, kSide, r, tiles, accumulation, std::nullopt};
    const RoundOutputs out = AccumulateRound(in);
    accumulation = out.accumulation_exr;
    double squared = 0;
    for (std::size_t p = 0; p < truth.size(); ++p) {
      sum[p] += round.data()[p * round.channels().size()];
      squared += std::pow(sum[p] / r - truth[p], 2);
    }
    if (r == 1) continue;
    run.estimates.push_back(*out.error_estimate);
    run.actual.push_back(std::sqrt(squared / double(truth.size())));
  }
  for (double s : sum) run.mean.push_back(s / kRounds);
  return run;
}

TEST(ProgressiveError, TheEstimateTracksTheErrorAgainstAClosedFormAndFallsRoundByRound) {
  const Scene scene = Scene::Build(CausticUnderAMirror(1), NoBlobs());
  const std::vector<double> truth = Truth(scene.data());
  std::vector<SeedRun> runs;
  for (uint64_t seed = 1; seed <= kSeeds; ++seed) runs.push_back(RenderSeed(seed, truth));

  // In expectation over the seeds, round by round: the mean squared estimate within 25% of
  // the mean squared actual error (the kernel here is wide for the caustic's curvature, so
  // that its bias matters: in the first rounds, whose kernels are widest, the companion's
  // difference finds about three quarters of the bias, by round 6 all of it), and the
  // estimate falls. Each seed's own actual error varies by about 40% (every pixel of a
  // round shares its photons): the interval holds it in at least 70% of the rounds
  // (measured: 74%; below 50% with the interval's 2x2-block degrees of freedom alone).
  double previous = INFINITY, held_all = 0;
  for (std::size_t i = 0; i < runs[0].estimates.size(); ++i) {
    double estimate = 0, actual = 0, held = 0;
    for (const SeedRun& run : runs) {
      estimate += run.estimates[i].rmse * run.estimates[i].rmse / kSeeds;
      actual += run.actual[i] * run.actual[i] / kSeeds;
      held += run.estimates[i].low <= run.actual[i] && run.actual[i] <= run.estimates[i].high;
    }
    estimate = std::sqrt(estimate);
    actual = std::sqrt(actual);
    const int round = int(i) + 2;
    EXPECT_NEAR(estimate / actual, 1.0, 0.25) << "round " << round << ": estimate " << estimate << ", actual " << actual;
    EXPECT_LT(estimate, previous) << "round " << round;
    EXPECT_GE(held, kSeeds / 2) << "round " << round << ": the interval held the actual error in " << held;
    held_all += held;
    previous = estimate;
  }

  EXPECT_GE(held_all, 0.7 * kSeeds * (kRounds - 1)) << "the interval held the actual error in " << held_all;

  // The bias after the last round, from the seeds' mean image (its noise, the seeds'
  // spread over kSeeds, taken off), against the estimates' bias part: the bias layer
  // finds it. And it matters: the spread between rounds alone falls short of the error.
  double bias2 = 0, spread = 0;
  for (std::size_t p = 0; p < truth.size(); ++p) {
    double m = 0, m2 = 0;
    for (const SeedRun& run : runs) {
      m += run.mean[p] / kSeeds;
      m2 += run.mean[p] * run.mean[p] / kSeeds;
    }
    const double variance = (m2 - m * m) * kSeeds / (kSeeds - 1);
    bias2 += (m - truth[p]) * (m - truth[p]) - variance / kSeeds;
    spread += variance;
  }
  const double bias = std::sqrt(bias2 / double(truth.size())), noise = std::sqrt(spread / double(truth.size()));
  double estimated_bias = 0, estimated_noise = 0, estimate = 0, actual = 0;
  for (const SeedRun& run : runs) {
    estimated_bias += run.estimates.back().bias / kSeeds;
    estimated_noise += run.estimates.back().noise / kSeeds;
    estimate += run.estimates.back().rmse / kSeeds;
    actual += run.actual.back() / kSeeds;
  }
  EXPECT_GT(bias, 0.5 * noise) << "the scene's bias should matter: bias " << bias << ", noise " << noise;
  EXPECT_NEAR(estimated_bias / bias, 1.0, 0.25) << "estimated bias " << estimated_bias << ", bias " << bias;
  EXPECT_NEAR(estimated_noise / noise, 1.0, 0.2) << "estimated noise " << estimated_noise << ", noise " << noise;
  EXPECT_LT(estimated_noise, 0.85 * actual) << "the spread alone would have done";
  EXPECT_NEAR(estimate / actual, 1.0, 0.25);
}

}  // namespace
}  // namespace farm
