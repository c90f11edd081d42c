#include "sampling/distribution.h"

#include <gtest/gtest.h>

#include <vector>

namespace farm {
namespace {

TEST(DiscreteDistribution, PicksInProportionToWeight) {
  const std::vector<float> w = {1, 0, 3, 4};
  const DiscreteDistribution d(w);
  SCOPED_TRACE(d.ToString());
  EXPECT_FLOAT_EQ(d.Pmf(0), 0.125f);
  EXPECT_FLOAT_EQ(d.Pmf(1), 0);
  EXPECT_FLOAT_EQ(d.Pmf(2), 0.375f);
  EXPECT_DOUBLE_EQ(d.total(), 8);
  std::vector<int> count(4, 0);
  const int n = 8000;
  for (int i = 0; i < n; ++i) {
    const auto c = d.Sample((i + 0.5f) / n);
    ++count[c.index];
    EXPECT_EQ(c.pmf, d.Pmf(c.index));
    EXPECT_GE(c.u_remapped, 0);
    EXPECT_LT(c.u_remapped, 1);
  }
  EXPECT_EQ(count[0], 1000);
  EXPECT_EQ(count[1], 0);
  EXPECT_EQ(count[2], 3000);
  EXPECT_EQ(count[3], 4000);
}

TEST(DiscreteDistribution, RemapsUWithinTheChosenInterval) {
  const std::vector<float> w = {1, 1};
  const DiscreteDistribution d(w);
  const auto c = d.Sample(0.75f);
  EXPECT_EQ(c.index, 1);
  EXPECT_FLOAT_EQ(c.u_remapped, 0.5f);
}

TEST(DiscreteDistribution, TrailingZeroWeightIsNeverChosen) {
  const std::vector<float> w = {1, 0};
  EXPECT_EQ(DiscreteDistribution(w).Sample(0.99999994f).index, 0);
}

TEST(DiscreteDistribution, AllZeroWeightsAreUniform) {
  const std::vector<float> w = {0, 0};
  const DiscreteDistribution d(w);
  EXPECT_FLOAT_EQ(d.Pmf(0), 0.5f);
  EXPECT_EQ(d.Sample(0.7f).index, 1);
}

}  // namespace
}  // namespace farm
