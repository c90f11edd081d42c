#include "image/srgb_preview.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "image/image_error.h"
#include "image/test_png.h"

namespace farm {
namespace {

using testing::ReadPng;

TEST(SrgbPreview, TransferFunctionAtKnownValues) {
  EXPECT_EQ(LinearToSrgb8(0.0f), 0);
  EXPECT_EQ(LinearToSrgb8(1.0f), 255);
  EXPECT_EQ(LinearToSrgb8(0.5f), 188);     // 1.055 * 0.5^(1/2.4) - 0.055 = 0.73536
  EXPECT_EQ(LinearToSrgb8(0.18f), 118);    // middle grey: 0.46136
  EXPECT_EQ(LinearToSrgb8(0.001f), 3);     // linear segment: 12.92 * 0.001 = 0.01292
  EXPECT_EQ(LinearToSrgb8(0.0031308f), 10);  // the knee: 0.04045
}

TEST(SrgbPreview, ClampsOutOfRangeAndNaN) {
  EXPECT_EQ(LinearToSrgb8(7.0f), 255);
  EXPECT_EQ(LinearToSrgb8(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(LinearToSrgb8(-0.5f), 0);
  EXPECT_EQ(LinearToSrgb8(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(AlphaTo8(0.5f), 128);
  EXPECT_EQ(AlphaTo8(1.5f), 255);
}

TEST(SrgbPreview, PngHoldsStraightAlphaSrgbValues) {
  // Premultiplied (0.25, 0.09, 0, 0.5) is straight (0.5, 0.18, 0) at half coverage.
  Image tile({0, 0, 2, 1}, RgbaChannels());
  const float pixels[] = {0.25f, 0.09f, 0.0f, 0.5f, 1.0f, 0.001f, 3.0f, 1.0f};
  std::copy(std::begin(pixels), std::end(pixels), tile.data().begin());
  std::vector<std::uint8_t> rgba8(2 * 1 * 4);
  WritePreviewPixels(tile, {2, 1}, rgba8);
  const std::string png = EncodePngRgba8({2, 1}, rgba8);
  EXPECT_EQ(png, EncodePngRgba8({2, 1}, rgba8));  // Deterministic.
  // The stored values as they are, not premultiplied by OpenImageIO.
  int width = 0, height = 0;
  EXPECT_EQ(ReadPng(png, &width, &height), (std::vector<std::uint8_t>{188, 118, 0, 128, 255, 3, 255, 255}));
  EXPECT_EQ(width, 2);
  EXPECT_EQ(height, 1);
}

TEST(SrgbPreview, TilePngIsTheTilesPartOfTheImagePreview) {
  // A 3x2 tile at (5, 4) of a 10x8 image, with an extra AOV channel the preview ignores and
  // the beauty channels out of order.
  Image tile({5, 4, 3, 2}, {"A", "direct.R", "B", "G", "R"});
  for (int y = 4; y < 6; ++y) {
    for (int x = 5; x < 8; ++x) {
      float* p = tile.pixel(x, y);
      p[0] = (x == 6 && y == 5) ? 0.5f : 1.0f;  // one half-covered pixel
      p[1] = 42.0f;
      p[2] = 0.01f * x;
      p[3] = 0.05f * y;
      p[4] = 0.1f * (x - 4);
    }
  }
  const std::string png = EncodeTilePreviewPng(tile);
  EXPECT_EQ(png, EncodeTilePreviewPng(tile));  // Deterministic.

  std::vector<std::uint8_t> whole(10 * 8 * 4);
  WritePreviewPixels(tile, {10, 8}, whole);
  int width = 0, height = 0;
  const std::vector<std::uint8_t> read = ReadPng(png, &width, &height);
  ASSERT_EQ(width, 3);
  ASSERT_EQ(height, 2);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 3; ++x) {
      for (int c = 0; c < 4; ++c) {
        EXPECT_EQ(read[(y * 3 + x) * 4 + c], whole[((y + 4) * 10 + (x + 5)) * 4 + c])
            << "pixel (" << x << ", " << y << ") channel " << c;
      }
    }
  }
  // The half-covered pixel: straight R = 0.2 / 0.5 = 0.4 -> sRGB 170, alpha 128.
  EXPECT_EQ(read[(1 * 3 + 1) * 4 + 0], LinearToSrgb8(0.4f));
  EXPECT_EQ(read[(1 * 3 + 1) * 4 + 3], 128);
}

TEST(SrgbPreview, TilePngNeedsTheBeautyChannels) {
  Image tile({0, 0, 2, 2}, {"R", "G", "B"});
  EXPECT_THROW(EncodeTilePreviewPng(tile), ImageError);
}

}  // namespace
}  // namespace farm

namespace farm {
namespace {

TEST(SrgbPreview, ExposureAndToneMapApplyToTheStraightColour) {
  // Premultiplied 0.25 at half coverage is straight 0.5; +1 stop makes it 1.
  Image tile({0, 0, 1, 1}, RgbaChannels());
  const float pixel[] = {0.25f, 0.25f, 0.25f, 0.5f};
  std::copy(std::begin(pixel), std::end(pixel), tile.data().begin());
  const PreviewSettings settings{1, ToneMap::kFilmic};
  std::vector<std::uint8_t> rgba8(4);
  WritePreviewPixels(tile, {1, 1}, rgba8, settings);
  EXPECT_EQ(rgba8[0], LinearToSrgb8(ToneMapColor(settings, {0.5f, 0.5f, 0.5f})[0]));
  EXPECT_EQ(rgba8[3], 128);
  int width = 0, height = 0;
  EXPECT_EQ(testing::ReadPng(EncodeTilePreviewPng(tile, settings), &width, &height), rgba8);
  // The default is the clamp at exposure 0, the preview as it always was.
  WritePreviewPixels(tile, {1, 1}, rgba8);
  EXPECT_EQ(rgba8[0], LinearToSrgb8(0.5f));
}

}  // namespace
}  // namespace farm
