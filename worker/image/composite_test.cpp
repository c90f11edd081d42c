#include "image/composite.h"

#include <OpenEXR/ImfTiledInputFile.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "image/exr_memory_stream.h"
#include "image/exr_util.h"
#include "image/image_error.h"
#include "image/srgb_preview.h"
#include "image/test_png.h"
#include "image/tile_exr.h"

namespace farm {
namespace {

// 70x45 with 32-pixel tiles: a 3x2 grid whose last column and row are partial.
constexpr ImageSize kSize{70, 45};
constexpr int kTile = 32;

float SourceValue(int x, int y, int c) { return 0.01f * x + 0.1f * y + 0.25f * c + 0.001f; }

std::vector<EncodedTile> MakeTiles(const std::vector<std::string>& channels) {
  std::vector<EncodedTile> tiles;
  for (int y = 0; y < kSize.height; y += kTile) {
    for (int x = 0; x < kSize.width; x += kTile) {
      const PixelRect rect{x, y, std::min(kTile, kSize.width - x), std::min(kTile, kSize.height - y)};
      Image tile(rect, channels);
      for (int py = rect.y; py < rect.y_end(); ++py) {
        for (int px = rect.x; px < rect.x_end(); ++px) {
          for (int c = 0; c < tile.channel_count(); ++c) tile.pixel(px, py)[c] = SourceValue(px, py, c);
        }
      }
      tiles.push_back({rect, EncodeTileExr(tile, kSize)});
    }
  }
  return tiles;
}

void ExpectSourcePixels(OIIO::ImageInput& in, int nchannels) {
  const OIIO::ImageSpec& spec = in.spec();
  EXPECT_EQ(spec.width, kSize.width);
  EXPECT_EQ(spec.height, kSize.height);
  EXPECT_EQ(spec.tile_width, kTile);
  EXPECT_EQ(spec.tile_height, kTile);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
  ASSERT_EQ(spec.nchannels, nchannels);
  EXPECT_EQ(spec.channelnames[0], "R");
  EXPECT_EQ(spec.channelnames[1], "G");
  EXPECT_EQ(spec.channelnames[2], "B");
  EXPECT_EQ(spec.channelnames[3], "A");
  EXPECT_EQ(spec.alpha_channel, 3);
  std::vector<float> pixels(static_cast<std::size_t>(kSize.width) * kSize.height * nchannels);
  ASSERT_TRUE(in.read_image(0, 0, 0, nchannels, OIIO::TypeDesc::FLOAT, pixels.data()))
      << in.geterror();
  int mismatches = 0;
  for (int y = 0; y < kSize.height; ++y) {
    for (int x = 0; x < kSize.width; ++x) {
      for (int c = 0; c < 4; ++c) {
        const float got = pixels[(static_cast<std::size_t>(y) * kSize.width + x) * nchannels + c];
        if (got != SourceValue(x, y, c) && mismatches++ < 5) {
          ADD_FAILURE() << "pixel (" << x << ", " << y << ") channel " << c << ": " << got;
        }
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
}

TEST(Composite, TiledExrInMemoryReadsBackAsTheSourcePixels) {
  const auto tiles = MakeTiles(RgbaChannels());
  const CompositeOutput out = Composite(kSize, kTile, tiles);
  OIIO::Filesystem::IOMemReader reader(out.exr.data(), out.exr.size());
  auto in = OIIO::ImageInput::open("image.exr", nullptr, &reader);
  ASSERT_TRUE(in) << OIIO::geterror();
  ExpectSourcePixels(*in, 4);
}

TEST(Composite, TiledExrFileKeepsExtraChannels) {
  const auto tiles = MakeTiles({"R", "G", "B", "A", "direct.R"});
  const auto path = std::filesystem::temp_directory_path() /
                    ("composite_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".exr");
  Compositor compositor(kSize, kTile, path);
  for (const auto& t : tiles) compositor.Add(t.rect, t.exr);
  const CompositeOutput out = compositor.Finish();
  EXPECT_TRUE(out.exr.empty());
  EXPECT_FALSE(out.preview_png.empty());
  {
    auto in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in) << OIIO::geterror();
    ExpectSourcePixels(*in, 5);
    EXPECT_EQ(in->spec().channelnames[4], "direct.R");
  }
  std::filesystem::remove(path);
}

TEST(Composite, BytesDoNotDependOnTileOrder) {
  auto tiles = MakeTiles(RgbaChannels());
  const CompositeOutput in_order = Composite(kSize, kTile, tiles);
  std::mt19937 rng(7);
  std::shuffle(tiles.begin(), tiles.end(), rng);
  std::reverse(tiles.begin(), tiles.end());
  const CompositeOutput shuffled = Composite(kSize, kTile, tiles);
  EXPECT_EQ(in_order.exr, shuffled.exr);
  EXPECT_EQ(in_order.preview_png, shuffled.preview_png);
}

TEST(Composite, PreviewHoldsSrgbOfTheSource) {
  const CompositeOutput out = Composite(kSize, kTile, MakeTiles(RgbaChannels()));
  int width = 0, height = 0;
  const std::vector<std::uint8_t> png = testing::ReadPng(out.preview_png, &width, &height);
  ASSERT_EQ(width, kSize.width);
  ASSERT_EQ(height, kSize.height);
  for (auto [x, y] : {std::pair{0, 0}, {5, 3}, {69, 44}, {40, 2}}) {
    const std::uint8_t* p = &png[(static_cast<std::size_t>(y) * kSize.width + x) * 4];
    const float alpha = SourceValue(x, y, 3);
    for (int c = 0; c < 3; ++c) {
      const float straight = alpha >= 1.0f ? SourceValue(x, y, c) : SourceValue(x, y, c) / alpha;
      EXPECT_EQ(p[c], LinearToSrgb8(straight)) << x << "," << y << " channel " << c;
    }
    EXPECT_EQ(p[3], AlphaTo8(alpha));
  }
}

TEST(Composite, ExrCarriesItsMetadataAndThePreviewItsToneMap) {
  OutputSettings settings;
  settings.preview = {1.5, ToneMap::kFilmic};
  std::array<double, 16> to_camera{}, to_ndc{};
  for (int i = 0; i < 16; ++i) {
    to_camera[i] = i % 5 == 0 ? 1 : 0.5 * i;
    to_ndc[i] = -0.25 * i;
  }
  settings.metadata = {to_camera, to_ndc, 12.5, 64, 4, "photonfarm test"};
  const CompositeOutput out = Composite(kSize, kTile, MakeTiles(RgbaChannels()), settings);
  ExrMemoryIStream stream(out.exr);
  Imf::TiledInputFile file(stream);
  const Imf::Header& header = file.header();
  ASSERT_TRUE(Imf::hasWorldToCamera(header));
  ASSERT_TRUE(Imf::hasWorldToNDC(header));
  for (int i = 0; i < 16; ++i) {
    EXPECT_EQ(Imf::worldToCamera(header)[i / 4][i % 4], float(to_camera[i])) << i;
    EXPECT_EQ(Imf::worldToNDC(header)[i / 4][i % 4], float(to_ndc[i])) << i;
  }
  ASSERT_TRUE(Imf::hasChromaticities(header));
  EXPECT_EQ(Imf::chromaticities(header).red, Imf::Chromaticities().red);  // Rec. 709
  EXPECT_EQ(header.typedAttribute<Imf::DoubleAttribute>("renderTime").value(), 12.5);
  EXPECT_EQ(header.typedAttribute<Imf::IntAttribute>("samplesPerPixel").value(), 64);
  EXPECT_EQ(header.typedAttribute<Imf::IntAttribute>("rounds").value(), 4);
  EXPECT_EQ(header.typedAttribute<Imf::StringAttribute>("software").value(), "photonfarm test");

  int width = 0, height = 0;
  const std::vector<std::uint8_t> png = testing::ReadPng(out.preview_png, &width, &height);
  const float alpha = std::min(SourceValue(5, 3, 3), 1.0f);  // the preview clamps coverage
  const std::array<float, 3> display =
      ToneMapColor(settings.preview, {SourceValue(5, 3, 0) / alpha, SourceValue(5, 3, 1) / alpha, SourceValue(5, 3, 2) / alpha});
  EXPECT_EQ(png[(3 * kSize.width + 5) * 4], LinearToSrgb8(display[0]));
  // Unset metadata is left out.
  const CompositeOutput bare = Composite(kSize, kTile, MakeTiles(RgbaChannels()));
  ExrMemoryIStream bare_stream(bare.exr);
  Imf::TiledInputFile bare_file(bare_stream);
  EXPECT_FALSE(Imf::hasWorldToCamera(bare_file.header()));
  EXPECT_EQ(bare_file.header().findTypedAttribute<Imf::DoubleAttribute>("renderTime"), nullptr);
}

void ExpectCompositeError(std::vector<EncodedTile> tiles, const std::string& needle) {
  try {
    Composite(kSize, kTile, tiles);
    FAIL() << "expected an ImageError mentioning '" << needle << "'";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(Composite, RefusesMissingTile) {
  auto tiles = MakeTiles(RgbaChannels());
  tiles.erase(tiles.begin() + 4);
  ExpectCompositeError(tiles, "missing");
}

TEST(Composite, RefusesOverlappingTile) {
  auto tiles = MakeTiles(RgbaChannels());
  tiles.push_back(tiles[1]);
  ExpectCompositeError(tiles, "overlaps");
}

TEST(Composite, RefusesTileOutsideImageOrOffGrid) {
  auto tiles = MakeTiles(RgbaChannels());
  tiles[0].rect = {64, 32, 32, 32};
  ExpectCompositeError(tiles, "outside");
  tiles = MakeTiles(RgbaChannels());
  tiles[0].rect = {16, 0, 32, 32};
  ExpectCompositeError(tiles, "grid");
}

TEST(Composite, RefusesTileWhoseBytesDisagreeWithItsRect) {
  auto tiles = MakeTiles(RgbaChannels());
  std::swap(tiles[0].exr, tiles[1].exr);
  ExpectCompositeError(tiles, "data window");
}

TEST(Composite, RefusesTilesWithDifferentChannels) {
  auto tiles = MakeTiles(RgbaChannels());
  tiles[3] = MakeTiles({"R", "G", "B", "A", "Z"})[3];
  ExpectCompositeError(tiles, "channels");
  ExpectCompositeError(MakeTiles({"R", "G", "B"}), "no channel A");
}

}  // namespace
}  // namespace farm
