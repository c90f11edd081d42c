#include "sampling/alias_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sampling/hash.h"
#include "sampling/sobol.h"

namespace farm {
namespace {

// Stratified u: the count of each item is its probability times n, within one.
std::vector<int> Counts(const AliasTable& t, int n) {
  std::vector<int> count(t.size(), 0);
  for (int i = 0; i < n; ++i) ++count[t.Sample((i + 0.5f) / n)];
  return count;
}

TEST(AliasTable, PicksInProportionToWeight) {
  const std::vector<float> w = {1, 0, 3, 4};
  const AliasTable t(w);
  EXPECT_FLOAT_EQ(t.Pmf(0), 0.125f);
  EXPECT_FLOAT_EQ(t.Pmf(1), 0);
  EXPECT_FLOAT_EQ(t.Pmf(3), 0.5f);
  EXPECT_DOUBLE_EQ(t.total(), 8);
  const std::vector<int> count = Counts(t, 8000);
  EXPECT_NEAR(count[0], 1000, 1);
  EXPECT_EQ(count[1], 0);
  EXPECT_NEAR(count[2], 3000, 1);
  EXPECT_NEAR(count[3], 4000, 1);
}

TEST(AliasTable, ManyUnevenWeightsArePickedAtTheirProbabilities) {
  std::vector<float> w;
  for (uint64_t i = 0; i < 1000; ++i) {
    const float u = FractionToFloat(static_cast<uint32_t>(Hash(7, i)));
    w.push_back(i % 10 == 0 ? 0 : std::pow(u, 4) * 100);  // zeros and a long tail
  }
  const AliasTable t(w);
  const int n = 4'000'000;
  const std::vector<int> count = Counts(t, n);
  for (int i = 0; i < t.size(); ++i) {
    // Within one for each bin the item fills.
    EXPECT_NEAR(count[i], double(t.Pmf(i)) * n, 2 + t.Pmf(i) * t.size()) << i;
    if (w[i] == 0) {
      EXPECT_EQ(count[i], 0) << i;
    }
  }
}

TEST(AliasTable, AllZeroWeightsAreUniformAndTheTopOfUIsInRange) {
  const std::vector<float> w = {0, 0};
  const AliasTable t(w);
  EXPECT_FLOAT_EQ(t.Pmf(1), 0.5f);
  EXPECT_EQ(t.Sample(0.7f), 1);
  EXPECT_EQ(AliasTable(std::vector<float>{1, 2, 3}).Sample(0.99999994f), 2);
}

}  // namespace
}  // namespace farm
