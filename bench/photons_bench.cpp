// Photons traced per second per core: traces the global and caustic maps of a scene (by
// default scenes/cornell-caustics.json) on one thread and on all threads, and prints paths
// per second, photons stored per second, and both per core.
//
//   farm_bench_photons [scene.json] [paths per map]

#include <google/protobuf/util/json_util.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "photon/trace_photons.h"
#include "renderfarm/v1/scene.pb.h"
#include "scene/scene.h"

namespace {

struct Run {
  double seconds = 0;
  uint64_t paths = 0, stored = 0;
};

Run TraceBoth(const farm::Scene& scene, uint64_t paths) {
  Run run;
  const auto start = std::chrono::steady_clock::now();
  for (farm::PhotonMapKind kind : {farm::PhotonMapKind::kGlobal, farm::PhotonMapKind::kCaustic}) {
    run.stored += farm::TracePhotons(scene, {kind, 0, paths, paths}).size();
    run.paths += paths;
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

void Print(const char* label, const Run& run, int threads) {
  std::printf("%-12s threads=%d  %.2f s  paths/s=%.0f  stored/s=%.0f  paths/s/core=%.0f  "
              "stored/s/core=%.0f\n",
              label, threads, run.seconds, run.paths / run.seconds, run.stored / run.seconds,
              run.paths / run.seconds / threads, run.stored / run.seconds / threads);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : PHOTONFARM_DEFAULT_SCENE;
  const uint64_t paths = argc > 2 ? std::stoull(argv[2]) : 200'000;
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "cannot read %s\n", path.c_str());
    return 2;
  }
  std::stringstream text;
  text << in.rdbuf();
  renderfarm::v1::Scene description;
  const auto status = google::protobuf::util::JsonStringToMessage(text.str(), &description);
  if (!status.ok()) {
    std::fprintf(stderr, "%s: %s\n", path.c_str(), status.ToString().c_str());
    return 2;
  }
  const farm::Scene scene = farm::Scene::Build(description, [](const std::string& d) -> std::string {
    throw std::runtime_error("no blob store in the benchmark: " + d);
  });
  std::printf("scene %s, %llu paths per map (global + caustic)\n", path.c_str(),
              static_cast<unsigned long long>(paths));
  TraceBoth(scene, paths / 10);  // warm up caches and TBB's threads
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    Print("1 thread", TraceBoth(scene, paths), 1);
  }
  const int all = tbb::info::default_concurrency();
  Print("all threads", TraceBoth(scene, paths), all);
  return 0;
}
