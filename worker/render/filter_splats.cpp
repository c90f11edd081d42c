#include "render/filter_splats.h"

#include <algorithm>

namespace farm {

FilterSplats::FilterSplats(const PixelFilter& filter, const PixelRect& tile, ImageSize image)
    : filter_(filter), tile_(tile), margin_(filter.margin()), side_(2 * filter.margin() + 1) {
  const int x0 = std::max(0, tile.x - margin_), y0 = std::max(0, tile.y - margin_);
  const int x1 = std::min(image.width, tile.x_end() + margin_), y1 = std::min(image.height, tile.y_end() + margin_);
  source_ = {x0, y0, x1 - x0, y1 - y0};
  for (int x = tile.x; x < tile.x_end(); ++x) expected_x_.push_back(filter.Integral(-(x + 0.5), image.width - (x + 0.5)));
  for (int y = tile.y; y < tile.y_end(); ++y) expected_y_.push_back(filter.Integral(-(y + 0.5), image.height - (y + 0.5)));
  slots_.resize(static_cast<std::size_t>(tile.width) * tile.height * side_ * side_, Slot{});
}

void FilterSplats::Add(int qx, int qy, double sx, double sy, const double* channels) {
  const int px0 = std::max(tile_.x, qx - margin_), px1 = std::min(tile_.x_end(), qx + margin_ + 1);
  const int py0 = std::max(tile_.y, qy - margin_), py1 = std::min(tile_.y_end(), qy + margin_ + 1);
  for (int py = py0; py < py1; ++py) {
    const double wy = filter_.Profile(sy - (py + 0.5));
    if (wy == 0) continue;
    for (int px = px0; px < px1; ++px) {
      const double w = wy * filter_.Profile(sx - (px + 0.5));
      if (w == 0) continue;
      Slot& slot = SlotOf(px, py, qx, qy);
      for (int c = 0; c < kChannels; ++c) slot[c] += w * channels[c];
      slot[kChannels] += w;
    }
  }
}

void FilterSplats::Resolve(int x, int y, std::span<const std::uint32_t> samples, float* out) const {
  std::array<double, kChannels + 1> sum{};
  const std::size_t at = Index(x, y);
  for (int qy = y - margin_; qy <= y + margin_; ++qy)
    for (int qx = x - margin_; qx <= x + margin_; ++qx) {
      if (qx < source_.x || qy < source_.y || qx >= source_.x_end() || qy >= source_.y_end()) continue;
      const std::uint32_t n = samples[static_cast<std::size_t>(qy - source_.y) * source_.width + (qx - source_.x)];
      if (n == 0) continue;
      const Slot& slot = slots_[at + static_cast<std::size_t>(qy - y + margin_) * side_ + (qx - x + margin_)];
      const double share = 1.0 / n;
      for (int c = 0; c <= kChannels; ++c) sum[c] += slot[c] * share;
    }
  const double expected = expected_x_[x - tile_.x] * expected_y_[y - tile_.y];
  const double weight = std::max(sum[kChannels], kMinWeightShare * expected);
  for (int c = 0; c < kChannels; ++c) out[c] = static_cast<float>(sum[c] / weight);
}

}  // namespace farm
