#pragma once

// The weighted sums from which a tile's pixels are reconstructed with the scene's pixel
// filter (scene/pixel_filter.h, docs/pixel-filters.md).
//
// Pixel p is the weighted mean of the samples about it: each sample s of a pixel q within
// the filter's margin of p weighs f(s - centre(p)) / n(q), n(q) the samples q took (edge
// anti-aliasing gives some pixels more, and dividing by it keeps a densely sampled pixel
// from outweighing its neighbours: each pixel's samples together weigh as the pixel's area).
//
// Except where edge anti-aliasing judged q smooth and left it with fewer samples: then q
// contributes its mean at the filter's exact weight over its area (PixelFilter::Integral),
// not its few samples at their positions. A lone sample's weight is a poor estimate of
// that area's (the Gaussian's falls from 0.48 to 0.01 of its peak across a neighbouring
// pixel), and next to a bright edge that error, times the contrast, outweighed what
// filtering gains (docs/pixel-filters.md); a smooth pixel's sub-pixel positions carry
// little.
//
// Bit-identical whatever the tiling: a sample's value depends only on (seed, round,
// pixel, sample index), so a margin sample is the same wherever it is drawn; each
// (p, q) pair has its own sum, added to in q's sample order by the one thread that draws
// q, and p's sums are added in a fixed order of q. Memory: 8 (channels + 1) (2 margin +
// 1)^2 bytes a tile pixel, 3.5 MB for a 32-pixel tile and radius 2.

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "image/image.h"
#include "scene/pixel_filter.h"

namespace farm {

class FilterSplats {
 public:
  // Filtered channels per sample: the tile renderer's light channels (beauty, alpha,
  // direct, indirect, caustic, volume, bias, albedo).
  static constexpr int kChannels = 22;
  // Where a pixel's summed weight falls below this share of its expected weight (Mitchell's
  // negative lobes can bring it near 0 when its samples sit far from its centre), the
  // expected weight times this share divides instead, so that no pixel's noise is
  // amplified more than four times. At one sample a pixel, Mitchell's radius-2 weight falls
  // below it in about 6 pixels of 10,000 (a simulation of uniform samples); the
  // non-negative filters' practically never.
  static constexpr double kMinWeightShare = 0.25;

  FilterSplats(const PixelFilter& filter, const PixelRect& tile, ImageSize image);

  // The pixels whose samples count for the tile: the tile grown by the filter's margin and
  // clipped to the image.
  const PixelRect& source() const { return source_; }

  // Adds sample (sx, sy) (image coordinates) of pixel (qx, qy) of source(), with its
  // kChannels values, to every tile pixel it reaches. Calls for one pixel must come in
  // sample order from one thread at a time; different pixels may be added concurrently.
  void Add(int qx, int qy, double sx, double sy, const double* channels);

  // What the tile renderer knows of a source pixel once it is sampled.
  struct Source {
    std::uint32_t samples = 0;
    // Whether its samples count at their positions, else its mean over its area (above).
    bool by_position = true;
    const double* light_sums = nullptr;  // its kChannels summed over its samples
  };

  // Writes the kChannels filtered values of tile pixel (x, y) to out; source_of(qx, qy)
  // describes each source() pixel.
  template <typename SourceOf>
  void Resolve(int x, int y, SourceOf source_of, float* out) const {
    std::array<double, kChannels + 1> sum{};
    for (int qy = std::max(y - margin_, source_.y); qy <= std::min(y + margin_, source_.y_end() - 1); ++qy)
      for (int qx = std::max(x - margin_, source_.x); qx <= std::min(x + margin_, source_.x_end() - 1); ++qx)
        AddSource(x, y, qx, qy, source_of(qx, qy), sum);
    Finish(x, y, sum, out);
  }

 private:
  using Slot = std::array<double, kChannels + 1>;  // weighted channels, then the weight
  Slot& SlotOf(int px, int py, int qx, int qy) {
    return slots_[Index(px, py) + static_cast<std::size_t>(qy - py + margin_) * side_ + (qx - px + margin_)];
  }
  std::size_t Index(int px, int py) const {
    return (static_cast<std::size_t>(py - tile_.y) * tile_.width + (px - tile_.x)) * side_ * side_;
  }

  void AddSource(int x, int y, int qx, int qy, const Source& q, std::array<double, kChannels + 1>& sum) const;
  void Finish(int x, int y, const std::array<double, kChannels + 1>& sum, float* out) const;

  PixelFilter filter_;
  PixelRect tile_;
  PixelRect source_;
  int margin_ = 0;
  int side_ = 1;  // 2 margin + 1
  // The filter's weight over the part of its support inside the image, by tile column and
  // row: what the summed weight of a pixel's samples estimates.
  std::vector<double> expected_x_, expected_y_;
  // The filter's weight along one axis over the pixel at offset d in [-margin, margin].
  std::vector<double> over_pixel_;
  std::vector<Slot> slots_;
};

}  // namespace farm
