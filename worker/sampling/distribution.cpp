#include "sampling/distribution.h"

#include <algorithm>
#include <cstdio>

#include "math/math.h"

namespace farm {

DiscreteDistribution::DiscreteDistribution(std::span<const float> weights) {
  const std::size_t n = weights.size();
  if (n == 0) return;
  // Accumulate in double: a mesh light with a million triangles would otherwise lose the
  // small ones to rounding.
  for (float w : weights) total_ += w;
  pmf_.resize(n);
  cdf_.resize(n + 1);
  cdf_[0] = 0;
  double running = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = total_ > 0 ? weights[i] / total_ : 1.0 / n;
    pmf_[i] = static_cast<float>(w);
    running += w;
    cdf_[i + 1] = running;
  }
  for (std::size_t i = 0; i <= n; ++i) cdf_[i] /= running;
  cdf_[n] = 1;
}

DiscreteDistribution::Choice DiscreteDistribution::Sample(float u) const {
  // First i with cdf_[i + 1] > u, skipping zero-weight items (their intervals are empty).
  const auto it = std::upper_bound(cdf_.begin() + 1, cdf_.end(), double(u));
  int index = static_cast<int>(it - cdf_.begin()) - 1;
  index = std::clamp(index, 0, size() - 1);
  while (pmf_[index] == 0 && index > 0) --index;  // u == 1 - eps at a trailing zero weight
  const double width = cdf_[index + 1] - cdf_[index];
  float remapped = width > 0 ? static_cast<float>((u - cdf_[index]) / width) : 0.0f;
  remapped = std::clamp(remapped, 0.0f, kOneMinusEpsilon);
  return {index, pmf_[index], remapped};
}

float DiscreteDistribution::Pmf(int index) const {
  return index >= 0 && index < size() ? pmf_[index] : 0.0f;
}

std::string DiscreteDistribution::ToString() const {
  std::string s = "DiscreteDistribution{total=" + std::to_string(total_) + ", pmf=[";
  for (int i = 0; i < size() && i < 16; ++i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s%.6g", i ? ", " : "", double(pmf_[i]));
    s += buf;
  }
  if (size() > 16) s += ", ...";
  return s + "]}";
}

}  // namespace farm
