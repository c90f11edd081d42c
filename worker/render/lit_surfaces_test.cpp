// Issue 14, black pixels: one round of the two Cornell boxes at one sample per pixel, every
// camera sample that reaches a lit diffuse surface carries light, and none is NaN or
// infinite. Rendered in process with the round's photon maps (traced and precomputed as
// the farm's EMIT, BUILD and PRECOMPUTE phases do, minus quantisation).
//
// Which surfaces are lit is decided from the geometry: the boxes are closed but for the
// front, the light hangs 0.1 below the ceiling, and every interior point sees, with
// positive solid angle, some wall point that the light reaches directly, so its radiance
// (direct, or indirect through the gather rays and the photons' irradiance) is positive.
// The one exception is the ceiling right above the light: that 0.1-high gap sees only the
// back of the light (which reflects nothing) and the open front, so it is dark for any
// renderer whose emitter does not reflect. A sample there is not counted as lit.

#include <gtest/gtest.h>

#include <google/protobuf/util/json_util.h>

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

pb::Scene LoadScene(const std::string& name) {
  std::ifstream in(std::string(SCENES_DIR) + "/" + name);
  std::stringstream text;
  text << in.rdbuf();
  pb::Scene s;
  EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(text.str(), &s).ok()) << name;
  return s;
}

// The ceiling (y = 548.8) above the light's quad (x in [213, 343], z in [227, 332]).
bool AboveTheLight(const Vec3& p) {
  return p.y > 548.7f && p.x >= 213 && p.x <= 343 && p.z >= 227 && p.z <= 332;
}

struct Outcome {
  int lit = 0, zero = 0, nonfinite = 0;
};

// One round (sample 0 of each pixel, as the tile renderer draws it) of a size x size film.
Outcome RenderOneRound(const std::string& name, int size, uint64_t paths) {
  pb::Scene s = LoadScene(name);
  s.mutable_film()->set_width(size);
  s.mutable_film()->set_height(size);
  const Scene scene = Scene::Build(s, NoBlobs());
  const SceneData& data = scene.data();
  auto global = TraceIntoMemory(scene, PhotonMapKind::kGlobal, paths);
  std::unique_ptr<MemoryPhotonMap> caustic;
  if (!data.specular_targets.empty()) caustic = TraceIntoMemory(scene, PhotonMapKind::kCaustic, paths);
  global->set_irradiance(ComputeIrradiance(data, *global, caustic.get(), 0, global->size(), 1.0));
  PhotonMaps maps;
  maps.global = maps.irradiance = global.get();
  maps.caustic = caustic.get();
  maps.global_estimate = ToRadianceEstimate(data.photons.global_estimate);
  maps.caustic_estimate = ToRadianceEstimate(data.photons.caustic_estimate);
  const PhotonMappingIntegrator integrator(data, maps);
  EXPECT_TRUE(integrator.final_gathering());

  PixelSampler sampler(data.samples_per_pixel, data.seed);
  std::vector<PhotonNeighbour> scratch;
  Outcome out;
  for (int y = 0; y < data.height; ++y)
    for (int x = 0; x < data.width; ++x) {
      sampler.StartPixelSample(uint64_t(y) * data.width + x, 0);
      const Vec2 u = sampler.Get2D();
      const Ray ray = data.camera.GenerateRay({x + u.x, y + u.y});
      const SampleResult r = integrator.Li(ray, sampler, scratch);
      out.nonfinite += r.nonfinite;
      if (!r.shaded || (r.hit && AboveTheLight(ray.At(r.depth)))) continue;
      ++out.lit;
      if (r.radiance.IsBlack() && out.zero++ < 10)
        ADD_FAILURE() << name << ": pixel " << x << ", " << y << " is black; first hit at "
                      << ToString(ray.At(r.depth)) << ", normal " << ToString(r.normal);
    }
  std::printf("%s at %dx%d, one round: %d lit samples, %d black, %d non-finite\n", name.c_str(), size, size,
              out.lit, out.zero, out.nonfinite);
  return out;
}

TEST(LitSurfaces, OneRoundOfTheCornellBoxHasNoBlackOrNonFiniteSample) {
  const Outcome o = RenderOneRound("cornell-box.json", 128, 50'000);
  EXPECT_GT(o.lit, 128 * 128 / 2);
  EXPECT_EQ(o.zero, 0);
  EXPECT_EQ(o.nonfinite, 0);
}

TEST(LitSurfaces, OneRoundOfTheCausticsBoxHasNoBlackOrNonFiniteSample) {
  // Glass and a mirror: paths reach the walls through them too (SPLIT), and the mirror
  // shows the open front, which is black and not a lit surface (no diffuse hit).
  const Outcome o = RenderOneRound("cornell-caustics.json", 128, 50'000);
  EXPECT_GT(o.lit, 128 * 128 / 2);
  EXPECT_EQ(o.zero, 0);
  EXPECT_EQ(o.nonfinite, 0);
}

}  // namespace
}  // namespace farm
