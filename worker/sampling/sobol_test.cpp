#include "sampling/sobol.h"

#include <gtest/gtest.h>

#include <set>
#include <vector>

namespace farm {
namespace {

// Each elementary interval of area 2^-k (2^a by 2^(k-a) cells) holds exactly one of the
// 2^k points: the defining property of a (0,k,2)-net in base 2.
bool IsZeroNet(const std::vector<std::pair<float, float>>& points, int k) {
  for (int a = 0; a <= k; ++a) {
    const int nx = 1 << a, ny = 1 << (k - a);
    std::vector<int> count(std::size_t(nx) * ny, 0);
    for (auto [x, y] : points) ++count[std::size_t(int(y * ny)) * nx + int(x * nx)];
    for (int c : count)
      if (c != 1) return false;
  }
  return true;
}

TEST(Sobol, UnscrambledFirstPointsAreTheKnownSequence) {
  // Dimension 0: 0, 1/2, 1/4, 3/4; dimension 1: 0, 1/2, 3/4, 1/4 (Joe and Kuo's tables).
  const float d0[] = {0, 0.5f, 0.25f, 0.75f}, d1[] = {0, 0.5f, 0.75f, 0.25f};
  for (uint32_t i = 0; i < 4; ++i) {
    EXPECT_EQ(FractionToFloat(SobolBits(i, 0)), d0[i]) << i;
    EXPECT_EQ(FractionToFloat(SobolBits(i, 1)), d1[i]) << i;
  }
}

TEST(Sobol, ScrambledPointsStayStratified) {
  for (uint32_t seed : {0u, 1u, 0xdeadbeefu, 123456789u}) {
    for (int k : {2, 4, 6, 8, 10}) {
      std::vector<std::pair<float, float>> pts;
      for (uint32_t i = 0; i < (1u << k); ++i)
        pts.emplace_back(SobolSample(i, 0, seed), SobolSample(i, 1, seed ^ 0x9e3779b9u));
      EXPECT_TRUE(IsZeroNet(pts, k)) << "seed " << seed << " k " << k;
    }
  }
}

TEST(Sobol, MeanIsOneHalf) {
  for (int dim : {0, 1}) {
    double sum = 0;
    const int n = 1 << 12;
    for (int i = 0; i < n; ++i) sum += SobolSample(i, dim, 77);
    EXPECT_NEAR(sum / n, 0.5, 1e-3) << "dim " << dim;
  }
}

TEST(Sobol, ScramblesDifferBySeed) {
  int different = 0;
  for (uint32_t i = 0; i < 64; ++i) different += SobolSample(i, 0, 1) != SobolSample(i, 0, 2);
  EXPECT_GT(different, 56);
  // ...and are deterministic.
  EXPECT_EQ(SobolSample(5, 1, 99), SobolSample(5, 1, 99));
}

TEST(Sobol, SamplesStayBelowOne) {
  EXPECT_LT(FractionToFloat(0xffffffffu), 1.0f);
  EXPECT_EQ(FractionToFloat(0), 0.0f);
}

TEST(PermutationElement, IsAPermutationForAnyLength) {
  for (uint32_t n : {1u, 2u, 7u, 16u, 100u, 1000u}) {
    for (uint32_t seed : {0u, 5u, 0xabcdef12u}) {
      std::set<uint32_t> seen;
      for (uint32_t i = 0; i < n; ++i) {
        const uint32_t p = PermutationElement(i, n, seed);
        EXPECT_LT(p, n);
        seen.insert(p);
      }
      EXPECT_EQ(seen.size(), n) << "n " << n << " seed " << seed;
    }
  }
  // Different seeds shuffle differently.
  int moved = 0;
  for (uint32_t i = 0; i < 64; ++i) moved += PermutationElement(i, 64, 1) != PermutationElement(i, 64, 2);
  EXPECT_GT(moved, 48);
}

}  // namespace
}  // namespace farm
