#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace farm {

// A rectangle of image pixels; the origin is the image's top-left corner.
struct PixelRect {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;

  int x_end() const { return x + width; }
  int y_end() const { return y + height; }
  bool Contains(const PixelRect& inner) const {
    return inner.x >= x && inner.y >= y && inner.x_end() <= x_end() && inner.y_end() <= y_end();
  }
  friend bool operator==(const PixelRect&, const PixelRect&) = default;
};

// Float pixels of a rectangle of a larger image, with named channels ("R", "G", "B", "A",
// later "direct.R" and the like), stored interleaved: channel c of pixel (x, y) is at
// ((y - rect.y) * rect.width + (x - rect.x)) * channel_count + c.
class Image {
 public:
  Image(PixelRect rect, std::vector<std::string> channels)
      : rect_(rect),
        channels_(std::move(channels)),
        pixels_(static_cast<std::size_t>(rect.width) * rect.height * channels_.size(), 0.0f) {}

  const PixelRect& rect() const { return rect_; }
  const std::vector<std::string>& channels() const { return channels_; }
  int channel_count() const { return static_cast<int>(channels_.size()); }

  // x and y are image coordinates inside rect().
  float* pixel(int x, int y) { return pixels_.data() + Offset(x, y); }
  const float* pixel(int x, int y) const { return pixels_.data() + Offset(x, y); }

  std::span<float> data() { return pixels_; }
  std::span<const float> data() const { return pixels_; }

  friend bool operator==(const Image&, const Image&) = default;

 private:
  std::size_t Offset(int x, int y) const {
    return (static_cast<std::size_t>(y - rect_.y) * rect_.width + (x - rect_.x)) * channels_.size();
  }

  PixelRect rect_;
  std::vector<std::string> channels_;
  std::vector<float> pixels_;
};

// The size of a whole image, of which tiles are rectangles.
struct ImageSize {
  int width = 0;
  int height = 0;
  friend bool operator==(const ImageSize&, const ImageSize&) = default;
};

// The channel of a rendered image that counts each pixel's camera samples (summed, not
// averaged, over rounds).
inline constexpr char kSamplesChannel[] = "samples.Y";

// The layer of a rendered image that holds, per pixel, the difference between a companion
// of the beauty whose photon estimates all take twice the neighbours and the beauty itself:
// an estimate of the beauty's kernel bias (render/integrator.h, image/error_estimate.h).
inline std::vector<std::string> BiasChannels() { return {"bias.R", "bias.G", "bias.B"}; }

// The channels of a beauty image.
inline std::vector<std::string> RgbaChannels() { return {"R", "G", "B", "A"}; }

}  // namespace farm
