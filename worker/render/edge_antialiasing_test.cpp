// Edge anti-aliasing in RenderTile, checked against independent ground truth: the base pass
// and the fully supersampled render of the same scene, and a Sobel filter written out here.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "image/reference_exr.h"
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

// The base pass alone: EDGES mode with a threshold nothing reaches, so the sampler and its
// permutation domain are those of the real render.
Image BasePass() {
  return RenderTile(Bars(pb::ANTIALIASING_MODE_EDGES, 12, 1e9), nullptr, {0, 0, kW, kH});
}

TEST(EdgeAntialiasing, EdgePixelsAreThoseASobelOfTheBasePassMarks) {
  const Image base = BasePass();
  const Image aa = RenderTile(Bars(pb::ANTIALIASING_MODE_EDGES), nullptr, {0, 0, kW, kH});
  // An independent Sobel of log(Rec. 709 luminance + 1/256), clamped at the image border.
  const auto f = [&](int x, int y) {
    const float* p = base.pixel(std::clamp(x, 0, kW - 1), std::clamp(y, 0, kH - 1));
    return std::log(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2] + 1.0 / 256);
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
      if (std::abs(gradient - 0.1) < 1e-9) continue;  // too close to call
      const bool edge = gradient > 0.1;
      edges += edge;
      EXPECT_EQ(base.pixel(x, y)[kEdgeChannel], 0.0f);
      if ((aa.pixel(x, y)[kEdgeChannel] == 1.0f) != edge && mismatches++ < 5)
        ADD_FAILURE() << "pixel " << x << ", " << y << ": gradient " << gradient;
    }
  EXPECT_EQ(mismatches, 0);
  // The bars cover a good part of the view, but edges are a minority of pixels.
  EXPECT_GT(edges, kW * kH / 20);
  EXPECT_LT(edges, kW * kH / 2);
}

TEST(EdgeAntialiasing, EdgePixelsEqualFullSupersamplingAndOthersTheBasePass) {
  const Image base = BasePass();
  const Image full = RenderTile(Bars(pb::ANTIALIASING_MODE_FULL), nullptr, {0, 0, kW, kH});
  const Image aa = RenderTile(Bars(pb::ANTIALIASING_MODE_EDGES), nullptr, {0, 0, kW, kH});
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const bool edge = aa.pixel(x, y)[kEdgeChannel] == 1.0f;
      ASSERT_TRUE(SamePixel(aa, edge ? full : base, x, y) ||
                  // the base pass's edge mask is 0, so compare the other channels only
                  (!edge && std::memcmp(aa.pixel(x, y), base.pixel(x, y),
                                        kEdgeChannel * sizeof(float)) == 0))
          << "pixel " << x << ", " << y << (edge ? " (edge)" : "");
      EXPECT_EQ(full.pixel(x, y)[kEdgeChannel], 1.0f);
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
