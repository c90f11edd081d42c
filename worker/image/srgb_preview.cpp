#include "image/srgb_preview.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "image/exr_util.h"
#include "image/image_error.h"

namespace farm {
namespace {

float Clamp01(float v) { return v > 0.0f ? std::min(v, 1.0f) : 0.0f; }  // NaN -> 0

// Collects what OpenImageIO writes. OpenImageIO 2.4's own IOVecOutput does not advance
// its position on write(), so every chunk of a PNG lands at offset 0.
class StringOutput final : public OIIO::Filesystem::IOProxy {
 public:
  explicit StringOutput(std::string& out) : IOProxy("", Write), out_(out) {}
  const char* proxytype() const override { return "stringoutput"; }
  size_t write(const void* buf, size_t size) override {
    const size_t n = pwrite(buf, size, m_pos);
    m_pos += static_cast<int64_t>(n);
    return n;
  }
  size_t pwrite(const void* buf, size_t size, int64_t offset) override {
    const auto at = static_cast<size_t>(offset);
    if (out_.size() < at + size) out_.resize(at + size);
    std::memcpy(out_.data() + at, buf, size);
    return size;
  }
  size_t size() const override { return out_.size(); }

 private:
  std::string& out_;
};

int ChannelIndex(const Image& tile, const char* name) {
  const auto& ch = tile.channels();
  const auto it = std::find(ch.begin(), ch.end(), name);
  if (it == ch.end()) throw ImageError(std::string("tile has no channel ") + name);
  return static_cast<int>(it - ch.begin());
}

}  // namespace

std::uint8_t LinearToSrgb8(float linear) {
  const double v = Clamp01(linear);
  const double encoded = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
  return static_cast<std::uint8_t>(std::lround(std::clamp(encoded, 0.0, 1.0) * 255.0));
}

std::uint8_t AlphaTo8(float alpha) {
  return static_cast<std::uint8_t>(std::lround(Clamp01(alpha) * 255.0f));
}

namespace {

// Converts the tile's pixels into `rgba8`, a straight-alpha sRGB RGBA8 buffer `row_width`
// pixels wide whose pixel (0, 0) is image pixel (origin_x, origin_y).
void ConvertPixels(const Image& tile, int origin_x, int origin_y, int row_width,
                   std::span<std::uint8_t> rgba8, const PreviewSettings& settings) {
  const PixelRect& r = tile.rect();
  const int index[4] = {ChannelIndex(tile, "R"), ChannelIndex(tile, "G"), ChannelIndex(tile, "B"),
                        ChannelIndex(tile, "A")};
  for (int y = r.y; y < r.y_end(); ++y) {
    for (int x = r.x; x < r.x_end(); ++x) {
      const float* p = tile.pixel(x, y);
      const float alpha = Clamp01(p[index[3]]);
      // Straight colour = premultiplied / alpha; with no coverage, show the colour as is.
      const float scale = alpha > 0.0f ? 1.0f / alpha : 1.0f;
      std::uint8_t* out =
          rgba8.data() +
          (static_cast<std::size_t>(y - origin_y) * row_width + (x - origin_x)) * 4;
      const std::array<float, 3> display =
          ToneMapColor(settings, {p[index[0]] * scale, p[index[1]] * scale, p[index[2]] * scale});
      for (int c = 0; c < 3; ++c) out[c] = LinearToSrgb8(display[c]);
      out[3] = AlphaTo8(alpha);
    }
  }
}

}  // namespace

void WritePreviewPixels(const Image& tile, ImageSize image_size, std::span<std::uint8_t> rgba8,
                        const PreviewSettings& settings) {
  const PixelRect& r = tile.rect();
  if (!PixelRect{0, 0, image_size.width, image_size.height}.Contains(r)) {
    throw ImageError("tile " + ToString(r) + " lies outside the " + ToString(image_size) + " image");
  }
  if (rgba8.size() != static_cast<std::size_t>(image_size.width) * image_size.height * 4) {
    throw ImageError("preview buffer does not match the " + ToString(image_size) + " image");
  }
  ConvertPixels(tile, 0, 0, image_size.width, rgba8, settings);
}

std::string EncodeTilePreviewPng(const Image& tile, const PreviewSettings& settings) {
  const PixelRect& r = tile.rect();
  if (r.width <= 0 || r.height <= 0) throw ImageError("tile " + ToString(r) + " is empty");
  std::vector<std::uint8_t> rgba8(static_cast<std::size_t>(r.width) * r.height * 4);
  ConvertPixels(tile, r.x, r.y, r.width, rgba8, settings);
  return EncodePngRgba8({r.width, r.height}, rgba8);
}

std::string EncodePngRgba8(ImageSize size, std::span<const std::uint8_t> rgba8) {
  if (rgba8.size() != static_cast<std::size_t>(size.width) * size.height * 4) {
    throw ImageError("PNG buffer does not match the " + ToString(size) + " image");
  }
  std::string bytes;
  StringOutput proxy(bytes);
  auto out = OIIO::ImageOutput::create("preview.png");
  if (!out) throw ImageError("OpenImageIO cannot write PNG: " + OIIO::geterror());
  OIIO::ImageSpec spec(size.width, size.height, 4, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:ColorSpace", "sRGB");
  // Our pixels already hold straight alpha; without this OpenImageIO would divide again.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  if (!out->set_ioproxy(&proxy) || !out->open("preview.png", spec) ||
      !out->write_image(OIIO::TypeDesc::UINT8, rgba8.data()) || !out->close()) {
    throw ImageError("cannot encode PNG preview: " + out->geterror());
  }
  return bytes;
}

}  // namespace farm
