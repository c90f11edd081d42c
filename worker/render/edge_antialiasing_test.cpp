// Edge anti-aliasing in RenderTile, checked against independent ground truth: the base pass
// and the fully supersampled render of the same scene, and the edge cues written out here.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "image/reference_exr.h"
#include "sampling/pixel_sampler.h"
#include "render/integrator.h"
#include "render/thin_bars_scene.h"
#include "render/tile_renderer.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr int kW = 64, kH = 48;
constexpr int kEdgeChannel = 20;

Scene Bars(pb::AntialiasingMode mode, uint32_t edges = 12, double threshold = 0) {
  pb::Scene s = ThinBarsScene(kW, kH, mode, edges);
  s.mutable_antialiasing()->set_edge_threshold(threshold);
  return Scene::Build(s, NoBlobs());
}

bool SamePixel(const Image& a, const Image& b, int x, int y) {
  return std::memcmp(a.pixel(x, y), b.pixel(x, y), a.channel_count() * sizeof(float)) == 0;
}

// Every pixel of the tiles equals, bit for bit, the whole-image render: all channels, the
// edge mask included.
void ExpectTilesStitch(const Scene& scene, const RoundSettings& round, int tile) {
  const Image whole = RenderTile(scene, nullptr, {0, 0, kW, kH}, round);
  for (int ty = 0; ty < kH; ty += tile)
    for (int tx = 0; tx < kW; tx += tile) {
      const PixelRect r{tx, ty, std::min(tile, kW - tx), std::min(tile, kH - ty)};
      const Image part = RenderTile(scene, nullptr, r, round);
      for (int y = r.y; y < r.y_end(); ++y)
        for (int x = r.x; x < r.x_end(); ++x)
          ASSERT_TRUE(SamePixel(whole, part, x, y)) << "pixel " << x << ", " << y << " of tile "
                                                    << tx << ", " << ty;
    }
}

TEST(EdgeAntialiasing, TilesStitchBitForBitIntoTheWholeImage) {
  const Scene scene = Bars(pb::ANTIALIASING_MODE_EDGES);
  ExpectTilesStitch(scene, {}, 16);
  ExpectTilesStitch(scene, {}, 7);  // tile borders cut edges at every offset
  ExpectTilesStitch(scene, {.radius_scale = 0.5, .first_sample = 3}, 13);
}

// The base pass alone, drawn here as the tile renderer draws it: the bars take 1 sample a
// pixel, sample 0 of the sampler whose permutation domain is the 12 samples of an edge
// pixel, keyed by the scene seed in round 1.
std::vector<SampleResult> BasePass() {
  const Scene scene = Bars(pb::ANTIALIASING_MODE_EDGES);
  const SceneData& data = scene.data();
  const PhotonMappingIntegrator integrator(data, PhotonMaps{});
  PixelSampler sampler(12, data.seed);
  std::vector<PhotonNeighbour> scratch;
  std::vector<SampleResult> base;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      sampler.StartPixelSample(uint64_t(y) * kW + x, 0);
      const Vec2 u = sampler.Get2D();
      base.push_back(integrator.Li(data.camera.GenerateRay({x + u.x, y + u.y}), sampler, scratch));
    }
  return base;
}

// In the bars scene (a flat floor, flat bars above it, one sample per pixel) the surface
// cues reduce to a change of surface id in the 3x3 neighbourhood (the bars are flat and
// face up, and each is a surface of its own, so no crease or depth step adds to them), and
// the light cue is a Sobel of the direct irradiance.
TEST(EdgeAntialiasing, EdgePixelsAreThoseWhereTheBasePassChangesSurfaceOrDirectIrradiance) {
  const std::vector<SampleResult> base = BasePass();
  const Image aa = RenderTile(Bars(pb::ANTIALIASING_MODE_EDGES), nullptr, {0, 0, kW, kH});
  const auto at = [&](int x, int y) -> const SampleResult& {
    return base[std::size_t(std::clamp(y, 0, kH - 1)) * kW + std::clamp(x, 0, kW - 1)];
  };
  // An independent Sobel of log(Rec. 709 luminance of the direct irradiance + 1/256),
  // clamped at the image border.
  const auto f = [&](int x, int y) {
    const Rgb& e = at(x, y).direct_irradiance;
    return std::log(0.2126 * e.r + 0.7152 * e.g + 0.0722 * e.b + 1.0 / 256);
  };
  const auto surface_changes = [&](int x, int y) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (at(x + dx, y + dy).surface != at(x, y).surface) return true;
    return false;
  };
  int edges = 0, mismatches = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      double gx = 0, gy = 0;
      for (int d = -1; d <= 1; ++d) {
        const double w = d == 0 ? 2 : 1;
        gx += w * (f(x + 1, y + d) - f(x - 1, y + d));
        gy += w * (f(x + d, y + 1) - f(x + d, y - 1));
      }
      const double gradient = std::hypot(gx, gy) / 8;
      if (std::abs(gradient - 0.1) < 1e-9 && !surface_changes(x, y)) continue;  // too close to call
      const bool edge = gradient > 0.1 || surface_changes(x, y);
      edges += edge;
      if ((aa.pixel(x, y)[kEdgeChannel] == 1.0f) != edge && mismatches++ < 5)
        ADD_FAILURE() << "pixel " << x << ", " << y << ": gradient " << gradient;
    }
  EXPECT_EQ(mismatches, 0);
  // The bars cover a good part of the view, but edges are a minority of pixels.
  EXPECT_GT(edges, kW * kH / 20);
  EXPECT_LT(edges, kW * kH / 2);
}

TEST(EdgeAntialiasing, EdgePixelsEqualFullSupersamplingAndOthersTheBasePass) {
  const std::vector<SampleResult> base = BasePass();
  const Image full = RenderTile(Bars(pb::ANTIALIASING_MODE_FULL), nullptr, {0, 0, kW, kH});
  const Image aa = RenderTile(Bars(pb::ANTIALIASING_MODE_EDGES), nullptr, {0, 0, kW, kH});
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const bool edge = aa.pixel(x, y)[kEdgeChannel] == 1.0f;
      EXPECT_EQ(full.pixel(x, y)[kEdgeChannel], 1.0f);
      if (edge) {
        ASSERT_TRUE(SamePixel(aa, full, x, y)) << "pixel " << x << ", " << y << " (edge)";
        continue;
      }
      // One sample: the pixel is that sample's beauty (and its alpha).
      const Rgb& r = base[std::size_t(y) * kW + x].radiance;
      const float* p = aa.pixel(x, y);
      ASSERT_TRUE(p[0] == r.r && p[1] == r.g && p[2] == r.b) << "pixel " << x << ", " << y;
    }
}

TEST(EdgeAntialiasing, NoneModeSupersamplesNothing) {
  const Image none = RenderTile(Bars(pb::ANTIALIASING_MODE_NONE), nullptr, {0, 0, kW, kH});
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) ASSERT_EQ(none.pixel(x, y)[kEdgeChannel], 0.0f);
}

double BeautyRmse(const Image& a, const Image& b) { return LayerRmse(a, b, "").value(); }

TEST(EdgeAntialiasing, EdgeSupersamplingRemovesMostOfTheAliasing) {
  const Image reference =
      RenderTile(Bars(pb::ANTIALIASING_MODE_FULL, 64), nullptr, {0, 0, kW, kH});
  const double aa = BeautyRmse(
      RenderTile(Bars(pb::ANTIALIASING_MODE_EDGES), nullptr, {0, 0, kW, kH}), reference);
  const double one = BeautyRmse(
      RenderTile(Bars(pb::ANTIALIASING_MODE_NONE), nullptr, {0, 0, kW, kH}), reference);
  EXPECT_LT(aa, one / 2) << "edges " << aa << ", 1 spp " << one;
}

TEST(EdgeAntialiasing, RoundsDrawFreshSamplesAndRound1IsTheDefault) {
  const Scene scene = Bars(pb::ANTIALIASING_MODE_FULL);
  const Image first = RenderTile(scene, nullptr, {0, 0, kW, kH});
  EXPECT_EQ(first, RenderTile(scene, nullptr, {0, 0, kW, kH}, {.first_sample = 0}));
  const Image second = RenderTile(scene, nullptr, {0, 0, kW, kH}, {.first_sample = 12});
  const Image second_again = RenderTile(scene, nullptr, {0, 0, kW, kH}, {.first_sample = 12});
  EXPECT_EQ(second, second_again);
  // On an edge the samples land elsewhere, so nearly every edge pixel changes value.
  int edge_pixels = 0, changed = 0;
  const Image aa = RenderTile(Bars(pb::ANTIALIASING_MODE_EDGES), nullptr, {0, 0, kW, kH});
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (aa.pixel(x, y)[kEdgeChannel] != 1.0f) continue;
      ++edge_pixels;
      changed += first.pixel(x, y)[0] != second.pixel(x, y)[0];
    }
  EXPECT_GT(changed, edge_pixels * 8 / 10) << changed << " of " << edge_pixels;
}

TEST(EdgeAntialiasing, RefusesANonPositiveRadiusScale) {
  const Scene scene = Bars(pb::ANTIALIASING_MODE_EDGES);
  EXPECT_THROW(RenderTile(scene, nullptr, {0, 0, 8, 8}, {.radius_scale = 0}),
               std::invalid_argument);
  EXPECT_THROW(RenderTile(scene, nullptr, {0, 0, 8, 8}, {.radius_scale = NAN}),
               std::invalid_argument);
}

}  // namespace
}  // namespace farm
