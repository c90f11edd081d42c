#include "image/sample_allocation.h"

#include <gtest/gtest.h>

#include <numeric>

namespace farm {
namespace {

std::uint64_t Sum(const std::vector<std::uint32_t>& n) { return std::accumulate(n.begin(), n.end(), std::uint64_t{0}); }

// The law: with no history, samples follow sigma, so 4x the variance draws 2x the samples.
TEST(SampleAllocation, FourTimesTheVarianceDrawsTwiceTheSamples) {
  std::vector<double> sigma(1000, 1.0), taken(1000, 0.0);
  for (std::size_t p = 0; p < sigma.size(); p += 2) sigma[p] = 2.0;  // variance 4
  const auto n = AllocateSamples(sigma, taken, {30000, 1, 1000});
  EXPECT_EQ(Sum(n), 30000u);
  // 500 pixels at 2 lambda and 500 at lambda: lambda = 20.
  for (std::size_t p = 0; p < n.size(); ++p) EXPECT_EQ(n[p], p % 2 == 0 ? 40u : 20u) << p;
}

// What a pixel has taken counts: the totals after the round follow sigma, so a pixel
// behind gets more until it catches up.
TEST(SampleAllocation, HistoryIsToppedUpToTotalsProportionalToSigma) {
  const std::vector<double> sigma = {1, 1, 1, 1};
  const std::vector<double> taken = {10, 10, 20, 20};
  const auto n = AllocateSamples(sigma, taken, {40, 1, 100});
  // Totals 25 each: lambda 25.
  EXPECT_EQ(n, (std::vector<std::uint32_t>{15, 15, 5, 5}));
}

// Against brute force: over every integer allocation of the same total within the bounds,
// none has an expected squared error sum sigma^2 / (taken + n) more than 2% below ours
// (ours rounds the continuous optimum).
TEST(SampleAllocation, ComesWithinTwoPercentOfTheBestIntegerAllocation) {
  const std::vector<double> sigma = {0.5, 1, 2, 4, 0.1};
  const std::vector<double> taken = {0, 2, 0, 1, 3};
  const AllocationBudget budget{20, 1, 9};
  const auto error = [&](const std::vector<std::uint32_t>& n) {
    double e = 0;
    for (std::size_t p = 0; p < n.size(); ++p) e += sigma[p] * sigma[p] / (taken[p] + n[p]);
    return e;
  };
  const auto ours = AllocateSamples(sigma, taken, budget);
  ASSERT_EQ(Sum(ours), budget.total);
  double best = 1e300;
  std::vector<std::uint32_t> n(5);
  for (n[0] = 1; n[0] <= 9; ++n[0])
    for (n[1] = 1; n[1] <= 9; ++n[1])
      for (n[2] = 1; n[2] <= 9; ++n[2])
        for (n[3] = 1; n[3] <= 9; ++n[3])
          for (n[4] = 1; n[4] <= 9; ++n[4])
            if (Sum(n) == budget.total) best = std::min(best, error(n));
  EXPECT_LE(error(ours), 1.02 * best);
  EXPECT_GT(ours[3], ours[2]);  // the noisiest pixel is capped at 9 or near it
  EXPECT_EQ(ours[4], 1u);       // the quiet one with history draws the least
}

TEST(SampleAllocation, BoundsHoldAndTheTotalIsClampedToThem) {
  const std::vector<double> sigma = {0, 0, 5, 1000};
  const std::vector<double> taken = {0, 0, 0, 0};
  // The noisy two reach the cap; the rest goes to the pixels of estimate 0, which count as
  // having a thousandth of the mean sigma, not as exact.
  EXPECT_EQ(AllocateSamples(sigma, taken, {50, 1, 16}), (std::vector<std::uint32_t>{9, 9, 16, 16}));
  EXPECT_EQ(AllocateSamples(sigma, taken, {100, 1, 16}), std::vector<std::uint32_t>(4, 16));  // at most 64
  EXPECT_EQ(AllocateSamples(sigma, taken, {2, 1, 16}), std::vector<std::uint32_t>(4, 1));     // at least 4
}

TEST(SampleAllocation, AnImageWithoutNoiseIsSampledEvenly) {
  const std::vector<double> sigma(10, 0.0), taken(10, 3.0);
  EXPECT_EQ(AllocateSamples(sigma, taken, {40, 1, 100}), std::vector<std::uint32_t>(10, 4));
}

}  // namespace
}  // namespace farm
