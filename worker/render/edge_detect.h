#pragma once

// Edge detection for edge anti-aliasing: which pixels of a tile get supersampled.
//
// A pixel is an edge when the Sobel gradient of log-luminance around it exceeds a threshold.
// Log-luminance makes the test relative (a step from 0.1 to 0.2 counts as much as one from
// 10 to 20, which is what the eye sees after tone mapping); a floor of 1/256 keeps noise in
// the darkest displayable values from counting as edges. The Sobel kernels are divided by 8,
// their weight on each side, so the gradient is in log units per pixel: a linear ramp of
// slope k reads k, and a sharp step of height h reads h/2 on the pixels either side of it.
//
// The decision for a pixel depends only on the 3x3 neighbourhood of base-pass values around
// it, clamped at the image border (never at a tile border), so it is the same whichever
// tile the pixel is rendered in.

#include <cstdint>
#include <vector>

#include "image/image.h"

namespace farm {

inline constexpr float kEdgeLuminanceFloor = 1.0f / 256.0f;

// log(luminance + floor) of a linear RGB value (Rec. 709 luminance).
double EdgeLogLuminance(float r, float g, float b);

// Log-luminance over `area`: a tile with its one-pixel apron, clipped to the image.
class LogLuminanceGrid {
 public:
  explicit LogLuminanceGrid(const PixelRect& area);

  const PixelRect& area() const { return area_; }
  void set(int x, int y, double value) { values_[Index(x, y)] = value; }
  // Coordinates outside the area are clamped into it. For a pixel of the tile the area holds
  // every neighbour inside the image, so this is clamping at the image border.
  double at(int x, int y) const;

 private:
  std::size_t Index(int x, int y) const {
    return static_cast<std::size_t>(y - area_.y) * area_.width + (x - area_.x);
  }
  PixelRect area_;
  std::vector<double> values_;
};

// The Sobel gradient magnitude at (x, y), in log units per pixel (see above).
double SobelGradient(const LogLuminanceGrid& grid, int x, int y);

// One byte per pixel of `tile` (row-major): 1 where SobelGradient exceeds threshold. The grid
// must cover the tile with its apron clipped to the image (ApronArea).
std::vector<std::uint8_t> DetectEdges(const LogLuminanceGrid& grid, const PixelRect& tile,
                                      double threshold);

// `tile` grown by one pixel on each side and clipped to the image.
PixelRect ApronArea(const PixelRect& tile, ImageSize image);

}  // namespace farm
