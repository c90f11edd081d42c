#include "sampling/alias_table.h"

#include <algorithm>

namespace farm {

AliasTable::AliasTable(std::span<const float> weights) {
  const std::size_t n = weights.size();
  if (n == 0) return;
  for (float w : weights) total_ += w;
  pmf_.resize(n);
  bins_.resize(n);
  // Vose's construction in double: each bin holds 1 / n of probability, filled first by its
  // own item and topped up from one item that has more than 1 / n left.
  std::vector<double> scaled(n);
  std::vector<int> small, large;
  for (std::size_t i = 0; i < n; ++i) {
    const double p = total_ > 0 ? weights[i] / total_ : 1.0 / n;
    pmf_[i] = static_cast<float>(p);
    scaled[i] = p * n;
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
  // What is left holds its bin whole, up to rounding.
  for (int i : small) bins_[i] = {1, i};
  for (int i : large) bins_[i] = {1, i};
}

int AliasTable::Sample(float u) const {
  const double x = double(u) * bins_.size();
  const int i = std::min(static_cast<int>(x), size() - 1);
  const Bin& bin = bins_[i];
  return x - i < bin.keep ? i : bin.alias;
}

}  // namespace farm
