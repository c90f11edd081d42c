#include "sampling/alias_table.h"

#include <algorithm>
#include <stdexcept>

#include "math/math.h"

namespace farm {

AliasTable::AliasTable(std::span<const float> weights) : bins_(weights.size()), pmf_(weights.size()) {
  double total = 0;
  for (float w : weights) total += w;
  if (weights.empty() || !(total > 0)) throw std::invalid_argument("AliasTable: no weight");
  const std::size_t n = weights.size();
  // Scaled so that a bin holds 1: items below 1 are topped up by aliases to items above.
  std::vector<double> scaled(n);
  std::vector<int> small, large;
  for (std::size_t i = 0; i < n; ++i) {
    pmf_[i] = static_cast<float>(weights[i] / total);
    scaled[i] = weights[i] / total * n;
    (scaled[i] < 1 ? small : large).push_back(static_cast<int>(i));
  }
  while (!small.empty() && !large.empty()) {
    const int s = small.back(), l = large.back();
    small.pop_back();
    bins_[s] = {static_cast<float>(scaled[s]), l};
    scaled[l] -= 1 - scaled[s];
    if (scaled[l] < 1) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // What is left holds 1 up to rounding: its own item always.
  for (int i : small) bins_[i] = {1, i};
  for (int i : large) bins_[i] = {1, i};
}

AliasTable::Choice AliasTable::Sample(float u) const {
  const float scaled = u * static_cast<float>(bins_.size());
  const int bin = std::min(static_cast<int>(scaled), size() - 1);
  const float within = scaled - static_cast<float>(bin);
  const int index = within < bins_[bin].keep ? bin : bins_[bin].alias;
  return {index, pmf_[index]};
}

}  // namespace farm
