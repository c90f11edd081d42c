// Issue 17 acceptance 6: caustic emission whose cost does not grow with the number of
// specular shapes. For 10 mirror spheres and for 10,000 over the same floor, under an area
// light and under a sun, on one thread: the time to aim the same number of caustic photons
// (EmitPhoton alone, what once looped over every shape), against the target of at most 2x,
// then the whole caustic shard (aiming and tracing) and the global shard, whose emission
// aims at nothing: how much tracing itself grows among 10,000 spheres. A missed target is
// printed as MISSED, not failed: the machine may be busy; each ratio comes from one run of
// both scenes back to back.
//
//   farm_bench_caustic_emission [paths]

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "photon/photon_emission.h"
#include "photon/trace_photons.h"
#include "scene/scene.h"
#include "scene/test_scenes.h"

namespace {

using namespace farm::testing;

// cols x rows mirror spheres in a grid over the same 10 x 10 of a white floor whatever
// their number (radius 0.4 of the grid's smaller spacing), lit by a quad light or a sun.
pb::Scene Spheres(int cols, int rows, bool sun) {
  pb::Scene s = MakeScene(4, 4, {0, -20, 10}, {0, 0, 0}, {0, 0, 1}, 40);
  AddLambert(s, "white", farm::Rgb(0.8f));
  pb::Material* mirror = s.add_materials();
  mirror->set_name("mirror");
  Set(mirror->mutable_mirror()->mutable_reflectance(), farm::Rgb(0.9f));
  AddQuad(s, "white", {-10, -10, 0}, {20, 0, 0}, {0, 20, 0});
  const double dx = 10.0 / cols, dy = 10.0 / rows, r = 0.4 * std::min(dx, dy);
  for (int i = 0; i < cols; ++i)
    for (int j = 0; j < rows; ++j) AddSphere(s, "mirror", {-5 + (i + 0.5) * dx, -5 + (j + 0.5) * dy, r}, r);
  if (sun) {
    pb::Light* light = s.add_lights();
    Set(light->mutable_sun()->mutable_direction(), {0.3, 0.2, -1});
    Set(light->mutable_sun()->mutable_irradiance(), farm::Rgb(3));
  } else {
    AddEmissive(s, "lamp", farm::Rgb(20));
    AddQuad(s, "lamp", {-1, -1, 8}, {0, 2, 0}, {2, 0, 0});
  }
  return s;
}

// Seconds to aim `paths` caustic photons (EmitPhoton alone: what grew with the shapes).
double Aim(const farm::Scene& scene, uint64_t paths) {
  const auto start = std::chrono::steady_clock::now();
  uint64_t emitted = 0;
  for (uint64_t i = 0; i < paths; ++i) {
    farm::PhotonRandom random(1, farm::PhotonMapKind::kCaustic, i);
    emitted += farm::EmitPhoton(scene.data(), farm::PhotonMapKind::kCaustic, random).has_value();
  }
  if (emitted == 0) std::printf("no photon emitted\n");
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Seconds to trace a shard of `paths` photon paths of a map (emission and tracing).
double Shard(const farm::Scene& scene, uint64_t paths, farm::PhotonMapKind kind) {
  const auto start = std::chrono::steady_clock::now();
  farm::TracePhotons(scene, {kind, 0, paths, paths});
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Times `run` on the few-spheres and the many-spheres scene, alternating, `repeats` times,
// and prints the fastest of each and their ratio: the fastest run is the one the machine's
// other work disturbed least, and alternating gives both scenes the same chances.
template <class Run>
void PrintRatio(const char* what, const farm::Scene& few, const farm::Scene& many, int repeats, bool target,
                Run run) {
  double best_few = 1e300, best_many = 1e300;
  for (int i = 0; i < repeats; ++i) {
    best_few = std::min(best_few, run(few));
    best_many = std::min(best_many, run(many));
  }
  const double ratio = best_many / best_few;
  std::printf("  %-48s 10 spheres %.3f s   10,000 spheres %.3f s   ratio %.2f%s\n", what, best_few, best_many, ratio,
              !target ? "" : ratio <= 2 ? " (target at most 2)" : " (target at most 2): MISSED");
}

}  // namespace

int main(int argc, char** argv) {
  const uint64_t paths = argc > 1 ? std::stoull(argv[1]) : 400'000;
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  std::printf("%llu photon paths per run, one thread, the fastest of 5 runs (aiming) or 3 (shards)\n",
              static_cast<unsigned long long>(paths));
  for (const bool sun : {false, true}) {
    std::printf("%s:\n", sun ? "sun" : "quad light");
    const farm::Scene few = farm::Scene::Build(Spheres(5, 2, sun), NoBlobs());
    const farm::Scene many = farm::Scene::Build(Spheres(100, 100, sun), NoBlobs());
    Shard(few, paths / 10, farm::PhotonMapKind::kCaustic);  // warm up
    PrintRatio("caustic emission, aiming (EmitPhoton)", few, many, 5, true,
               [&](const farm::Scene& s) { return Aim(s, paths); });
    PrintRatio("caustic shard, aiming and tracing", few, many, 3, false,
               [&](const farm::Scene& s) { return Shard(s, paths, farm::PhotonMapKind::kCaustic); });
    PrintRatio("global shard, tracing's own growth (no aiming)", few, many, 3, false,
               [&](const farm::Scene& s) { return Shard(s, paths, farm::PhotonMapKind::kGlobal); });
  }
  return 0;
}
