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
  for (int d = -margin_; d <= margin_; ++d) over_pixel_.push_back(filter.Integral(d - 0.5, d + 0.5));
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

void FilterSplats::AddSource(int x, int y, int qx, int qy, const Source& q,
                             std::array<double, kChannels + 1>& sum) const {
  if (q.samples == 0) return;
  const double share = 1.0 / q.samples;
  if (q.by_position) {
    const Slot& slot = slots_[Index(x, y) + static_cast<std::size_t>(qy - y + margin_) * side_ + (qx - x + margin_)];
    for (int c = 0; c <= kChannels; ++c) sum[c] += slot[c] * share;
    return;
  }
  const double weight = over_pixel_[qx - x + margin_] * over_pixel_[qy - y + margin_];
  for (int c = 0; c < kChannels; ++c) sum[c] += weight * (q.light_sums[c] * share);
  sum[kChannels] += weight;
}

void FilterSplats::Finish(int x, int y, const std::array<double, kChannels + 1>& sum, float* out) const {
  const double expected = expected_x_[x - tile_.x] * expected_y_[y - tile_.y];
  const double weight = std::max(sum[kChannels], kMinWeightShare * expected);
  for (int c = 0; c < kChannels; ++c) out[c] = static_cast<float>(sum[c] / weight);
}

}  // namespace farm
