#include "sampling/distribution_2d.h"

#include <algorithm>
#include <stdexcept>

#include "math/math.h"

namespace farm {

Distribution2D::Distribution2D(std::span<const float> weights, int width, int height)
    : width_(width), height_(height) {
  if (width <= 0 || height <= 0 || weights.size() != std::size_t(width) * std::size_t(height))
    throw std::invalid_argument("Distribution2D: " + std::to_string(weights.size()) + " weights for a " +
                                std::to_string(width) + "x" + std::to_string(height) + " grid");
  std::vector<float> row_sums(height);
  columns_.reserve(height);
  for (int y = 0; y < height; ++y) {
    const std::span<const float> row = weights.subspan(std::size_t(y) * width, width);
    double sum = 0;
    for (float w : row) sum += w;
    row_sums[y] = static_cast<float>(sum);
    columns_.emplace_back(row);
  }
  rows_ = DiscreteDistribution(row_sums);
}

Distribution2D::Sample Distribution2D::Draw(Vec2 u) const {
  const DiscreteDistribution::Choice row = rows_.Sample(u.y);
  const DiscreteDistribution::Choice column = columns_[row.index].Sample(u.x);
  const Vec2 uv{std::min((column.index + column.u_remapped) / width_, kOneMinusEpsilon),
                std::min((row.index + row.u_remapped) / height_, kOneMinusEpsilon)};
  return {uv, row.pmf * column.pmf * float(width_) * float(height_)};
}

float Distribution2D::Pdf(Vec2 uv) const {
  if (columns_.empty()) return 0;
  const int x = std::clamp(int(uv.x * width_), 0, width_ - 1);
  const int y = std::clamp(int(uv.y * height_), 0, height_ - 1);
  return rows_.Pmf(y) * columns_[y].Pmf(x) * float(width_) * float(height_);
}

std::string Distribution2D::ToString() const {
  return "Distribution2D{" + std::to_string(width_) + "x" + std::to_string(height_) +
         ", rows=" + rows_.ToString() + "}";
}

}  // namespace farm
