// Final gathering against closed forms: the furnace sphere (every wall point's radiance is
// known exactly), a dark room behind a thin wall (exactly black), a wall lit by a ball's
// photons (its view factor), determinism, and the PHOTON_MAP mode still seeing the global
// map directly.

#include <gtest/gtest.h>

#include <cstdio>
#include <cmath>
#include <cstring>
#include <numbers>
#include <string>

#include "photon/irradiance_precompute.h"
#include "photon/test_photons.h"
#include "photon/trace_photons.h"
#include "photonmap/memory_photon_map.h"
#include "render/integrator.h"
#include "render/test_integrator.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

// Traces a scene's global photons into an in-memory map with precomputed irradiance: what
// the farm's EMIT, BUILD, PRECOMPUTE and MERGE phases give a tile, minus quantisation.
std::unique_ptr<MemoryPhotonMap> GlobalMapWithIrradiance(const Scene& scene, uint64_t paths) {
  auto map = TraceIntoMemory(scene, PhotonMapKind::kGlobal, paths);
  map->set_irradiance(ComputeIrradiance(scene.data(), *map, nullptr, 0, map->size(), 1.0));
  return map;
}

// The closed box [0, 2] x [0, 1] x [0, 1] as six quads of `material`: a room twice as long
// as it is wide.
void AddLongRoom(pb::Scene& s, const std::string& material) {
  const Vec3d x{2, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  AddQuad(s, material, {0, 0, 0}, x, z);  // floor
  AddQuad(s, material, {0, 1, 0}, x, z);  // ceiling
  AddQuad(s, material, {0, 0, 0}, x, y);  // front
  AddQuad(s, material, {0, 0, 1}, x, y);  // back
  AddQuad(s, material, {0, 0, 0}, y, z);  // left end
  AddQuad(s, material, {2, 0, 0}, y, z);  // right end
}

// The mean of one camera sample per pixel of the image's central 8 x 8 pixels, final
// gathering with `paths` global photon paths.
SampleResult FinalGatherOverCentre(const pb::Scene& s, uint64_t paths, int pixels = 8, uint32_t samples = 1) {
  const Scene scene = Scene::Build(s, NoBlobs());
  const SceneData& data = scene.data();
  const auto global = GlobalMapWithIrradiance(scene, paths);
  const PhotonMappingIntegrator integrator(data, MapsOf(data, global.get()));
  EXPECT_TRUE(integrator.final_gathering()) << integrator.ToString();
  return MeanOverCentre(data, integrator, pixels, samples);
}

// Inside a closed Lambert sphere of albedo rho and radius R, a point light of intensity I
// (power 4 pi I) at the centre: every wall point sees every other with the same form
// factor, so the radiance is L = rho Phi / (pi A (1 - rho)) = rho I / (pi R^2 (1 - rho)),
// of which rho I / (pi R^2) is direct. The camera at the centre looks at the wall.
// Also in spectral mode (every photon and camera path at eight wavelengths): a grey's
// uplift is flat, so the closed form holds there too.
TEST(FinalGather, FurnaceSphereGivesTheClosedFormRadianceInRgbAndSpectralModes) {
  const float rho = 0.5f, radius = 1.0f, intensity = 3.0f;
  for (const pb::SpectralSampling mode : {pb::SPECTRAL_SAMPLING_AUTO, pb::SPECTRAL_SAMPLING_ALWAYS}) {
    pb::Scene s = MakeScene(32, 32, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 30, 1, 5);
    s.mutable_sampling()->set_spectral(mode);
    AddLambert(s, "wall", Rgb(rho));
    AddSphere(s, "wall", {0, 0, 0}, radius);
    pb::Light* light = s.add_lights();
    Set(light->mutable_point()->mutable_position(), {0, 0, 0});
    Set(light->mutable_point()->mutable_intensity(), Rgb(intensity));
    // Spectral: each camera sample's wavelengths estimate white with a variance of up
    // to 0.011 per channel (spectral_light_test.cpp), so 16 stratified samples per pixel.
    const bool rgb = mode == pb::SPECTRAL_SAMPLING_AUTO;
    const SampleResult r = FinalGatherOverCentre(s, 300'000, rgb ? 8 : 4, rgb ? 1 : 16);
    const double pi = std::numbers::pi;
    const double direct = rho * intensity / (pi * radius * radius);
    const double total = direct / (1 - rho);
    const std::string name = pb::SpectralSampling_Name(mode);
    std::printf("furnace, %s: L = (%.5f, %.5f, %.5f) (closed form %.5f), indirect %.5f (%.5f)\n", name.c_str(),
                r.radiance.r, r.radiance.g, r.radiance.b, total, r.indirect.g, total - direct);
    // Spectral: the uplift of grey is flat to 1e-3 (uplift_test.cpp), and eight wavelengths
    // of each shadow ray estimate each channel.
    const double direct_tolerance = rgb ? 1e-3 : 5e-3;
    EXPECT_NEAR(r.direct.g, direct, direct_tolerance * direct) << name;
    // Within 1%: the box estimate's k/(k-1) bias (k = 100) on the indirect half is +0.5%,
    // the rest is noise of 64 gather rays x 64 pixels over 300k photons.
    EXPECT_NEAR(r.radiance.r, total, 0.01 * total) << name << ", indirect " << r.indirect.r;
    EXPECT_NEAR(r.radiance.g, total, 0.01 * total) << name;
    EXPECT_NEAR(r.radiance.b, total, 0.01 * total) << name;
    EXPECT_NEAR(r.indirect.b, total - direct, 0.02 * (total - direct)) << name;
  }
}

// A closed cube whose walls all emit Le and reflect rho (an emissive material with a
// reflectance): light bounces off the emitters themselves, and the radiance everywhere is
// L = Le / (1 - rho): Le emitted, rho Le direct (every wall sees only lit walls), the rest
// indirect. The camera at the centre looks at the middle of a wall. Without reflecting
// emitters it would see Le alone.
TEST(FinalGather, FurnaceCubeOfGlowingWallsGivesLeOverOneMinusRho) {
  const float rho = 0.5f, le = 1.0f;
  pb::Scene s = MakeScene(32, 32, {0.5, 0.5, 0.5}, {0.5, 0.5, 1}, {0, 1, 0}, 20, 1, 9);
  AddEmissive(s, "glow", Rgb(le), Rgb(rho));
  AddInwardCube(s, "glow");
  const SampleResult r = FinalGatherOverCentre(s, 200'000);
  const double total = le / (1 - rho), direct = rho * le, indirect = total - le - direct;
  std::printf("glowing cube: L = %.5f (closed form %.5f, %+.2f%%), direct %.5f (%.5f), indirect %.5f (%.5f)\n",
              r.radiance.g, total, 100 * (r.radiance.g / total - 1), r.direct.g, direct, r.indirect.g, indirect);
  EXPECT_NEAR(r.direct.g, direct, 0.01 * direct);
  // The indirect light is read from photon estimates at the gather rays' hits, some near
  // the cube's edges, where the estimate's disc hangs over the edge: within 3%.
  EXPECT_NEAR(r.indirect.g, indirect, 0.03 * indirect);
  EXPECT_NEAR(r.radiance.g, total, 0.01 * total);
}

// Two rooms side by side in a closed box, split by a thin wall (0.02 thick, much thinner
// than the photon search radius); a point light in the left room. The right room receives
// no light at all: its floor at the foot of the wall must be exactly black. The global map
// seen directly leaks there (photons on the lit floor, across the wall, are within the
// search radius and face the same way); final gathering must not.
TEST(FinalGather, NoLightLeaksUnderAThinWallIntoADarkRoom) {
  pb::Scene s = MakeScene(16, 16, {1.7, 0.5, 0.5}, {1.01, 0.03, 0.5}, {0, 1, 0}, 20, 1, 3);
  AddLambert(s, "white", Rgb(0.8f));
  AddLongRoom(s, "white");
  const Vec3d y{0, 1, 0}, z{0, 0, 1};
  AddQuad(s, "white", {0.99, 0, 0}, y, z);  // the wall's lit face
  AddQuad(s, "white", {1.01, 0, 0}, y, z);  // its dark face
  pb::Light* light = s.add_lights();
  Set(light->mutable_point()->mutable_position(), {0.5, 0.5, 0.5});
  Set(light->mutable_point()->mutable_intensity(), Rgb(1));
  const Scene scene = Scene::Build(s, NoBlobs());
  const SceneData& data = scene.data();
  ASSERT_GT(data.photons.global_estimate.max_radius, 0.02f * 3);
  const auto global = GlobalMapWithIrradiance(scene, 20'000);
  const PhotonMaps maps = MapsOf(data, global.get());

  const PhotonMappingIntegrator gather(data, maps);
  ASSERT_TRUE(gather.final_gathering());
  const SampleResult dark = MeanOverCentre(data, gather, 8, 1);
  EXPECT_EQ(dark.radiance.r, 0.0f);
  EXPECT_EQ(dark.radiance.g, 0.0f);
  EXPECT_EQ(dark.radiance.b, 0.0f);

  pb::Scene direct_view = s;
  direct_view.mutable_indirect()->set_mode(pb::INDIRECT_MODE_PHOTON_MAP);
  const Scene leaky_scene = Scene::Build(direct_view, NoBlobs());
  const PhotonMappingIntegrator leaky(leaky_scene.data(), maps);
  ASSERT_FALSE(leaky.final_gathering());
  EXPECT_GT(MeanOverCentre(leaky_scene.data(), leaky, 8, 1).indirect.g, 0.0f)
      << "the scene no longer shows the leak the remedy is for";

  // The lit room's corner at the foot of the wall is lit, indirect light included.
  pb::Scene lit = s;
  Set(lit.mutable_camera()->mutable_position(), {0.3, 0.5, 0.5});
  Set(lit.mutable_camera()->mutable_look_at(), {0.99, 0.03, 0.5});
  const Scene lit_scene = Scene::Build(lit, NoBlobs());
  const PhotonMappingIntegrator lit_gather(lit_scene.data(), maps);
  const SampleResult corner = MeanOverCentre(lit_scene.data(), lit_gather, 8, 1);
  EXPECT_GT(corner.indirect.g, 0.0f);
  EXPECT_TRUE(corner.radiance.IsFinite());
}

// The bias layer's share of final gathering: with it, one shading point in four recomputes
// at one of its gather rays the irradiance of the photon that ray reads with the
// precompute's companion estimates (twice the neighbours over twice the area), weighted to
// stand for all of them. It must come out as what the indirect light gains when the whole
// precompute is done with the companion estimates (a second array, the same photons, the
// same gather rays): a room lit by a point light near its wall, estimated from few photons
// with many neighbours (400 of 8,000 paths) so that the blur shows through gathering,
// which averages it again: the companion precompute moves the indirect light by -0.27%
// (with the default 100 neighbours of 50,000 paths, by -0.01%, within the layer's noise).
TEST(FinalGather, TheBiasLayerIsWhatTheCompanionPrecomputeAddsToTheIndirectLight) {
  const auto room = [](uint32_t neighbours, double max_radius) {
    pb::Scene s = MakeScene(32, 32, {1.0, 0.5, 0.5}, {0.0, 0.4, 0.5}, {0, 1, 0}, 50, 16, 4);
    AddLambert(s, "white", Rgb(0.7f));
    AddLongRoom(s, "white");  // the camera looks at its left end
    AddPointLight(s, {0.15, 0.5, 0.5}, Rgb(1));
    s.mutable_photons()->mutable_global_estimate()->set_neighbours(neighbours);
    s.mutable_photons()->mutable_global_estimate()->set_max_radius(max_radius);
    return s;
  };
  const Scene scene = Scene::Build(room(400, 0.6), NoBlobs());
  const Scene companion_scene = Scene::Build(room(800, 0.6 * std::numbers::sqrt2), NoBlobs());
  const SceneData& data = scene.data();
  auto global = TraceIntoMemory(scene, PhotonMapKind::kGlobal, 8'000);
  auto companion_global = TraceIntoMemory(scene, PhotonMapKind::kGlobal, 8'000);
  global->set_irradiance(ComputeIrradiance(data, *global, nullptr, 0, global->size(), 1.0));
  companion_global->set_irradiance(
      ComputeIrradiance(companion_scene.data(), *companion_global, nullptr, 0, companion_global->size(), 1.0));

  const PhotonMappingIntegrator with_layer(data, MapsOf(data, global.get()), 1.0, /*bias_layer=*/true);
  const PhotonMappingIntegrator companion(data, MapsOf(data, companion_global.get()));
  const SampleResult a = MeanOverCentre(data, with_layer, 16, 48);
  const SampleResult b = MeanOverCentre(data, companion, 16, 48);
  const double gain = b.indirect.g - a.indirect.g;
  std::printf("indirect %.5f, with the companion precompute %.5f: %+.5f; bias layer %+.5f\n", a.indirect.g,
              b.indirect.g, gain, a.bias.g);
  ASSERT_GT(std::abs(gain), 0.002 * a.indirect.g) << "the scene's precompute should be visibly biased";
  EXPECT_NEAR(a.bias.g, gain, 0.15 * std::abs(gain));
  // The beauty is the same with the layer as without.
  const SampleResult plain = MeanOverCentre(data, PhotonMappingIntegrator(data, MapsOf(data, global.get())), 16, 48);
  EXPECT_EQ(plain.radiance, a.radiance);
}

// A Lambert ball of albedo rho_s and radius R in front of a Lambert wall of albedo rho_f,
// its centre at distance H on the wall's normal at the point the camera looks at; a point
// light behind the wall, which lights neither (the scene needs a light), and a global map of photons spread evenly over the ball, each holding irradiance E. The
// ball's radiance is rho_s E / pi everywhere, and it covers the share (R / H)^2 of the wall
// point's cosine-weighted hemisphere (the view factor of a sphere on the normal), so the
// wall's indirect radiance is rho_f rho_s E (R / H)^2 / pi. A gather ray that lands on the
// ball reads the photon nearest to where it lands, on the same convex surface, whose chord
// to it runs beneath the surface: the lookup must not take the ball for a wall in between.
TEST(FinalGather, GatherRaysReadThePhotonsOfAConvexSurface) {
  const double rho_f = 0.8, rho_s = 0.5, radius = 0.5, height = 1.0, e = 2.0;
  pb::Scene s = MakeScene(16, 16, {2, 0, 1.5}, {0, 0, 0}, {0, 1, 0}, 2, 1, 7);
  AddLambert(s, "wall", Rgb(float(rho_f)));
  AddLambert(s, "ball", Rgb(float(rho_s)));
  AddQuad(s, "wall", {-3, -3, 0}, {6, 0, 0}, {0, 6, 0});
  AddSphere(s, "ball", {0, 0, height}, radius);
  AddPointLight(s, {0, 0, -1}, Rgb(1));
  const Scene scene = Scene::Build(s, NoBlobs());
  const SceneData& data = scene.data();
  // A Fibonacci lattice of photons on the ball, about 1.4 cm apart: the nearest photon to a
  // gather hit lies a few millimetres away, where the ball's surface bows out above the
  // chord by far more than the ray offset.
  const int count = 4000;
  std::vector<DecodedPhoton> photons;
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1 - (2 * i + 1.0) / count, r = std::sqrt(1 - z * z), phi = golden * i;
    const Vec3 n(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
    photons.push_back({Vec3(0, 0, float(height)) + n * float(radius), Rgb(1e-4f), n, n});
  }
  MemoryPhotonMap global(std::move(photons));
  global.set_irradiance(std::vector<Rgb>(count, Rgb(float(e))));
  const PhotonMappingIntegrator integrator(data, MapsOf(data, &global));
  ASSERT_TRUE(integrator.final_gathering()) << integrator.ToString();

  const SampleResult r = MeanOverCentre(data, integrator, 4, 16);
  const double expected = rho_f * rho_s * e * (radius / height) * (radius / height) / std::numbers::pi;
  std::printf("wall before a ball: indirect %.5f (closed form %.5f, %+.2f%%)\n", r.indirect.g, expected,
              100 * (r.indirect.g / expected - 1));
  EXPECT_EQ(r.direct.g, 0.0f);
  // Within 3%: the noise of 64 stratified gather rays x 256 samples, of which a quarter
  // land on the ball.
  EXPECT_NEAR(r.indirect.g, expected, 0.03 * expected);
}

TEST(FinalGather, SamplesAreBitIdenticalWhateverTheOrderTheyAreTakenIn) {
  pb::Scene s = MakeScene(16, 16, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 60, 1, 9);
  AddLambert(s, "wall", Rgb(0.6f, 0.5f, 0.4f));
  AddSphere(s, "wall", {0, 0, 0}, 1);
  pb::Light* light = s.add_lights();
  Set(light->mutable_point()->mutable_position(), {0.2, 0.3, 0});
  Set(light->mutable_point()->mutable_intensity(), Rgb(1));
  const Scene scene = Scene::Build(s, NoBlobs());
  const SceneData& data = scene.data();
  const auto global = GlobalMapWithIrradiance(scene, 20'000);
  const PhotonMappingIntegrator integrator(data, MapsOf(data, global.get()));
  auto render = [&](bool reverse) {
    std::vector<Rgb> out(data.width * data.height);
    PixelSampler sampler(1, data.seed);
    std::vector<PhotonNeighbour> scratch;
    for (int k = 0; k < data.width * data.height; ++k) {
      const int i = reverse ? data.width * data.height - 1 - k : k;
      sampler.StartPixelSample(i, 0);
      const Vec2 u = sampler.Get2D();
      out[i] = integrator.Li(data.camera.GenerateRay({i % data.width + u.x, i / data.width + u.y}),
                             sampler, scratch).radiance;
    }
    return out;
  };
  const std::vector<Rgb> a = render(false), b = render(true);
  ASSERT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(Rgb)), 0);
  double sum = 0;
  for (const Rgb& c : a) sum += c.g;
  EXPECT_GT(sum, 0);
}

}  // namespace
}  // namespace farm
