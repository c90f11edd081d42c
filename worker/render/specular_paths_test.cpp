// Camera paths through specular surfaces and delta lights, against closed forms.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "render/integrator.h"
#include "sampling/pixel_sampler.h"
#include "render/test_images.h"
#include "render/tile_renderer.h"
#include "scene/fresnel.h"
#include "scene/scene_data.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr double kPiD = std::numbers::pi;

Rgb CentrePixel(const pb::Scene& s) {
  const Scene scene = Scene::Build(s, NoBlobs());
  const Image image = RenderTile(scene, nullptr, {0, 0, 1, 1});
  const float* p = image.pixel(0, 0);
  return {p[0], p[1], p[2]};
}

// A camera at the origin looking down +z through a 0.5 degree field of view.
pb::Scene Narrow(uint32_t spp) { return MakeScene(1, 1, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 0.5, spp, 3); }

void AddMaterial(pb::Scene& s, const std::string& name,
                 const std::function<void(pb::Material*)>& fill) {
  pb::Material* m = s.add_materials();
  m->set_name(name);
  fill(m);
}

TEST(SpecularPaths, MirrorShowsTheEmitterScaledByItsReflectance) {
  // Camera -> mirror tilted 45 degrees -> emitter to the side.
  pb::Scene s = Narrow(4);
  AddEmissive(s, "lamp", Rgb(2, 3, 4));
  AddMaterial(s, "mirror", [](pb::Material* m) { Set(m->mutable_mirror()->mutable_reflectance(), Rgb(0.5f)); });
  // Mirror through (0, 0, 5) with normal (1, 0, -1)/sqrt2: the ray turns to +x.
  AddQuad(s, "mirror", {-1, -1, 4}, {0, 2, 0}, {2, 0, 2});
  AddQuad(s, "lamp", {10, -5, 0}, {0, 0, 10}, {0, 10, 0});  // x = 10, facing -x
  const Rgb L = CentrePixel(s);
  EXPECT_NEAR(L.r, 1.0f, 1e-5);
  EXPECT_NEAR(L.b, 2.0f, 1e-5);
}

TEST(SpecularPaths, GlassSlabTransmitsEmitterRadianceUnscaledOnTheWayOut) {
  // A slab between the camera and an emitter, at normal incidence: the radiance scales by
  // 1/eta^2 going in and eta^2 coming out, and the stochastic Fresnel choices at the two
  // faces sum the inter-reflections to (1 - R) / (1 + R) of the emitter's radiance.
  pb::Scene s = Narrow(4096);
  AddEmissive(s, "lamp", Rgb(1));
  AddMaterial(s, "glass", [](pb::Material* m) { m->mutable_dielectric()->set_ior(1.5); });
  AddQuad(s, "glass", {-5, -5, 5}, {0, 10, 0}, {10, 0, 0});    // entry face, front -z
  AddQuad(s, "glass", {-5, -5, 5.5}, {10, 0, 0}, {0, 10, 0});  // exit face, front +z
  AddQuad(s, "lamp", {-50, -50, 10}, {0, 100, 0}, {100, 0, 0});  // facing -z
  const double R = FresnelDielectric(1, 1.5f);
  const double expected = (1 - R) / (1 + R);
  const Rgb L = CentrePixel(s);
  EXPECT_NEAR(L.g, expected, 0.01) << "R = " << R;
}

// The slab of GlassSlabTransmitsEmitterRadianceUnscaledOnTheWayOut in a 4x4 image at one
// sample per pixel, glass sampled as `specular` says.
Image GlassSlabAtOneSample(pb::SpecularSampling specular) {
  pb::Scene s = MakeScene(4, 4, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 0.5, 1, 3);
  s.mutable_sampling()->set_specular(specular);
  s.mutable_antialiasing()->set_mode(pb::ANTIALIASING_MODE_NONE);  // one sample, also at edges
  AddEmissive(s, "lamp", Rgb(1));
  AddMaterial(s, "glass", [](pb::Material* m) { m->mutable_dielectric()->set_ior(1.5); });
  AddQuad(s, "glass", {-5, -5, 5}, {0, 10, 0}, {10, 0, 0});
  AddQuad(s, "glass", {-5, -5, 5.5}, {10, 0, 0}, {0, 10, 0});
  AddQuad(s, "lamp", {-50, -50, 10}, {0, 100, 0}, {100, 0, 0});
  return RenderTile(Scene::Build(s, NoBlobs()), nullptr, {0, 0, 4, 4});
}

TEST(SpecularPaths, SplitGlassSlabIsItsClosedFormAtOneSample) {
  // SPLIT follows both ways at the first three faces: the light through both faces,
  // (1 - R)^2, and the first inter-reflection are exact, and what is left to chance after
  // the third face carries at most (1 - R) R^2 (0.0015). A path that chooses at every face
  // brings the lamp whole (1) or nothing: never the mean, at least R^2 + R (1 - R) / (1 + R)
  // (0.075) away from it.
  const double R = FresnelDielectric(1, 1.5f);
  const double expected = (1 - R) / (1 + R);
  const Image split = GlassSlabAtOneSample(pb::SPECULAR_SAMPLING_SPLIT);
  const Image choose = GlassSlabAtOneSample(pb::SPECULAR_SAMPLING_CHOOSE);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      EXPECT_NEAR(split.pixel(x, y)[1], expected, 2 * (1 - R) * R * R) << "pixel " << x << ", " << y;
      EXPECT_GT(std::abs(choose.pixel(x, y)[1] - expected), 0.07) << "pixel " << x << ", " << y;
    }
}

TEST(SpecularPaths, GlassSphereInAWhiteFurnaceStaysWhiteEitherWay) {
  // Lossless glass in a constant white environment, nothing else: every path that leaves
  // the sphere sees radiance 1 and every bounce conserves it (R + (1 - R) = 1, and the
  // 1 / eta^2 going in is eta^2 coming out), so each pixel's expected value is exactly 1
  // with either strategy; Russian roulette inside the sphere is all that varies.
  for (const pb::SpecularSampling specular : {pb::SPECULAR_SAMPLING_SPLIT, pb::SPECULAR_SAMPLING_CHOOSE}) {
    pb::Scene s = MakeScene(16, 16, {0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 30, 64, 7);
    s.mutable_sampling()->set_specular(specular);
    Set(s.mutable_environment()->mutable_radiance(), Rgb(1));
    AddMaterial(s, "glass", [](pb::Material* m) { m->mutable_dielectric()->set_ior(1.5); });
    AddSphere(s, "glass", {0, 0, 0}, 1);
    const Image image = RenderTile(Scene::Build(s, NoBlobs()), nullptr, {0, 0, 16, 16});
    double sum = 0;
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) sum += image.pixel(x, y)[1];
    EXPECT_NEAR(sum / 256, 1.0, 2e-3) << pb::SpecularSampling_Name(specular);
  }
}

// Edge anti-aliasing's pilots trace a camera ray for its cues alone (render/edge_detect.h):
// they must be the cues Li finds on the same ray with the same dimensions, through mirrors
// and glass, split or chosen.
TEST(SpecularPaths, CuesAreWhatLiFindsOnTheSameRay) {
  for (const pb::SpecularSampling specular : {pb::SPECULAR_SAMPLING_SPLIT, pb::SPECULAR_SAMPLING_CHOOSE}) {
    pb::Scene s = MakeScene(24, 24, {0, 1, 6}, {0, 0.5, 0}, {0, 1, 0}, 40, 1, 5);
    s.mutable_sampling()->set_specular(specular);
    AddLambert(s, "white", Rgb(0.7f));
    AddEmissive(s, "lamp", Rgb(5));
    AddMaterial(s, "mirror", [](pb::Material* m) { Set(m->mutable_mirror()->mutable_reflectance(), Rgb(0.9f)); });
    AddMaterial(s, "glass", [](pb::Material* m) { m->mutable_dielectric()->set_ior(1.5); });
    AddQuad(s, "white", {-4, 0, -4}, {0, 0, 8}, {8, 0, 0});
    AddQuad(s, "lamp", {-1, 3, -1}, {2, 0, 0}, {0, 0, 2});  // facing down
    AddSphere(s, "mirror", {-0.8, 0.6, 0}, 0.6);
    AddSphere(s, "glass", {0.8, 0.6, 0.5}, 0.6);
    const Scene scene = Scene::Build(s, NoBlobs());
    const SceneData& data = scene.data();
    const PhotonMappingIntegrator integrator(data, PhotonMaps{});
    PixelSampler li_sampler(4, 11), cue_sampler(4, 11);
    std::vector<PhotonNeighbour> scratch;
    int specular_hits = 0, lamp_seen = 0;
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x)
        for (uint32_t j = 0; j < 4; ++j) {
          const Ray ray = data.camera.GenerateRay({x + (j + 0.5f) / 4, y + 0.5f});
          li_sampler.StartPixelSample(uint64_t(y) * 24 + x, j);
          cue_sampler.StartPixelSample(uint64_t(y) * 24 + x, j);
          const SampleResult li = integrator.Li(ray, li_sampler, scratch);
          const SampleResult cues = integrator.Cues(ray, cue_sampler);
          ASSERT_EQ(cues.surface, li.surface) << x << ", " << y << ", " << j;
          ASSERT_EQ(cues.hit, li.hit) << x << ", " << y << ", " << j;
          ASSERT_EQ(cues.surface_normal, li.surface_normal) << x << ", " << y << ", " << j;
          ASSERT_EQ(cues.depth, li.depth) << x << ", " << y << ", " << j;
          // No light but what the lamp emits towards the path, as Li finds it (edge
          // anti-aliasing's bright edges read it).
          ASSERT_EQ(cues.emitted, li.emitted) << x << ", " << y << ", " << j;
          ASSERT_EQ(cues.radiance, cues.emitted) << "cues find no other light";
          specular_hits += li.hit && li.surface != 0 && !li.shaded;
          lamp_seen += !li.emitted.IsBlack();
        }
    // Some samples saw a sphere and went on through it (a chain of surfaces, not one), and
    // some saw the lamp.
    EXPECT_GT(specular_hits, 0) << pb::SpecularSampling_Name(specular);
    EXPECT_GT(lamp_seen, 0) << pb::SpecularSampling_Name(specular);
  }
}

// A light reflected in glass is part of the surface cue although the first branch refracts:
// a glass sphere (centre (0, 0, 5), radius 1) before a white wall, seen from the origin, and
// a small lamp behind the camera. The ray through the sphere's centre reflects straight back
// into the lamp; one that meets the sphere half a radius off its axis reflects 66 degrees
// aside and misses it. Both refract onto the wall.
TEST(SpecularPaths, ALightReflectedInGlassIsPartOfTheSurfaceCue) {
  pb::Scene s = MakeScene(8, 8, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 30, 1, 5);
  AddLambert(s, "white", Rgb(0.7f));
  AddEmissive(s, "lamp", Rgb(5));
  AddMaterial(s, "glass", [](pb::Material* m) { m->mutable_dielectric()->set_ior(1.5); });
  AddQuad(s, "white", {-20, -20, 12}, {40, 0, 0}, {0, 40, 0});
  AddQuad(s, "lamp", {-0.5, -0.5, -3}, {1, 0, 0}, {0, 1, 0});
  AddSphere(s, "glass", {0, 0, 5}, 1);
  const Scene scene = Scene::Build(s, NoBlobs());
  const SceneData& data = scene.data();
  const PhotonMappingIntegrator integrator(data, PhotonMaps{});
  PixelSampler sampler(1, 11);
  const auto cues = [&](const Vec3& direction) {
    sampler.StartPixelSample(0, 0);
    return integrator.Cues(Ray{Vec3(0, 0, 0), Normalize(direction)}, sampler);
  };
  std::vector<PhotonNeighbour> scratch;
  const SampleResult centre = cues({0, 0, 1});
  const SampleResult aside = cues({0.1f, 0, 1});  // meets the sphere 0.5 off its axis
  sampler.StartPixelSample(0, 0);
  const SampleResult lit = integrator.Li(Ray{Vec3(0, 0, 0), Vec3(0, 0, 1)}, sampler, scratch);
  EXPECT_GT(lit.emitted.g, 0.1f) << "the centre's reflection shows the lamp (Fresnel 0.04 of 5)";
  EXPECT_EQ(lit.surface, centre.surface);
  EXPECT_NE(centre.surface, aside.surface) << "the lamp reflected at the centre is a cue";
  // The same surfaces with a point light for the lamp: the glass and the wall behind it.
  s.mutable_shapes()->DeleteSubrange(1, 1);
  AddPointLight(s, {0, 0, -3}, Rgb(5));
  const Scene dark = Scene::Build(s, NoBlobs());
  const PhotonMappingIntegrator unlit(dark.data(), PhotonMaps{});
  sampler.StartPixelSample(0, 0);
  const uint32_t a = unlit.Cues(Ray{Vec3(0, 0, 0), Vec3(0, 0, 1)}, sampler).surface;
  sampler.StartPixelSample(0, 0);
  const uint32_t b = unlit.Cues(Ray{Vec3(0, 0, 0), Normalize(Vec3(0.1f, 0, 1))}, sampler).surface;
  EXPECT_EQ(a, b) << "without the lamp, both rays meet the glass and then the wall";
}

TEST(SpecularPaths, DispersiveGlassInAWhiteFurnaceStaysWhiteInEveryChannel) {
  // As above, but each path through the glass is traced at one wavelength: the clipped
  // matching functions add up to white over the spectrum (spectral/monochrome.h), so each
  // channel's mean stays 1, from an index barely above air to one of 4 across the spectrum
  // and Abbe numbers from 20 to 90, with no NaN or infinity anywhere.
  struct Glass {
    double ior;
    double abbe;  // 0: BK7's Sellmeier fit
  };
  // In RGB mode the path draws its wavelength at the glass; in spectral mode it arrives
  // with eight and keeps its hero.
  for (const pb::SpectralSampling mode : {pb::SPECTRAL_SAMPLING_AUTO, pb::SPECTRAL_SAMPLING_ALWAYS})
  for (const Glass g : {Glass{1.0001, 90}, Glass{1.5168, 0}, Glass{2.4, 20}, Glass{4, 20}}) {
    pb::Scene s = MakeScene(16, 16, {0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 30, 64, 7);
    s.mutable_sampling()->set_spectral(mode);
    Set(s.mutable_environment()->mutable_radiance(), Rgb(1));
    AddMaterial(s, "glass", [&](pb::Material* m) {
      m->mutable_dielectric()->set_ior(g.ior);
      if (g.abbe > 0) {
        m->mutable_dielectric()->mutable_dispersion()->set_abbe_number(g.abbe);
      } else {
        m->mutable_dielectric()->mutable_dispersion()->set_glass(pb::GLASS_BK7);
      }
    });
    AddSphere(s, "glass", {0, 0, 0}, 1);
    const Image image = RenderTile(Scene::Build(s, NoBlobs()), nullptr, {0, 0, 16, 16});
    double sum[3] = {0, 0, 0};
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x)
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(std::isfinite(image.pixel(x, y)[c])) << "ior " << g.ior << " pixel " << x << ", " << y;
          sum[c] += image.pixel(x, y)[c];
        }
    const std::string name = pb::SpectralSampling_Name(mode);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(sum[c] / 256, 1.0, 0.01) << name << ", ior " << g.ior << ", Abbe " << g.abbe << ", channel " << c;
    std::printf("dispersive furnace, %s, ior %g, Abbe %g: (%.4f, %.4f, %.4f)\n", name.c_str(), g.ior, g.abbe,
                sum[0] / 256, sum[1] / 256, sum[2] / 256);
  }
}

// Issue 18's spectral white furnace: a white Lambertian sphere and a glass one in a white
// environment, every camera path at eight wavelengths (Sampling.spectral ALWAYS). A convex
// white sphere reflects exactly the radiance 1 that reaches it, glass loses nothing, so
// every channel stays 1: the uplift of white is flat and the matching functions add up to
// white.
TEST(SpecularPaths, SpectralWhiteFurnaceStaysWhiteInEveryChannel) {
  for (const bool glass : {false, true}) {
    pb::Scene s = MakeScene(16, 16, {0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 30, 64, 7);
    s.mutable_sampling()->set_spectral(pb::SPECTRAL_SAMPLING_ALWAYS);
    Set(s.mutable_environment()->mutable_radiance(), Rgb(1));
    if (glass) {
      AddMaterial(s, "sphere", [](pb::Material* m) { m->mutable_dielectric()->set_ior(1.5); });
    } else {
      AddLambert(s, "sphere", Rgb(1));
    }
    AddSphere(s, "sphere", {0, 0, 0}, 1);
    const Scene scene = Scene::Build(s, NoBlobs());
    ASSERT_TRUE(scene.data().spectral_always);
    const Image image = RenderTile(scene, nullptr, {0, 0, 16, 16});
    double sum[3] = {0, 0, 0};
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x)
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(std::isfinite(image.pixel(x, y)[c])) << "pixel " << x << ", " << y;
          sum[c] += image.pixel(x, y)[c];
        }
    const char* what = glass ? "glass" : "white Lambertian";
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c] / 256, 1.0, 0.01) << what << ", channel " << c;
    std::printf("spectral furnace, %s sphere: (%.4f, %.4f, %.4f)\n", what, sum[0] / 256, sum[1] / 256, sum[2] / 256);
  }
}

TEST(SpecularPaths, SplitGlassGivesTheSameBytesWhateverTheTiles) {
  // A split path's branches draw from its sample's dimensions: tiles still stitch into the
  // whole image's bytes.
  pb::Scene s = MakeScene(16, 12, {0, 1, 5}, {0, 0.5, 0}, {0, 1, 0}, 40, 2, 9);
  AddLambert(s, "floor", Rgb(0.6f));
  AddEmissive(s, "lamp", Rgb(4));
  AddMaterial(s, "glass", [](pb::Material* m) { m->mutable_dielectric()->set_ior(1.5); });
  AddQuad(s, "floor", {-5, 0, -5}, {0, 0, 10}, {10, 0, 0});  // front +y
  AddQuad(s, "lamp", {-1, 3, -1}, {2, 0, 0}, {0, 0, 2});     // faces down
  AddSphere(s, "glass", {0, 0.6, 0}, 0.6);
  const Scene scene = Scene::Build(s, NoBlobs());
  ASSERT_TRUE(scene.data().split_specular);
  const Image whole = RenderTile(scene, nullptr, {0, 0, 16, 12});
  for (const PixelRect& tile : {PixelRect{0, 0, 9, 5}, PixelRect{9, 0, 7, 5}, PixelRect{0, 5, 16, 7}}) {
    const Image part = RenderTile(scene, nullptr, tile);
    ExpectSamePixels(whole, part);
  }
}

TEST(SpecularPaths, GoldReflectsItsFresnelColour) {
  pb::Scene s = Narrow(4);
  AddEmissive(s, "lamp", Rgb(1));
  AddMaterial(s, "gold", [](pb::Material* m) {
    Set(m->mutable_conductor()->mutable_eta(), Rgb(0.143f, 0.374f, 1.442f));
    Set(m->mutable_conductor()->mutable_k(), Rgb(3.983f, 2.385f, 1.603f));
  });
  AddQuad(s, "gold", {-1, -1, 4}, {0, 2, 0}, {2, 0, 2});
  AddQuad(s, "lamp", {10, -5, 0}, {0, 0, 10}, {0, 10, 0});
  const Rgb L = CentrePixel(s);
  const float c = std::cos(static_cast<float>(kPiD / 4));
  EXPECT_NEAR(L.r, FresnelConductor(c, 0.143f, 3.983f), 1e-4);
  EXPECT_NEAR(L.b, FresnelConductor(c, 1.442f, 1.603f), 1e-4);
}

// A Lambert floor at z = 0 seen at the origin from above.
pb::Scene FloorFromAbove() {
  pb::Scene s = MakeScene(1, 1, {0.5, 0, 10}, {0, 0, 0}, {0, 0, 1}, 0.02, 4, 5);
  AddLambert(s, "floor", Rgb(0.5f));
  AddQuad(s, "floor", {-100, -100, 0}, {200, 0, 0}, {0, 200, 0});
  return s;
}

TEST(SpecularPaths, PointAndSunLightDirectLightingMatchClosedForms) {
  {
    pb::Scene s = FloorFromAbove();
    auto* p = s.add_lights()->mutable_point();
    Set(p->mutable_position(), {3, 0, 4});
    Set(p->mutable_intensity(), Rgb(50));
    // rho / pi * I cos / d^2 with d = 5, cos = 4/5.
    EXPECT_NEAR(CentrePixel(s).g, 0.5 / kPiD * 50 * 0.8 / 25, 1e-3);
  }
  {
    pb::Scene s = FloorFromAbove();
    auto* sun = s.add_lights()->mutable_sun();
    Set(sun->mutable_direction(), {-1, 0, -1});
    Set(sun->mutable_irradiance(), Rgb(2));
    EXPECT_NEAR(CentrePixel(s).g, 0.5 / kPiD * 2 * std::sqrt(0.5), 1e-4);
    // A blocker between the floor point and the sun (not in the camera's way) casts a hard
    // shadow.
    AddQuad(s, "floor", {0.5, -1, 1}, {2, 0, 0}, {0, 2, 0});
    EXPECT_EQ(CentrePixel(s).g, 0.0f);
  }
}

}  // namespace
}  // namespace farm
