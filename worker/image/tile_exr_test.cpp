#include "image/tile_exr.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "image/image_error.h"

namespace farm {
namespace {

constexpr ImageSize kImage{100, 60};

Image MakeTile(PixelRect rect, std::vector<std::string> channels) {
  Image tile(rect, std::move(channels));
  auto data = tile.data();
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = std::sin(0.37f * i) * 10.0f + 0.001f * i;
  return tile;
}

bool SameBits(const Image& a, const Image& b) {
  return a.rect() == b.rect() && a.channels() == b.channels() &&
         a.data().size() == b.data().size() &&
         std::memcmp(a.data().data(), b.data().data(), a.data().size_bytes()) == 0;
}

TEST(TileExr, RoundTripIsBitExact) {
  Image tile = MakeTile({32, 16, 32, 16}, RgbaChannels());
  // Values a careless codec would alter: infinities, NaN, negative zero, denormals.
  tile.data()[0] = std::numeric_limits<float>::infinity();
  tile.data()[1] = std::numeric_limits<float>::quiet_NaN();
  tile.data()[2] = -0.0f;
  tile.data()[3] = std::numeric_limits<float>::denorm_min();
  const std::string bytes = EncodeTileExr(tile, kImage);
  const Image back = DecodeTileExr(bytes, kImage, tile.rect(), RgbaChannels());
  EXPECT_TRUE(SameBits(tile, back));
}

TEST(TileExr, KeepsExtraChannelsAndTheCallersOrder) {
  const std::vector<std::string> channels = {"R", "G", "B", "A", "direct.R", "albedo.G"};
  const Image tile = MakeTile({96, 32, 4, 28}, channels);  // A partial tile at the corner.
  const std::string bytes = EncodeTileExr(tile, kImage);
  EXPECT_EQ(ReadTileExrChannels(bytes),
            (std::vector<std::string>{"A", "B", "G", "R", "albedo.G", "direct.R"}));
  EXPECT_TRUE(SameBits(tile, DecodeTileExr(bytes, kImage, tile.rect(), channels)));
}

TEST(TileExr, SamePixelsGiveSameBytes) {
  const Image tile = MakeTile({0, 0, 32, 32}, RgbaChannels());
  EXPECT_EQ(EncodeTileExr(tile, kImage), EncodeTileExr(MakeTile({0, 0, 32, 32}, RgbaChannels()), kImage));
}

TEST(TileExr, RefusesTileOutsideImage) {
  EXPECT_THROW(EncodeTileExr(MakeTile({90, 0, 32, 32}, RgbaChannels()), kImage), ImageError);
}

void ExpectDecodeError(const std::string& bytes, ImageSize size, PixelRect rect,
                       const std::vector<std::string>& channels, const std::string& needle) {
  try {
    DecodeTileExr(bytes, size, rect, channels);
    FAIL() << "expected an ImageError mentioning '" << needle << "'";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(TileExr, DecodeRefusesWhatWasNotAskedFor) {
  const Image tile = MakeTile({32, 0, 32, 32}, RgbaChannels());
  const std::string bytes = EncodeTileExr(tile, kImage);
  ExpectDecodeError(bytes, kImage, {0, 0, 32, 32}, RgbaChannels(), "data window");
  ExpectDecodeError(bytes, {200, 60}, tile.rect(), RgbaChannels(), "display window");
  ExpectDecodeError(bytes, kImage, tile.rect(), {"R", "G", "B"}, "channels");
  ExpectDecodeError(bytes, kImage, tile.rect(), {"R", "G", "B", "A", "Z"}, "channels");
}

TEST(TileExr, DecodeRefusesGarbageAndTruncation) {
  const Image tile = MakeTile({0, 0, 32, 32}, RgbaChannels());
  const std::string bytes = EncodeTileExr(tile, kImage);
  ExpectDecodeError("not an exr at all", kImage, tile.rect(), RgbaChannels(), "OpenEXR");
  ExpectDecodeError("", kImage, tile.rect(), RgbaChannels(), "OpenEXR");
  ExpectDecodeError(bytes.substr(0, bytes.size() / 2), kImage, tile.rect(), RgbaChannels(),
                    "OpenEXR");
  EXPECT_THROW(ReadTileExrChannels("garbage"), ImageError);
}

}  // namespace
}  // namespace farm
