// Caustic emission against the number of specular shapes (issue 17, acceptance 6): emits
// the same number of caustic photons (EmitPhoton alone, no tracing) in a scene of 10 and
// one of 10,000 metal balls under a quad lamp, a point light and a sun, and prints the cost
// per photon of each and their ratio against the target of 2x ("met" or "MISSED": a
// figure, not an error), then main's emission before it (every cone summed, a pass over
// every ball a photon) as the baseline. Each side is timed in CPU seconds of its thread, in interleaved
// repetitions, the median kept, so a busy machine slows neither side alone. Then, for
// context, the whole caustic map of each scene (tracing included) on one thread.
//
//   farm_bench_caustic_emission [photons per repetition] [repetitions]

#include <tbb/global_control.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "photon/every_cone_emission.h"
#include "photon/photon_emission.h"
#include "photon/photon_random.h"
#include "photon/trace_photons.h"
#include "sampling/hash.h"
#include "sampling/sobol.h"
#include "scene/test_scenes.h"

namespace {

using namespace farm::testing;

// The floor and lights of every scene, no balls.
pb::Scene Room() {
  pb::Scene s = MakeScene(4, 4, {0, -30, 10}, {0, 0, 0}, {0, 0, 1}, 40);
  AddLambert(s, "white", farm::Rgb(0.5f));
  AddEmissive(s, "lamp", farm::Rgb(4));
  pb::Material* metal = s.add_materials();
  metal->set_name("metal");
  Set(metal->mutable_mirror()->mutable_reflectance(), farm::Rgb(0.9f));
  AddQuad(s, "white", {-25, -25, 0}, {50, 0, 0}, {0, 50, 0});
  AddQuad(s, "lamp", {-1, -1, 12}, {0, 2, 0}, {2, 0, 0});  // facing down
  AddPointLight(s, {5, -3, 8}, farm::Rgb(40));
  auto* sun = s.add_lights()->mutable_sun();
  Set(sun->mutable_direction(), {0.3, 0.2, -1});
  Set(sun->mutable_irradiance(), farm::Rgb(1));
  return s;
}

// `side` x `side` metal balls of radius 0.15 on a grid of pitch 0.4 centred on the floor.
pb::Scene Balls(int side) {
  pb::Scene s = Room();
  const double start = -0.2 * (side - 1);
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) AddSphere(s, "metal", {start + 0.4 * i, start + 0.4 * j, 0.15}, 0.15);
  return s;
}

// Side 3 plus one ball: 10.
pb::Scene TenBalls() {
  pb::Scene s = Balls(3);
  AddSphere(s, "metal", {3, 3, 0.15}, 0.15);
  return s;
}

// 10,000 such balls scattered through a 20 x 20 x 6 box on the floor (a ray passes near
// more of them than over the grid).
pb::Scene Cloud() {
  pb::Scene s = Room();
  const auto unit = [](uint64_t a, uint64_t i) { return farm::FractionToFloat(static_cast<uint32_t>(farm::Hash(a, i))); };
  for (uint64_t i = 0; i < 10'000; ++i)
    AddSphere(s, "metal", {-10 + 20.0 * unit(1, i), -10 + 20.0 * unit(2, i), 0.15 + 6.0 * unit(3, i)}, 0.15);
  return s;
}

double ThreadSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}

struct Emission {
  double seconds = 0;
  uint64_t emitted = 0;  // photons that carry light
};

std::optional<farm::PhotonRay> EmitNow(const farm::SceneData& scene, farm::PhotonRandom& random) {
  return farm::EmitPhoton(scene, farm::PhotonMapKind::kCaustic, random);
}

template <typename Emitter = decltype(EmitNow)>
Emission Emit(const farm::SceneData& scene, uint64_t first, uint64_t photons, Emitter&& emit = EmitNow) {
  Emission e;
  const double start = ThreadSeconds();
  for (uint64_t i = first; i < first + photons; ++i) {
    farm::PhotonRandom random(scene.seed, farm::PhotonMapKind::kCaustic, i);
    if (emit(scene, random)) ++e.emitted;
  }
  e.seconds = ThreadSeconds() - start;
  return e;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const uint64_t photons = argc > 1 ? std::stoull(argv[1]) : 1'000'000;
  const int repetitions = argc > 2 ? std::stoi(argv[2]) : 5;
  const farm::Scene few = farm::Scene::Build(TenBalls(), NoBlobs());
  const farm::Scene many = farm::Scene::Build(Balls(100), NoBlobs());
  const farm::Scene cloud = farm::Scene::Build(Cloud(), NoBlobs());
  std::printf("caustic emission, %llu photons a repetition, %d repetitions interleaved, thread CPU time\n",
              static_cast<unsigned long long>(photons), repetitions);
  std::vector<double> few_ns, many_ns, cloud_ns;
  Emission last_few, last_many;
  Emit(few.data(), 0, photons / 10);  // warm up
  Emit(many.data(), 0, photons / 10);
  for (int r = 0; r < repetitions; ++r) {
    last_few = Emit(few.data(), r * photons, photons);
    last_many = Emit(many.data(), r * photons, photons);
    few_ns.push_back(last_few.seconds * 1e9 / photons);
    many_ns.push_back(last_many.seconds * 1e9 / photons);
    cloud_ns.push_back(Emit(cloud.data(), r * photons, photons).seconds * 1e9 / photons);
  }
  const double a = Median(few_ns), b = Median(many_ns);
  std::printf("%6zu specular balls: %7.1f ns a photon (%.0f%% carry light)\n", few.data().specular_targets.size(), a,
              100.0 * last_few.emitted / photons);
  std::printf("%6zu specular balls: %7.1f ns a photon (%.0f%% carry light)\n", many.data().specular_targets.size(), b,
              100.0 * last_many.emitted / photons);
  const double ratio = b / a;
  std::printf("10,000 / 10 balls: %.2fx (target at most 2x: %s)\n", ratio, ratio <= 2 ? "met" : "MISSED");
  std::printf(" 10000 balls in a 20 x 20 x 6 box, for context: %.1f ns a photon, %.2fx the 10 balls\n",
              Median(cloud_ns), Median(cloud_ns) / a);

  // The baseline: main's emission before issue 17, a pass over every sphere a photon
  // (photon/every_cone_emission.h), on a hundredth of the photons.
  const uint64_t few_photons = std::max<uint64_t>(photons / 100, 1);
  for (const farm::Scene* scene : {&few, &many}) {
    const Emission e = Emit(scene->data(), 0, few_photons, farm::testing::EmitByEveryCone);
    const double ns = e.seconds * 1e9 / few_photons;
    std::printf("%6zu specular balls, every cone summed (before issue 17): %9.1f ns a photon, %.1fx this emission\n",
                scene->data().specular_targets.size(), ns, ns / (scene == &few ? a : b));
  }

  // Context: the whole caustic map, tracing included, on one thread.
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const uint64_t paths = photons / 5;
  for (const farm::Scene* scene : {&few, &many}) {
    const double start = ThreadSeconds();
    const auto stored = farm::TracePhotons(*scene, {farm::PhotonMapKind::kCaustic, 0, paths, paths}).size();
    std::printf("caustic map of %zu balls, traced: %llu paths, %zu photons stored, %.2f s\n",
                scene->data().specular_targets.size(), static_cast<unsigned long long>(paths), stored,
                ThreadSeconds() - start);
  }
  return 0;
}
