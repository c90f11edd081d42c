#include "texture/texture_system.h"

// Before OIIO's headers (texture_system.cpp says why).
#include "contract/failure.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <vector>

#include "texture/footprint.h"
#include "texture/test_images.h"

namespace farm {
namespace {

float SrgbToLinear(float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); }

class TextureSystemTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshTestDir("texture_system_test", ::testing::UnitTest::GetInstance()->current_test_info()->name());
    textures_ = std::make_unique<TextureSystem>(TextureSystemOptions{64, dir_ / "prepared"});
  }
  void TearDown() override {
    textures_.reset();
    std::filesystem::remove_all(dir_);
  }
  // A source file without an extension, as the blob cache keeps them.
  std::filesystem::path Source(const std::string& name) const { return dir_ / name; }

  std::filesystem::path dir_;
  std::unique_ptr<TextureSystem> textures_;
};

constexpr TextureWrap kRepeat = TextureWrap::kRepeat;

TextureSystem::SourceFile From(const std::filesystem::path& file) {
  return [file] { return file; };
}

Rgba At(const TextureSystem& ts, const PreparedTexture& t, float u, float v, TextureWrap wrap = kRepeat) {
  return ts.Lookup(t, TextureLookup{{u, v}, {}, {}}, wrap);
}

TEST_F(TextureSystemTest, ColoursInIntegerFilesAreSrgbAndDataIsLinear) {
  WriteTestImage(Source("grey"), "png", 16, 16, 3, OIIO::TypeDesc::UINT8, [](int, int, int) { return 128 / 255.0f; });
  const PreparedTexture colour =
      textures_->Prepare(TestDigest('a'), TextureUse::kColor, TextureEncoding::kByUse, From(Source("grey")));
  const PreparedTexture data =
      textures_->Prepare(TestDigest('a'), TextureUse::kData, TextureEncoding::kByUse, From(Source("grey")));
  EXPECT_TRUE(colour.srgb);
  EXPECT_FALSE(data.srgb);
  EXPECT_NEAR(At(*textures_, colour, 0.5f, 0.5f).rgb.g, SrgbToLinear(128 / 255.0f), 1e-3);  // 0.2158
  EXPECT_NEAR(At(*textures_, data, 0.5f, 0.5f).rgb.g, 128 / 255.0f, 1e-6);
  EXPECT_EQ(At(*textures_, colour, 0.5f, 0.5f).alpha, 1) << "no alpha channel reads as opaque";
  // Texture.encoding overrides the use for integer files.
  EXPECT_FALSE(textures_->Prepare(TestDigest('a'), TextureUse::kColor, TextureEncoding::kLinear, From(Source("grey"))).srgb);
  EXPECT_TRUE(textures_->Prepare(TestDigest('a'), TextureUse::kData, TextureEncoding::kSrgb, From(Source("grey"))).srgb);
}

TEST_F(TextureSystemTest, FloatFilesAreLinearEvenAsColours) {
  WriteTestImage(Source("hdr"), "exr", 8, 8, 3, OIIO::TypeDesc::HALF, [](int, int, int c) { return c == 0 ? 4.0f : 0.5f; });
  const PreparedTexture t = textures_->Prepare(TestDigest('b'), TextureUse::kColor, TextureEncoding::kByUse, From(Source("hdr")));
  EXPECT_FALSE(t.srgb);
  const Rgba v = At(*textures_, t, 0.3f, 0.6f);
  EXPECT_FLOAT_EQ(v.rgb.r, 4.0f);
  EXPECT_FLOAT_EQ(v.rgb.b, 0.5f);
}

// A black and white checkerboard averages to 0.5 in linear light: the MIP levels are made
// after the sRGB decoding (averaging the stored values would give 0.21 once decoded).
TEST_F(TextureSystemTest, WideFootprintsAndTheAverageAreLinearMeans) {
  WriteTestImage(Source("checker"), "png", 64, 64, 3, OIIO::TypeDesc::UINT8,
                 [](int x, int y, int) { return float(((x / 8) + (y / 8)) % 2); });
  const PreparedTexture t = textures_->Prepare(TestDigest('c'), TextureUse::kColor, TextureEncoding::kByUse, From(Source("checker")));
  EXPECT_NEAR(textures_->Average(t).rgb.r, 0.5f, 1e-3);
  EXPECT_NEAR(textures_->Average(t).alpha, 1.0f, 1e-6);
  EXPECT_NEAR(textures_->Lookup(t, TextureLookup{{0.5f, 0.5f}, {1, 0}, {0, 1}}, kRepeat).rgb.r, 0.5f, 0.02);
  // A point lookup at a texel's centre reads that texel.
  EXPECT_NEAR(At(*textures_, t, 4.5f / 64, 4.5f / 64).rgb.r, 0.0f, 1e-3);
  EXPECT_NEAR(At(*textures_, t, 12.5f / 64, 4.5f / 64).rgb.r, 1.0f, 1e-3);
}

// glTF's texture coordinates: (0, 0) is the top-left corner of the image, v grows down.
TEST_F(TextureSystemTest, TheFirstRowOfTheFileIsAtVZero) {
  WriteTestImage(Source("rows"), "png", 4, 4, 1, OIIO::TypeDesc::UINT8, [](int, int y, int) { return y == 0 ? 1.0f : 0.0f; });
  const PreparedTexture t = textures_->Prepare(TestDigest('d'), TextureUse::kData, TextureEncoding::kByUse, From(Source("rows")));
  EXPECT_NEAR(At(*textures_, t, 0.5f, 0.125f, TextureWrap::kClamp).rgb.b, 1.0f, 1e-3) << "grey is replicated into RGB";
  EXPECT_NEAR(At(*textures_, t, 0.5f, 0.875f, TextureWrap::kClamp).rgb.r, 0.0f, 1e-3);
}

TEST_F(TextureSystemTest, WrapModes) {
  // Columns 0..3 hold 0, 1/3, 2/3, 1 (linear data).
  WriteTestImage(Source("ramp"), "png", 4, 1, 1, OIIO::TypeDesc::UINT16, [](int x, int, int) { return x / 3.0f; });
  const PreparedTexture t = textures_->Prepare(TestDigest('e'), TextureUse::kData, TextureEncoding::kByUse, From(Source("ramp")));
  const float second = 1 / 3.0f, third = 2 / 3.0f;
  EXPECT_NEAR(At(*textures_, t, 1.375f, 0.5f, TextureWrap::kRepeat).rgb.r, second, 1e-4);
  EXPECT_NEAR(At(*textures_, t, 1.375f, 0.5f, TextureWrap::kClamp).rgb.r, 1.0f, 1e-4);
  EXPECT_NEAR(At(*textures_, t, 1.375f, 0.5f, TextureWrap::kMirror).rgb.r, third, 1e-4);
  EXPECT_NEAR(At(*textures_, t, -0.625f, 0.5f, TextureWrap::kRepeat).rgb.r, second, 1e-4);
}

TEST_F(TextureSystemTest, AlphaIsReadUnassociated) {
  // Grey 0.8 with alpha 0 on the left half, 1 on the right: the colour where alpha is 0 is
  // still the colour (glTF's base colour does not depend on alpha).
  WriteTestImage(Source("leaf"), "png", 8, 8, 2, OIIO::TypeDesc::UINT8,
                 [](int x, int, int c) { return c == 0 ? 0.8f : (x < 4 ? 0.0f : 1.0f); });
  const PreparedTexture t = textures_->Prepare(TestDigest('f'), TextureUse::kData, TextureEncoding::kByUse, From(Source("leaf")));
  const Rgba left = At(*textures_, t, 1.5f / 8, 0.5f), right = At(*textures_, t, 6.5f / 8, 0.5f);
  EXPECT_NEAR(left.alpha, 0, 1e-3);
  EXPECT_NEAR(right.alpha, 1, 1e-3);
  EXPECT_NEAR(left.rgb.r, 0.8f, 3e-3);
  EXPECT_NEAR(right.rgb.g, 0.8f, 3e-3);
  EXPECT_NEAR(textures_->Average(t).alpha, 0.5f, 1 / 255.0f) << "stored in 8 bits, as the file is";
  EXPECT_NEAR(textures_->Average(t).rgb.r, 0.8f, 3e-3);
}

TEST_F(TextureSystemTest, AFileThatIsNotAnImageIsBadInput) {
  std::ofstream(Source("junk")) << "this is not an image";
  try {
    textures_->Prepare(TestDigest('9'), TextureUse::kColor, TextureEncoding::kByUse, From(Source("junk")));
    FAIL() << "a text file was prepared as a texture";
  } catch (const BadInputError& e) {
    EXPECT_NE(std::string(e.what()).find(TestDigest('9')), std::string::npos) << e.what();
  }
}

// Prepared once per host: a second system (another worker sharing the folder) reads the
// same file without writing it again.
TEST_F(TextureSystemTest, EachTextureIsPreparedOnce) {
  WriteTestImage(Source("once"), "png", 8, 8, 3, OIIO::TypeDesc::UINT8, [](int, int, int) { return 1.0f; });
  textures_->Prepare(TestDigest('7'), TextureUse::kColor, TextureEncoding::kByUse, From(Source("once")));
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir_ / "prepared")) files.push_back(e.path());
  ASSERT_EQ(files.size(), 1u) << "one prepared file, no temporary left behind";
  const auto written = std::filesystem::last_write_time(files[0]);
  TextureSystem other(TextureSystemOptions{64, dir_ / "prepared"});
  bool read_source = false;
  const PreparedTexture t = other.Prepare(TestDigest('7'), TextureUse::kColor, TextureEncoding::kByUse, [&] {
    read_source = true;
    return Source("once");
  });
  EXPECT_FALSE(read_source) << "a prepared texture's blob is not fetched again";
  EXPECT_TRUE(t.srgb) << "the decoding is known from the prepared file's name";
  EXPECT_EQ(std::filesystem::last_write_time(files[0]), written);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_ / "prepared"), std::filesystem::directory_iterator()), 1);
  EXPECT_NEAR(other.Lookup(t, TextureLookup{{0.5f, 0.5f}, {}, {}}, kRepeat).rgb.r, 1.0f, 1e-3);
}

// The tile cache stays within its bound while lookups sweep a texture four times larger.
TEST_F(TextureSystemTest, TheTileCacheIsBounded) {
  WriteTestImage(Source("big"), "png", 2048, 2048, 3, OIIO::TypeDesc::UINT8,
                 [](int x, int y, int c) { return float((x * 7 + y * 13 + c) % 256) / 255; });
  TextureSystem small(TextureSystemOptions{4, dir_ / "prepared"});
  const PreparedTexture t = small.Prepare(TestDigest('8'), TextureUse::kColor, TextureEncoding::kByUse, From(Source("big")));
  for (int y = 0; y < 2048; y += 16)
    for (int x = 0; x < 2048; x += 16) small.Lookup(t, TextureLookup{{(x + 0.5f) / 2048, (y + 0.5f) / 2048}, {}, {}}, kRepeat);
  EXPECT_GT(small.CacheBytes(), 0u);
  EXPECT_LE(small.CacheBytes(), 5u << 20) << "a 4 MiB cache (and a tile's slack)";
}

TEST_F(TextureSystemTest, AConstantTextureReadsItsValueWhateverTheFootprint) {
  WriteTestImage(Source("flat"), "exr", 32, 16, 4, OIIO::TypeDesc::FLOAT,
                 [](int, int, int c) { return 0.125f * float(c + 1); });
  const PreparedTexture t = textures_->Prepare(TestDigest('1'), TextureUse::kData, TextureEncoding::kByUse, From(Source("flat")));
  for (const TextureLookup& at : {TextureLookup{{0.3f, 0.7f}, {}, {}}, TextureLookup{{-2.1f, 5.5f}, {0.01f, 0}, {0, 0.2f}},
                                  TextureLookup{{0.5f, 0.5f}, {3, 1}, {-0.5f, 2}}}) {
    const Rgba v = textures_->Lookup(t, at, kRepeat);
    EXPECT_FLOAT_EQ(v.rgb.r, 0.125f);
    EXPECT_FLOAT_EQ(v.rgb.g, 0.25f);
    EXPECT_FLOAT_EQ(v.rgb.b, 0.375f);
    EXPECT_FLOAT_EQ(v.alpha, 0.5f);
  }
}

// A point lookup between texel centres is the bilinear blend of the four around it: on a
// 2x2 texture (clamped) with texels a b / c d, at (u, v) it is a blend with weights
// s = 2u - 0.5 and t = 2v - 0.5 (texel centres are at 0.25 and 0.75).
TEST_F(TextureSystemTest, PointLookupsAreBilinear) {
  const float texel[2][2] = {{0.1f, 0.9f}, {0.4f, 0.2f}};  // [row][column]
  WriteTestImage(Source("2x2"), "exr", 2, 2, 1, OIIO::TypeDesc::FLOAT, [&](int x, int y, int) { return texel[y][x]; });
  const PreparedTexture t = textures_->Prepare(TestDigest('2'), TextureUse::kData, TextureEncoding::kByUse, From(Source("2x2")));
  for (const Vec2 uv : {Vec2{0.25f, 0.25f}, Vec2{0.5f, 0.5f}, Vec2{0.3f, 0.6f}, Vec2{0.7f, 0.35f}, Vec2{0.6f, 0.74f}}) {
    const float s = 2 * uv.x - 0.5f, r = 2 * uv.y - 0.5f;
    const float want = (1 - r) * ((1 - s) * texel[0][0] + s * texel[0][1]) + r * ((1 - s) * texel[1][0] + s * texel[1][1]);
    EXPECT_NEAR(At(*textures_, t, uv.x, uv.y, TextureWrap::kClamp).rgb.g, want, 1e-5) << ToString(uv);
  }
}

// A checkerboard floor seen from 1 unit above it, looking at the horizon: the lower half of
// the image sees the floor ever more obliquely, out to where a pixel covers many checks.
// Each pixel's one filtered lookup (its ray cone's footprint, footprint.h) is compared
// with the reference, 256 point lookups (16 x 16 stratified) weighted by a tent one pixel
// in radius (the footprint's axes are one pixel's step, and the tent is the filter such a
// step stands for; a box over the pixel alone keeps moire where a pixel spans about one
// check). The RMSE over the floor's pixels (those whose tent lies wholly below the horizon)
// is at most 0.065 of the 0 to 1 checkerboard (0.053 measured; deterministic). One point lookup per pixel,
// as without a footprint, aliases: its RMSE is more than five times that.
TEST_F(TextureSystemTest, AGrazingCheckerboardMatchesASupersampledReference) {
  constexpr int kSize = 64, kCheck = 8;
  WriteTestImage(Source("floor"), "png", kSize, kSize, 1, OIIO::TypeDesc::UINT8,
                 [](int x, int y, int) { return float(((x / kCheck) + (y / kCheck)) % 2); });
  const PreparedTexture t = textures_->Prepare(TestDigest('3'), TextureUse::kData, TextureEncoding::kByUse, From(Source("floor")));
  // The texture repeats every 4 units in x (u) and z (v): a check is half a unit wide.
  const Vec3 n(0, 1, 0), dpdu(4, 0, 0), dpdv(0, 0, 4);
  constexpr int kWidth = 64, kHeight = 48;
  const float tan_half = std::tan(0.5f * 0.6f);  // a vertical field of view of 0.6 radians
  const float pixel = 2 * tan_half / kHeight;   // the pixel's extent on the image plane at z = 1
  const RayCone cone{0, pixel};                 // Camera::PixelSpreadAngle's small-angle value
  // Where the ray through image-plane point (x, y) (y up, the camera at (0, 1, 0) looking
  // along +z) meets the floor, or nothing above the horizon.
  struct FloorHit {
    Vec3 d;
    float t;
    Vec2 uv;
  };
  const auto floor_hit = [](float x, float y) -> std::optional<FloorHit> {
    const Vec3 d = Normalize(Vec3(x, y, 1));
    if (!(d.y < -1e-3f)) return std::nullopt;
    const float dist = -1 / d.y;
    const Vec3 p = Vec3(0, 1, 0) + d * dist;
    return FloorHit{d, dist, {p.x / 4, p.z / 4}};
  };
  double filtered_error = 0, point_error = 0;
  int pixels = 0;
  for (int j = kHeight / 2; j < kHeight; ++j) {
    for (int i = 0; i < kWidth; ++i) {
      const float x0 = (i - kWidth / 2) * pixel, y0 = (kHeight / 2 - j) * pixel;  // top-left corner
      const float cx = x0 + pixel / 2, cy = y0 - pixel / 2;
      const std::optional<FloorHit> centre = floor_hit(cx, cy);
      if (!centre || !floor_hit(cx, cy + pixel)) continue;  // the tent reaches the sky
      double reference = 0, weights = 0;
      for (int sy = 0; sy < 16; ++sy)
        for (int sx = 0; sx < 16; ++sx) {
          const float ox = (sx + 0.5f) / 8 - 1, oy = (sy + 0.5f) / 8 - 1;  // in (-1, 1) pixels
          const float w = (1 - std::abs(ox)) * (1 - std::abs(oy));
          const std::optional<FloorHit> h = floor_hit(cx + ox * pixel, cy + oy * pixel);
          reference += w * At(*textures_, t, h->uv.x, h->uv.y).rgb.r;
          weights += w;
        }
      reference /= weights;
      const FootprintAxes f = FootprintOf(centre->d, n, dpdu, dpdv, cone.WidthAt(centre->t));
      const float filtered = textures_->Lookup(t, TextureLookup{centre->uv, f.axis1, f.axis2}, kRepeat).rgb.r;
      const float point = At(*textures_, t, centre->uv.x, centre->uv.y).rgb.r;
      filtered_error += (filtered - reference) * (filtered - reference);
      point_error += (point - reference) * (point - reference);
      ++pixels;
    }
  }
  ASSERT_GT(pixels, kWidth * kHeight / 3);
  const double filtered_rmse = std::sqrt(filtered_error / pixels), point_rmse = std::sqrt(point_error / pixels);
  EXPECT_LT(filtered_rmse, 0.065) << "point lookups: " << point_rmse;
  EXPECT_GT(point_rmse, 5 * filtered_rmse) << "the scene is not one a footprint matters in";
}

}  // namespace
}  // namespace farm
