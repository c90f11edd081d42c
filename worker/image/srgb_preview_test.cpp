#include "image/srgb_preview.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace farm {
namespace {

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

  OIIO::Filesystem::IOMemReader reader(png.data(), png.size());
  // Ask for the stored values as they are, without OpenImageIO premultiplying them.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  // With a config, OpenImageIO 2.4 only sees the proxy if the config names it too.
  void* proxy = &reader;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  auto in = OIIO::ImageInput::open("preview.png", &config, &reader);
  ASSERT_TRUE(in) << OIIO::geterror();
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT8);
  ASSERT_EQ(in->spec().nchannels, 4);
  std::vector<std::uint8_t> read(8);
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, read.data()));
  EXPECT_EQ(read, (std::vector<std::uint8_t>{188, 118, 0, 128, 255, 3, 255, 255}));
}

}  // namespace
}  // namespace farm
