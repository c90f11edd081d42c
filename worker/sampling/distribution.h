#pragma once

// A discrete distribution over n items with given nonnegative weights, sampled by inverting
// its CDF: picks lights in proportion to power and mesh-light triangles in proportion to
// area.

#include <span>
#include <string>
#include <vector>

namespace farm {

class DiscreteDistribution {
 public:
  DiscreteDistribution() = default;
  // Weights must be finite and >= 0. If they sum to zero, all items are equally likely.
  explicit DiscreteDistribution(std::span<const float> weights);

  struct Choice {
    int index = 0;
    float pmf = 0;
    // u rescaled to [0, 1) within the chosen item's CDF interval, so that one uniform number
    // can drive a second, dependent choice without losing its stratification.
    float u_remapped = 0;
  };

  // u in [0, 1); the distribution must not be empty.
  Choice Sample(float u) const;
  float Pmf(int index) const;

  int size() const { return static_cast<int>(pmf_.size()); }
  bool empty() const { return pmf_.empty(); }
  // Sum of the weights given (before normalisation).
  double total() const { return total_; }

  std::string ToString() const;

 private:
  std::vector<float> pmf_;
  std::vector<double> cdf_;  // n + 1 entries, cdf_[0] = 0, cdf_[n] = 1
  double total_ = 0;
};

}  // namespace farm
