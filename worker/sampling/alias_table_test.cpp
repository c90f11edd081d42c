// The alias table against the weights it was built from: exact pmfs, frequencies within
// their statistical bounds, and zero weights never picked.

#include "sampling/alias_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace farm {
namespace {

TEST(AliasTable, PicksEachItemInProportionToItsWeight) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> weight(0, 1);
  std::vector<float> weights(1000);
  for (float& w : weights) w = weight(rng) * weight(rng) * weight(rng);  // skewed
  weights[7] = 0;
  weights[500] = 50;  // one item far above the rest
  double total = 0;
  for (float w : weights) total += w;
  const AliasTable table(weights);
  const int n = 4'000'000;
  std::vector<int> count(weights.size());
  std::uniform_real_distribution<float> u(0, 1);
  for (int i = 0; i < n; ++i) {
    const AliasTable::Choice c = table.Sample(u(rng));
    ASSERT_EQ(c.pmf, table.Pmf(c.index));
    ++count[c.index];
  }
  for (std::size_t i = 0; i < weights.size(); ++i) {
    const double p = weights[i] / total;
    EXPECT_NEAR(table.Pmf(static_cast<int>(i)), p, 1e-6 * p + 1e-12);
    EXPECT_NEAR(count[i] / double(n), p, 5 * std::sqrt(p * (1 - p) / n) + 1e-7) << "item " << i;
  }
  EXPECT_EQ(count[7], 0);
}

TEST(AliasTable, OneItemAndTheEdgesOfU) {
  const std::vector<float> one{2.5f};
  const AliasTable single(one);
  EXPECT_EQ(single.Sample(0).index, 0);
  EXPECT_EQ(single.Sample(0.99999994f).index, 0);
  EXPECT_EQ(single.Sample(0.5f).pmf, 1.0f);
  const std::vector<float> last_zero{1, 1, 0};
  const AliasTable table(last_zero);
  EXPECT_NE(table.Sample(0.99999994f).index, 2);
  EXPECT_NE(table.Sample(0).index, 2);
  EXPECT_THROW(AliasTable(std::vector<float>{0, 0}), std::invalid_argument);
  EXPECT_THROW(AliasTable(std::vector<float>{}), std::invalid_argument);
}

}  // namespace
}  // namespace farm
