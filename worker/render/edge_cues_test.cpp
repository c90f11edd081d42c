// Edge anti-aliasing supersamples what more samples fix and not what they cannot: a sun's
// hard shadow across a textured floor is an edge; a fine checker texture on the floor, which
// the texture lookups already filter over each pixel, is not (nor is it under the old test,
// a Sobel of the beauty's log-luminance, which marks most of it: checked here so that the
// scene is one where the difference shows), nor a normal map's bumps of the same size.

// Before OIIO's headers (texture/texture_system.cpp says why).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "render/tile_renderer.h"
#include "scene/test_scenes.h"
#include "texture/test_images.h"
#include "texture/texture_system.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr int kSize = 32;
const int kEdgeChannel = RenderChannelIndex("edge.Y");
constexpr int kTexels = 256;
constexpr int kCell = 4;  // texels a checker cell: about 2.8 pixels in the view
// The bumps' cells tilt the normal by this much about the texture's v axis, one way and the
// other: neighbouring pixels' normals differ by twice it, far over the crease angle.
constexpr double kBumpDegrees = 40;

// A 20 x 20 floor at y = 0 under the texture's unit square, seen straight down (the view
// about 3.6 units across, 8.8 pixels a unit, 12.8 texels a unit), under a delta sun straight down; a
// blocker high above the camera, out of its view, shades the floor where x < 0, so the
// shadow's edge runs down the middle of the image. Direct light only; 4 samples a pixel, 16 at edges.
// With bumps, the floor has the normal map "bumps" too.
pb::Scene CheckerFloorScene(bool bumps) {
  pb::Scene s = MakeScene(kSize, kSize, {0, 5, 0}, {0, 0, 0}, {0, 0, 1}, 40);
  s.mutable_antialiasing()->set_mode(pb::ANTIALIASING_MODE_EDGES);
  s.mutable_antialiasing()->set_edge_samples(16);
  s.mutable_indirect()->set_mode(pb::INDIRECT_MODE_PHOTON_MAP);
  pb::Material* m = s.add_materials();
  m->set_name("checker");
  pb::Principled* p = m->mutable_principled();
  p->set_roughness(1);
  p->mutable_base_color_texture()->set_texture("checker");
  for (const char* name : {"checker", "bumps"}) {
    pb::Texture* t = s.add_textures();
    t->set_name(name);
    t->set_path(std::string(name) + ".png");
    t->set_digest(FakeDigest(name));
  }
  if (bumps) p->mutable_normal_texture()->set_texture("bumps");
  AddLambert(s, "blocker", Rgb(0.5f));
  AddQuad(s, "checker", {-10, 0, 10}, {20, 0, 0}, {0, 0, -20});
  AddQuad(s, "blocker", {-20, 10, -20}, {0, 0, 40}, {20, 0, 0});
  pb::Light* sun = s.add_lights();
  Set(sun->mutable_sun()->mutable_direction(), {0, -1, 0});
  Set(sun->mutable_sun()->mutable_irradiance(), Rgb(3));
  return s;
}

class CheckerFloor : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshTestDir("edge_cues_test", ::testing::UnitTest::GetInstance()->current_test_info()->name());
    textures_ = std::make_unique<TextureSystem>(TextureSystemOptions{16, dir_ / "prepared"});
    WriteTestImage(dir_ / "checker", "png", kTexels, kTexels, 3, OIIO::TypeDesc::UINT8, [](int x, int y, int) {
      return (x / kCell + y / kCell) % 2 == 0 ? 0.9f : 0.1f;
    });
    // Tangent-space normals (+-sin, 0, cos) stored as (n + 1) / 2.
    const double tilt = kBumpDegrees * std::acos(-1.0) / 180;
    WriteTestImage(dir_ / "bumps", "png", kTexels, kTexels, 3, OIIO::TypeDesc::UINT8, [tilt](int x, int y, int c) {
      const double side = (x / kCell + y / kCell) % 2 == 0 ? 1 : -1;
      const double n[3] = {side * std::sin(tilt), 0, std::cos(tilt)};
      return float((n[c] + 1) / 2);
    });
  }
  void TearDown() override {
    textures_.reset();
    std::filesystem::remove_all(dir_);
  }

  Image Render(double edge_threshold, bool bumps = false) const {
    SceneOptions options;
    options.textures = textures_.get();
    options.load_file = [this](const std::string& digest) {
      return dir_ / (digest == FakeDigest("bumps") ? "bumps" : "checker");
    };
    pb::Scene s = CheckerFloorScene(bumps);
    s.mutable_antialiasing()->set_edge_threshold(edge_threshold);
    return RenderTile(Scene::Build(s, NoBlobs(), options), nullptr, {0, 0, kSize, kSize});
  }

  std::filesystem::path dir_;
  std::unique_ptr<TextureSystem> textures_;
};

// The sun's shadow edge, which falls between columns 15 and 16 (x = 0 is the image's
// centre; the shadow is on the image's right), is supersampled on every row; no pixel two
// or more columns from it is, texture or not.
void ExpectEdgesAtTheShadowAlone(const Image& aa) {
  for (int y = 0; y < kSize; ++y) {
    int near_shadow = 0;
    for (int x = 0; x < kSize; ++x) {
      const bool edge = aa.pixel(x, y)[kEdgeChannel] == 1.0f;
      if (x == 15 || x == 16) {
        near_shadow += edge;
      } else if (x < 14 || x > 17) {
        EXPECT_FALSE(edge) << "pixel " << x << ", " << y;
      }
    }
    EXPECT_GE(near_shadow, 1) << "row " << y;
  }
}

// The old test's Sobel of the beauty marks most of the lit half.
TEST_F(CheckerFloor, ShadowEdgesAreSupersampledAndTextureDetailIsNot) {
  const Image aa = Render(0);  // the default threshold, 0.1
  ExpectEdgesAtTheShadowAlone(aa);
  const Image base = Render(1e9);
  int lit = 0, old_edges = 0;
  const auto log_luminance = [&](int x, int y) {
    const float* q = base.pixel(std::clamp(x, 0, kSize - 1), std::clamp(y, 0, kSize - 1));
    return std::log(0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2] + 1.0 / 256);
  };
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < 14; ++x) {  // the lit part, away from the shadow
      ++lit;
      double gx = 0, gy = 0;
      for (int d = -1; d <= 1; ++d) {
        const double w = d == 0 ? 2 : 1;
        gx += w * (log_luminance(x + 1, y + d) - log_luminance(x - 1, y + d));
        gy += w * (log_luminance(x + d, y + 1) - log_luminance(x + d, y - 1));
      }
      old_edges += std::hypot(gx, gy) / 8 > 0.1;
    }
  EXPECT_GT(old_edges, lit / 2) << old_edges << " of " << lit;
  std::printf("lit pixels away from the shadow the old test marks: %d of %d\n", old_edges, lit);
}

// A normal map's bumps turn the shading normal from pixel to pixel by twice kBumpDegrees,
// but the crease cue reads the surface's own normal: still only the shadow is an edge. The
// bumps do change the shading (so the map is read), which the beauty shows.
TEST_F(CheckerFloor, NormalMapBumpsAreNoEdges) {
  const Image bumped = Render(0, true);
  ExpectEdgesAtTheShadowAlone(bumped);
  const Image flat = Render(0);
  int changed = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < 14; ++x) changed += std::abs(bumped.pixel(x, y)[0] - flat.pixel(x, y)[0]) > 0.01f;
  EXPECT_GT(changed, 14 * kSize / 2) << changed;
}

}  // namespace
}  // namespace farm
