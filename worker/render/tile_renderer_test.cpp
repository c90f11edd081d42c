#include "render/tile_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "render/test_images.h"
#include "scene/scene_data.h"
#include "scene/test_scenes.h"
#include "util/test_progress.h"

namespace farm {
namespace {

using namespace farm::testing;

// Where the layers sit among RenderChannels().
const int kDirect = RenderChannelIndex("direct.R"), kIndirect = RenderChannelIndex("indirect.R"),
          kCaustic = RenderChannelIndex("caustic.R"), kVolume = RenderChannelIndex("volume.R"),
          kBias = RenderChannelIndex("bias.R"),
          kAlbedo = RenderChannelIndex("albedo.R"), kNormal = RenderChannelIndex("normal.X"),
          kDepth = RenderChannelIndex("depth.Z"), kEdge = RenderChannelIndex("edge.Y"),
          kSamples = RenderChannelIndex("samples.Y");

// A small Cornell-like box: floor, back wall, a red and a green wall, a Lambert sphere, an
// OBJ block and a quad light under the ceiling, seen from the front.
pb::Scene BoxScene(uint64_t seed, int width = 24, int height = 16) {
  pb::Scene s = MakeScene(width, height, {278, 273, -800}, {278, 273, 0}, {0, 1, 0}, 39.3, 4, seed);
  AddLambert(s, "white", Rgb(0.75f));
  AddLambert(s, "red", Rgb(0.6f, 0.05f, 0.05f));
  AddLambert(s, "green", Rgb(0.1f, 0.5f, 0.1f));
  AddEmissive(s, "lamp", Rgb(17, 12, 4));
  AddQuad(s, "white", {0, 0, 0}, {0, 0, 559}, {556, 0, 0});         // floor, front +y
  AddQuad(s, "white", {0, 0, 559}, {0, 548, 0}, {556, 0, 0});       // back wall
  AddQuad(s, "red", {556, 0, 0}, {0, 0, 559}, {0, 548, 0});         // x = 556: left in image
  AddQuad(s, "green", {0, 0, 0}, {0, 548, 0}, {0, 0, 559});         // x = 0: right
  AddQuad(s, "lamp", {213, 547, 227}, {130, 0, 0}, {0, 0, 105});   // faces down
  AddSphere(s, "white", {380, 100, 300}, 100);
  AddMeshFile(s, "white", FakeDigest("block"));
  return s;
}

const std::string kBlockObj =
    "v 100 0 200\nv 200 0 200\nv 200 150 200\nv 100 150 200\n"
    "f 1 2 3 4\n";

Scene BuildBox(uint64_t seed, int width = 24, int height = 16) {
  return Scene::Build(BoxScene(seed, width, height), MapLoader({{FakeDigest("block"), kBlockObj}}));
}

TEST(RenderTile, FourTilesEqualTheWholeImageBitForBit) {
  const Scene scene = BuildBox(42);
  // Edge anti-aliasing is on by default: the tiles' aprons must not change any pixel.
  ASSERT_EQ(scene.data().antialiasing.mode, AntialiasingMode::kEdges);
  for (const RoundSettings& round : {RoundSettings{}, RoundSettings{.first_sample = 4}}) {
    const Image whole = RenderTile(scene, nullptr, {0, 0, 24, 16}, round);
    for (const PixelRect& tile : {PixelRect{0, 0, 13, 7}, PixelRect{13, 0, 11, 7},
                                  PixelRect{0, 7, 13, 9}, PixelRect{13, 7, 11, 9}}) {
      const Image part = RenderTile(scene, nullptr, tile, round);
      EXPECT_EQ(part.rect(), tile);
      EXPECT_EQ(part.channels(), RenderChannels());
      ExpectSamePixels(whole, part);
    }
  }
}

// Under adaptive sampling each pixel draws what the map gives it (samples.Y says so, and no
// pixel is flagged an edge), its value is the mean of samples 0.. of the round's set
// whatever the map gives its neighbours, and tiles stitch into the whole image's bytes.
TEST(RenderTile, AdaptiveSamplingDrawsTheMapsSamplesAndTilesStillStitch) {
  const Scene scene = BuildBox(42);
  std::vector<std::uint32_t> map(24 * 16), other(24 * 16);
  for (std::size_t p = 0; p < map.size(); ++p) {
    map[p] = std::uint32_t(1 + p * 7 % 12);
    other[p] = p == 5 * 24 + 9 ? map[p] : std::uint32_t(1 + p % 5);  // only (9, 5) the same
  }
  const RoundSettings round{.first_sample = 8, .samples = map, .max_samples = 64};
  const Image whole = RenderTile(scene, nullptr, {0, 0, 24, 16}, round);
  const int samples = int(RenderChannels().size()) - 1, edge = samples - 1;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x) {
      ASSERT_EQ(whole.pixel(x, y)[samples], float(map[std::size_t(y) * 24 + std::size_t(x)])) << x << ", " << y;
      ASSERT_EQ(whole.pixel(x, y)[edge], 0.0f);
    }
  for (const PixelRect& tile : {PixelRect{0, 0, 13, 7}, PixelRect{13, 7, 11, 9}}) {
    ExpectSamePixels(whole, RenderTile(scene, nullptr, tile, round));
  }
  const Image moved = RenderTile(scene, nullptr, {9, 5, 1, 1}, {.first_sample = 8, .samples = other, .max_samples = 64});
  ExpectSamePixels(whole, moved);
  EXPECT_THROW(RenderTile(scene, nullptr, {0, 0, 4, 4}, {.samples = std::span(map).first(10), .max_samples = 64}),
               std::invalid_argument);
  EXPECT_THROW(RenderTile(scene, nullptr, {0, 0, 4, 4}, {.samples = map, .max_samples = 8}), std::invalid_argument);
}

void SetFilter(pb::Scene& s, PixelFilterKind kind) {
  pb::PixelFilter* f = s.mutable_film()->mutable_filter();
  switch (kind) {
    case PixelFilterKind::kBox: f->mutable_box()->set_radius(1); break;
    case PixelFilterKind::kTent: f->mutable_tent(); break;
    case PixelFilterKind::kGaussian: f->mutable_gaussian(); break;
    case PixelFilterKind::kMitchell: f->mutable_mitchell(); break;
  }
}

// Wider filters read the samples of a margin about the tile, and with edge anti-aliasing
// supersample the margin's edge pixels: the tiles still stitch into the whole image's
// bytes, in every sampling mode, in later rounds too.
TEST(RenderTile, FilteredTilesEqualTheWholeImageBitForBit) {
  for (const auto kind : {PixelFilterKind::kBox, PixelFilterKind::kTent, PixelFilterKind::kGaussian,
                          PixelFilterKind::kMitchell})
    for (const auto mode : {pb::ANTIALIASING_MODE_EDGES, pb::ANTIALIASING_MODE_NONE, pb::ANTIALIASING_MODE_FULL}) {
      pb::Scene s = BoxScene(42);
      SetFilter(s, kind);
      s.mutable_antialiasing()->set_mode(mode);
      s.mutable_antialiasing()->set_edge_samples(6);
      const Scene scene = Scene::Build(s, MapLoader({{FakeDigest("block"), kBlockObj}}));
      SCOPED_TRACE(scene.data().filter.ToString() + " mode " + std::to_string(mode));
      for (const RoundSettings& round : {RoundSettings{}, RoundSettings{.first_sample = 4}}) {
        const Image whole = RenderTile(scene, nullptr, {0, 0, 24, 16}, round);
        for (const PixelRect& tile : {PixelRect{0, 0, 13, 7}, PixelRect{13, 0, 11, 7}, PixelRect{0, 7, 13, 9},
                                      PixelRect{13, 7, 11, 9}, PixelRect{5, 3, 1, 1}})
          ExpectSamePixels(whole, RenderTile(scene, nullptr, tile, round));
      }
    }
}

// The filter weighs the light layers only: each differs from the box-filtered image's, and
// normal, depth and the edge mask stay those of the pixel's own samples.
TEST(RenderTile, FiltersWeighTheLightLayersAndKeepTheGeometryLayers) {
  pb::Scene s = BoxScene(7);
  s.mutable_antialiasing()->set_mode(pb::ANTIALIASING_MODE_NONE);
  const Image box = RenderTile(Scene::Build(s, MapLoader({{FakeDigest("block"), kBlockObj}})), nullptr, {0, 0, 24, 16});
  SetFilter(s, PixelFilterKind::kGaussian);
  const Image gaussian =
      RenderTile(Scene::Build(s, MapLoader({{FakeDigest("block"), kBlockObj}})), nullptr, {0, 0, 24, 16});
  int differing_beauty = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x) {
      differing_beauty += box.pixel(x, y)[0] != gaussian.pixel(x, y)[0];
      for (int c = kNormal; c < kSamples; ++c) ASSERT_EQ(box.pixel(x, y)[c], gaussian.pixel(x, y)[c]) << x << ", " << y << " c " << c;
    }
  EXPECT_GT(differing_beauty, 24 * 16 / 2);
}

// A filter's margin is rendered too: a one-pass tile adds its samples and the margin's.
TEST(RenderTile, ProgressCountsTheFilterMarginsSamples) {
  pb::Scene s = BoxScene(2);
  s.mutable_antialiasing()->set_mode(pb::ANTIALIASING_MODE_NONE);
  SetFilter(s, PixelFilterKind::kMitchell);  // radius 2: a margin of 2
  const Scene scene = Scene::Build(s, MapLoader({{FakeDigest("block"), kBlockObj}}));
  ProgressCounter counter{0};
  RenderTile(scene, nullptr, {4, 1, 12, 8}, {}, {}, Progress(counter));
  EXPECT_EQ(counter.load(), 16u * 11u * 4u);  // x 2..17, y 0..10: clipped at the top
}

TEST(RenderTile, OrdinaryPixelsTakeOneSampleByDefault) {
  pb::Scene s = BoxScene(5);
  s.mutable_sampling()->clear_samples_per_pixel();
  s.mutable_antialiasing()->set_mode(pb::ANTIALIASING_MODE_NONE);
  const Scene scene = Scene::Build(s, MapLoader({{FakeDigest("block"), kBlockObj}}));
  EXPECT_EQ(scene.data().samples_per_pixel, 1u);
  const Image image = RenderTile(scene, nullptr, {0, 0, 24, 16});
  // With one sample a pixel is either fully covered or not at all, and its normal is unit.
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x) {
      const float* p = image.pixel(x, y);
      ASSERT_TRUE(p[3] == 0.0f || p[3] == 1.0f) << x << ", " << y;
      if (p[3] == 1.0f) {
        EXPECT_NEAR(Length(Vec3(p[kNormal], p[kNormal + 1], p[kNormal + 2])), 1.0f, 1e-5f);
      }
      EXPECT_EQ(p[kEdge], 0.0f);
    }
}

TEST(RenderTile, SameSeedSameBytesDifferentSeedDifferentBytes) {
  const Image a = RenderTile(BuildBox(42), nullptr, {0, 0, 24, 16});
  const Image b = RenderTile(BuildBox(42), nullptr, {0, 0, 24, 16});  // a separately built scene
  const Image c = RenderTile(BuildBox(43), nullptr, {0, 0, 24, 16});
  ASSERT_EQ(a.data().size(), b.data().size());
  EXPECT_EQ(std::memcmp(a.data().data(), b.data().data(), a.data().size_bytes()), 0);
  EXPECT_NE(std::memcmp(a.data().data(), c.data().data(), a.data().size_bytes()), 0);
}

TEST(RenderTile, ImageIsFiniteLitAndCovered) {
  const Image image = RenderTile(BuildBox(1), nullptr, {0, 0, 24, 16});
  double sum = 0;
  const std::span<const float> data = image.data();
  const std::size_t channels = RenderChannels().size();
  for (std::size_t i = 0; i < data.size(); ++i) {
    ASSERT_TRUE(std::isfinite(data[i]));
    const bool normal = int(i % channels) >= kNormal && int(i % channels) < kNormal + 3;  // normals may point any way
    if (!normal) {
      ASSERT_GE(data[i], 0);
    }
    sum += data[i];
  }
  EXPECT_GT(sum, 0);
  // The box fills the view's centre, where the back wall faces the camera.
  EXPECT_EQ(image.pixel(12, 8)[3], 1.0f);
  EXPECT_NEAR(image.pixel(12, 8)[kNormal + 2], -1.0f, 1e-3);
}

TEST(RenderTile, RedWallAtLargeXIsOnTheLeft) {
  const Image image = RenderTile(BuildBox(1, 16, 16), nullptr, {0, 0, 16, 16});
  // Middle row: the leftmost pixel sees the red wall (x = 556), the rightmost the green.
  const float* left = image.pixel(0, 8);
  const float* right = image.pixel(15, 8);
  EXPECT_GT(left[0], 2 * left[1]) << "left pixel is not red";
  EXPECT_GT(right[1], 2 * right[0]) << "right pixel is not green";
}

TEST(RenderTile, PassesAddUpToTheBeautyAndGeometryLayersAreFilled) {
  const Image image = RenderTile(BuildBox(3), nullptr, {0, 0, 24, 16});
  const std::vector<std::string> channels = RenderChannels();
  ASSERT_EQ(image.channels(), channels);
  ASSERT_EQ(channels.size(), 28u);
  EXPECT_EQ(channels[kDepth], "depth.Z");
  EXPECT_EQ(channels[kEdge], "edge.Y");
  EXPECT_EQ(channels[kSamples], "samples.Y");
  EXPECT_EQ(channels[kVolume], "volume.R");
  EXPECT_EQ(channels[kBias], "bias.R");
  int edges = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x) {
      const float* p = image.pixel(x, y);
      // No photon maps and no media: no indirect, caustic or volume light, and no photon
      // estimate to be biased; emitted light (the lamp) is the difference between beauty
      // and direct.
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(p[kBias + c], 0.0f);
        EXPECT_EQ(p[kIndirect + c], 0.0f);
        EXPECT_EQ(p[kCaustic + c], 0.0f);
        EXPECT_EQ(p[kVolume + c], 0.0f);
        EXPECT_LE(p[kDirect + c], p[c] * (1 + 1e-5f) + 1e-6f);
      }
      if (p[3] == 1) {
        const Vec3 n(p[kNormal], p[kNormal + 1], p[kNormal + 2]);
        // Averaged over the pixel: unit inside a face, shorter where faces meet.
        EXPECT_LE(Length(n), 1 + 1e-5f) << x << ", " << y;
        EXPECT_GT(Length(n), 0.0f) << x << ", " << y;
        EXPECT_GT(p[kDepth], 700);  // the box is at least 800 away, walls at an angle nearer
        EXPECT_GT(p[kAlbedo], 0);  // albedo of white, red or green walls
      }
      EXPECT_TRUE(p[kEdge] == 0.0f || p[kEdge] == 1.0f);
      edges += p[kEdge] == 1.0f;
    }
  // The sphere, the block and the wall corners make edges; at this size, and with the soft
  // shadows' noise at 4 samples, so does much of the view, but not all of it.
  EXPECT_GT(edges, 0);
  EXPECT_LT(edges, 24 * 16);
}

TEST(RenderTile, StopsWhenAsked) {
  const Scene scene = BuildBox(1);
  std::stop_source source;
  source.request_stop();
  const Image image = RenderTile(scene, nullptr, {0, 0, 24, 16}, {}, source.get_token());
  // Nothing rendered: every row checks the token first.
  for (float v : image.data()) EXPECT_EQ(v, 0.0f);
}

TEST(RenderTile, RefusesARectOutsideTheImage) {
  const Scene scene = BuildBox(1);
  EXPECT_THROW(RenderTile(scene, nullptr, {20, 0, 8, 8}), std::invalid_argument);
}

// Progress counts camera samples: a one-pass tile adds width x height x samples.
TEST(RenderTile, ProgressCountsEveryCameraSampleOfAOnePassTile) {
  for (const auto mode : {pb::ANTIALIASING_MODE_NONE, pb::ANTIALIASING_MODE_FULL}) {
    pb::Scene s = BoxScene(2);
    s.mutable_antialiasing()->set_mode(mode);
    s.mutable_antialiasing()->set_edge_samples(6);
    const Scene scene = Scene::Build(s, MapLoader({{FakeDigest("block"), kBlockObj}}));
    ProgressCounter counter{0};
    RenderTile(scene, nullptr, {4, 2, 12, 8}, {}, {}, Progress(counter));
    const std::uint64_t samples = mode == pb::ANTIALIASING_MODE_FULL ? 6 : 4;
    EXPECT_EQ(counter.load(), 12u * 8u * samples) << "mode " << mode;
  }
}

// With edge anti-aliasing: the base pass over the tile and its one-pixel apron, then the
// extra samples of each pixel the edge layer marks.
TEST(RenderTile, ProgressWithEdgesCountsTheApronBasePassAndEachEdgePixelsExtraSamples) {
  const Scene scene = BuildBox(3);  // EDGES by default: 4 samples, edge_samples at edges.
  const std::uint64_t edge_samples = scene.data().antialiasing.edge_samples;
  ProgressCounter counter{0};
  const PixelRect tile{4, 4, 8, 8};
  const Image image = RenderTile(scene, nullptr, tile, {}, {}, Progress(counter));
  std::uint64_t edges = 0;
  for (int y = tile.y; y < tile.y_end(); ++y)
    for (int x = tile.x; x < tile.x_end(); ++x) edges += image.pixel(x, y)[kEdge] == 1.0f;
  EXPECT_GT(edges, 0u);
  EXPECT_EQ(counter.load(), 10u * 10u * 4u + edges * (edge_samples - 4u));
}

// The counts agree with the image they describe: at one sample per pixel, every sample is
// counted, and the zero ones are exactly the covered pixels of non-black albedo (in this
// scene, of a diffuse surface: the lamp's albedo is black) that came out black (here,
// with direct light only, surfaces facing away from the lamp).
TEST(RenderTile, CountsEverySampleAndTheZeroOnes) {
  pb::Scene s = BoxScene(5, 48, 32);
  s.mutable_antialiasing()->set_mode(pb::ANTIALIASING_MODE_NONE);
  s.mutable_sampling()->set_samples_per_pixel(1);
  const Scene scene = Scene::Build(s, MapLoader({{FakeDigest("block"), kBlockObj}}));
  SampleCounts counts;
  const Image image = RenderTile(scene, nullptr, {0, 0, 48, 32}, {}, {}, {}, &counts);
  std::uint64_t black = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x) {
      const float* p = image.pixel(x, y);
      const bool albedo = p[kAlbedo] > 0 || p[kAlbedo + 1] > 0 || p[kAlbedo + 2] > 0;
      black += p[3] == 1 && albedo && p[0] == 0 && p[1] == 0 && p[2] == 0;
    }
  EXPECT_EQ(counts.samples, 48u * 32u);
  EXPECT_EQ(counts.nonfinite, 0u);
  EXPECT_GT(black, 0u) << "the scene has no unlit surface to count";
  EXPECT_EQ(counts.zero, black);
}

// What the heartbeat sees: read from another thread while the TBB threads render, the
// counter never goes back and ends at the tile's total.
TEST(RenderTile, ProgressReadFromAnotherThreadOnlyGrows) {
  pb::Scene s = BoxScene(4, 48, 32);
  s.mutable_antialiasing()->set_mode(pb::ANTIALIASING_MODE_NONE);
  const Scene scene = Scene::Build(s, MapLoader({{FakeDigest("block"), kBlockObj}}));
  ProgressCounter counter{0};
  const auto seen = ProgressSeenDuring(
      counter, [&](Progress progress) { RenderTile(scene, nullptr, {0, 0, 48, 32}, {}, {}, progress); });
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_EQ(counter.load(), 48u * 32u * 4u);
}

}  // namespace
}  // namespace farm
