// Grid media (docs/media.md) rendered end to end against closed forms and against the
// homogeneous medium: a constant-density grid is the homogeneous medium of that density
// (the same expectation, reached by tracking instead of closed forms), and a glowing cube
// filled with an albedo-1 grid of any density keeps its radiance (the furnace of
// volume_furnace_test.cpp, heterogeneous: what the smoke takes from the walls' light it
// gives back, however thick it is where), whether its multiple scattering comes from the
// volume photon map or, for a peaked phase function, from volumetric paths.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "photon/test_photons.h"
#include "render/integrator.h"
#include "render/test_integrator.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

const std::string kGrid = FakeDigest("grid");

// A lit floor seen from above and in front in fog of density 0.3, albedo 0.8, g 0.3: as a
// homogeneous medium, or as a 4 x 4 x 4 grid of 1s with density scale 0.3 over a box that
// holds the scene's medium ball.
pb::Scene FoggyFloor(bool grid) {
  pb::Scene s = MakeScene(32, 32, {0, 2, 4}, {0, 0, 0}, {0, 1, 0}, 50, 1, 21);
  AddLambert(s, "white", Rgb(0.7f));
  AddQuad(s, "white", {-2, 0, 2}, {4, 0, 0}, {0, 0, -4});
  AddPointLight(s, {0.5, 1.5, 0.5}, Rgb(6));
  if (grid) {
    SetGridMedium(s.mutable_medium(), kGrid, Rgb(0.8f), 0.3f, 0.3f);
  } else {
    Set(s.mutable_medium()->mutable_albedo()->mutable_albedo(), Rgb(0.8f));
    s.mutable_medium()->mutable_albedo()->set_density(0.3);
    s.mutable_medium()->set_g(0.3);
  }
  return s;
}

// The mean of the centre pixels x pixels (samples each) of the scene's image lit by direct
// light and a volume map of `paths` photon paths (and no global map), with the number of
// volume photons stored.
SampleResult MeanWithVolumeMap(const Scene& scene, uint64_t paths, int pixels, uint32_t samples,
                               std::size_t& stored) {
  const SceneData& data = scene.data();
  const auto volume = TraceIntoMemory(scene, PhotonMapKind::kVolume, paths);
  stored = volume ? volume->size() : 0;
  PhotonMaps maps = MapsOf(data, nullptr);
  maps.volume = volume.get();
  maps.volume_estimate = ToRadianceEstimate(data.photons.volume_estimate);
  return MeanOverCentre(data, PhotonMappingIntegrator(data, maps), pixels, samples);
}

BlobLoader ConstantGridBlob() {
  return MapLoader({{kGrid, FarmGridBytes(4, 4, 4, Bounds3{{-4, -4, -4}, {4, 4, 4}}, std::vector<float>(64, 1.0f))}});
}

// Single scattering, the floor's direct light through the fog and the volume photon map's
// multiple scattering, homogeneous against the constant grid: the same expectation, each
// estimated with its own numbers (distances drawn by inverting the exact optical depth,
// delta-tracked photons; the grid's transmittance is exact). Measured: direct 0.00%, volume +0.6% at this sampling;
// the bounds leave room for the noise of both (ratio-tracked transmittance, which answers
// 0 or 1 through a uniform brick, was off by +57% here: the point light's halo multiplies
// that noise).
TEST(GridMedia, AConstantGridRendersAsTheHomogeneousMediumOfItsDensity) {
  SampleResult mean[2];
  for (const bool grid : {false, true}) {
    const Scene scene = Scene::Build(FoggyFloor(grid), grid ? ConstantGridBlob() : NoBlobs());
    std::size_t stored = 0;
    mean[grid] = MeanWithVolumeMap(scene, 100'000, 24, 16, stored);
    ASSERT_GT(stored, 0u);
    std::printf("%s: direct %.5f, volume %.5f, %zu volume photons\n", grid ? "grid" : "homogeneous", mean[grid].direct.g,
                mean[grid].volume.g, stored);
  }
  ASSERT_GT(mean[0].volume.g, 0.05 * mean[0].radiance.g) << "the fog must matter";
  EXPECT_NEAR(mean[1].direct.g / mean[0].direct.g, 1.0, 0.02);
  EXPECT_NEAR(mean[1].volume.g / mean[0].volume.g, 1.0, 0.03);
}

// The glowing cube of volume_furnace_test.cpp filled with smoke of albedo 1 and asymmetry g
// whose density varies from 0.2 to 1.8 per unit (a ramp along x times a bump along y,
// 12^3 cells).
Scene GridGlowingCube(float g) {
  pb::Scene s = MakeScene(32, 32, {0.5, 0.5, 0.5}, {0.5, 0.5, 1}, {0, 1, 0}, 90, 1, 13);
  s.mutable_photons()->mutable_volume_estimate()->set_neighbours(200);
  AddEmissive(s, "glow", Rgb(1));
  AddInwardCube(s, "glow");
  SetGridMedium(s.mutable_medium(), kGrid, Rgb(1), 1, g);
  const int n = 12;
  std::vector<float> densities;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        densities.push_back(0.2f + 1.6f * float(x) / (n - 1) * std::sin(3.14159265f * (float(y) + 0.5f) / n));
  return Scene::Build(s, MapLoader({{kGrid, FarmGridBytes(n, n, n, Bounds3{{0, 0, 0}, {1, 1, 1}}, densities)}}));
}

// Isotropic smoke, its multiple scattering from the volume photon map: the radiance stays
// Le = 1 within 1%.
TEST(GridMedia, AnAlbedoOneGridInAGlowingCubeKeepsItsRadiance) {
  const Scene scene = GridGlowingCube(0);
  std::size_t stored = 0;
  const SampleResult r = MeanWithVolumeMap(scene, 300'000, 32, 8, stored);
  ASSERT_GT(stored, 0u);
  std::printf("L = (%.5f, %.5f, %.5f) (closed form 1, %+.2f%%), emitted %.4f, volume %.4f, %zu volume photons\n",
              r.radiance.r, r.radiance.g, r.radiance.b, 100 * (r.radiance.g - 1), r.emitted.g, r.volume.g, stored);
  EXPECT_GT(r.volume.g, 0.1);
  EXPECT_NEAR(r.radiance.g, 1.0, 0.01);
}

// The same smoke with a lobe of |g| at or above path_traced_media_min_abs_g: no volume
// photon is stored in it, single scattering weighs light and phase samples by MIS with the
// grid's own distance densities, and light scattered more than once is path traced, the
// paths' free flights delta-tracked through the bricks (VolumePath). The furnace holds
// within 1% in every channel.
TEST(GridMedia, APathTracedAlbedoOneGridInAGlowingCubeKeepsItsRadiance) {
  for (const float g : {0.95f, -0.999f}) {
    SCOPED_TRACE("g = " + std::to_string(g));
    const Scene scene = GridGlowingCube(g);
    const SceneData& data = scene.data();
    EXPECT_EQ(TraceIntoMemory(scene, PhotonMapKind::kVolume, 20'000), nullptr) << "no volume photon in it";
    const SampleResult r = MeanOverCentre(data, PhotonMappingIntegrator(data, MapsOf(data, nullptr)), 32, 8);
    std::printf("g %+.3f: L = (%.5f, %.5f, %.5f) (closed form 1, %+.2f%%), emitted %.4f, direct %.4f, volume %.4f\n",
                g, r.radiance.r, r.radiance.g, r.radiance.b, 100 * (r.radiance.g - 1), r.emitted.g, r.direct.g,
                r.volume.g);
    EXPECT_GT(r.volume.g, 0.1);
    EXPECT_NEAR(r.radiance.r, 1.0, 0.01);
    EXPECT_NEAR(r.radiance.g, 1.0, 0.01);
    EXPECT_NEAR(r.radiance.b, 1.0, 0.01);
  }
}

// A grid file that breaks the format is refused as bad input naming the scene's field, the
// file and the byte.
TEST(GridMedia, ABadGridFileIsRefusedNamingTheFieldTheFileAndTheByte) {
  pb::Scene s = FoggyFloor(true);
  s.mutable_medium()->mutable_grid()->set_path("smoke/plume.farmgrid");
  std::vector<float> densities(64, 1.0f);
  densities[5] = -1;
  try {
    Scene::Build(s, MapLoader({{kGrid, FarmGridBytes(4, 4, 4, Bounds3{{-4, -4, -4}, {4, 4, 4}}, densities)}}));
    FAIL() << "built a scene whose grid has a negative density";
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(),
                 "medium.grid: farm grid file \"smoke/plume.farmgrid\" byte 68: the density of cell (1, 1, 0) is "
                 "negative: -1");
  }
}

}  // namespace
}  // namespace farm
