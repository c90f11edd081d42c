// Issue 14, acceptance 5: what the error estimate's bias layer costs a round. In process,
// for each scene given: its photons traced once into in-memory maps (global, caustic and
// volume, as the scene has them) with precomputed irradiance, then every pixel rendered
// at samples_per_pixel with the bias layer (each photon estimate and its companion:
// render/integrator.h) and without, alternating, the fastest of `repeats` each. Prints
// the times of tracing, precomputing and rendering, the render's ratio with / without, and
// a round's: (trace + precompute + render with) / (trace + precompute + render without),
// with a target of at most 1.30 (MISSED when above; timings on a shared machine are
// figures, not a test). Edge anti-aliasing's extra samples and the farm's phases outside
// the worker (build, merge, composite) are left out: they add to both sides alike, so the
// ratio printed is the most a round can grow.
//
//   farm_bench_bias_layer [size [repeats]] scene.json...
//   (default 64 3 and scenes/cornell-box.json, cornell-caustics.json, cornell-fog.json)

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "in_process.h"
#include "photon/irradiance_precompute.h"

namespace {

namespace pb = renderfarm::v1;

constexpr double kTarget = 1.30;

double Since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Measure(const std::string& path, int size, int repeats) {
  pb::Scene description = farm::bench::LoadScene(path);
  description.mutable_film()->set_width(size);
  description.mutable_film()->set_height(size);
  const farm::Scene scene = farm::bench::BuildScene(description);
  const farm::SceneData& data = scene.data();
  const pb::PhotonMapping& counts = description.photons();
  const auto paths = [](uint64_t n, uint64_t fallback) { return n ? n : fallback; };

  auto start = std::chrono::steady_clock::now();
  auto global = farm::testing::TraceIntoMemory(scene, farm::PhotonMapKind::kGlobal, paths(counts.global_photons(), 200000));
  auto caustic = farm::testing::TraceIntoMemory(scene, farm::PhotonMapKind::kCaustic, paths(counts.caustic_photons(), 200000));
  auto volume = farm::testing::TraceIntoMemory(scene, farm::PhotonMapKind::kVolume, paths(counts.volume_photons(), 200000));
  const double trace = Since(start);
  start = std::chrono::steady_clock::now();
  if (global) global->set_irradiance(farm::ComputeIrradiance(data, *global, caustic.get(), 0, global->size(), 1.0));
  const double precompute = Since(start);

  farm::PhotonMaps maps;
  maps.global = maps.irradiance = global.get();
  maps.caustic = caustic.get();
  maps.volume = volume.get();
  maps.global_estimate = farm::ToRadianceEstimate(data.photons.global_estimate);
  maps.caustic_estimate = farm::ToRadianceEstimate(data.photons.caustic_estimate);
  maps.volume_estimate = farm::ToRadianceEstimate(data.photons.volume_estimate);
  std::vector<int> pixels(std::size_t(data.width) * std::size_t(data.height));
  std::iota(pixels.begin(), pixels.end(), 0);
  double without = 1e30, with = 1e30;
  for (int r = 0; r < repeats; ++r) {
    for (const bool bias_layer : {false, true}) {
      const farm::PhotonMappingIntegrator integrator(data, maps, 1.0, bias_layer);
      double seconds = 0;
      farm::bench::RenderPixels(data, integrator, pixels, data.samples_per_pixel, data.seed, seconds);
      (bias_layer ? with : without) = std::min(bias_layer ? with : without, seconds);
    }
  }
  const double round_ratio = (trace + precompute + with) / (trace + precompute + without);
  std::printf("%s at %dx%d: trace %.2f s, precompute %.2f s, render %.2f s without the bias layer and %.2f s "
              "with (%.2fx); a round %.2fx (target <= %.2f)%s\n",
              path.c_str(), size, size, trace, precompute, without, with, with / without, round_ratio, kTarget,
              round_ratio <= kTarget ? "" : "  MISSED");
}

}  // namespace

int main(int argc, char** argv) try {
  const int size = argc > 1 ? std::stoi(argv[1]) : 64;
  const int repeats = argc > 2 ? std::stoi(argv[2]) : 3;
  std::vector<std::string> scenes(argv + std::min(argc, 3), argv + argc);
  if (scenes.empty())
    for (const char* name : {"cornell-box", "cornell-caustics", "cornell-fog"})
      scenes.push_back(std::string(PHOTONFARM_SCENES_DIR) + "/" + name + ".json");
  for (const std::string& path : scenes) Measure(path, size, repeats);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "farm_bench_bias_layer: %s\n", e.what());
  return 1;
}
