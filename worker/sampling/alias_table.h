#pragma once

// A discrete distribution sampled in constant time (Walker's alias method, built by Vose's
// algorithm): one table entry read per sample whatever the number of items, where
// DiscreteDistribution's inverted CDF reads a binary search's worth. For items picked per
// photon among very many (the caustic targets of a sun or the environment).

#include <cstdint>
#include <span>
#include <vector>

namespace farm {

class AliasTable {
 public:
  AliasTable() = default;
  // Weights must be finite and >= 0, not all zero.
  explicit AliasTable(std::span<const float> weights);

  struct Choice {
    int index = 0;
    float pmf = 0;
  };
  // u in [0, 1); the table must not be empty.
  Choice Sample(float u) const;
  float Pmf(int index) const { return pmf_[index]; }
  int size() const { return static_cast<int>(pmf_.size()); }

 private:
  struct Bin {
    float keep = 1;  // probability of the bin's own item; else its alias
    int alias = 0;
  };
  std::vector<Bin> bins_;
  std::vector<float> pmf_;
};

}  // namespace farm
