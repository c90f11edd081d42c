#pragma once

// Walker's alias method: picks index i with probability weights[i] / sum in constant time
// (one bin chosen by u, then the bin's own item or its alias), where DiscreteDistribution
// searches its cumulative table. For choices among many items made very often: caustic
// photons choosing among thousands of specular shapes (scene/caustic_targets.h).

#include <span>
#include <vector>

namespace farm {

class AliasTable {
 public:
  AliasTable() = default;
  // Weights must be finite and >= 0. If they sum to zero, all items are equally likely.
  explicit AliasTable(std::span<const float> weights);

  // u in [0, 1); the table must not be empty.
  int Sample(float u) const;
  float Pmf(int index) const { return pmf_[index]; }

  int size() const { return static_cast<int>(pmf_.size()); }
  // Sum of the weights given (before normalisation).
  double total() const { return total_; }

 private:
  struct Bin {
    float keep = 1;  // the share of the bin that picks the bin's own item; the rest picks alias
    int alias = 0;
  };
  std::vector<Bin> bins_;
  std::vector<float> pmf_;
  double total_ = 0;
};

}  // namespace farm
