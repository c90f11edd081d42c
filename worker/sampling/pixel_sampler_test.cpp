#include "sampling/pixel_sampler.h"

#include <gtest/gtest.h>

#include <vector>

namespace farm {
namespace {

TEST(PixelSampler, DependsOnlyOnSeedPixelSampleAndDimension) {
  PixelSampler a(16, 7), b(16, 7);
  // b visits other pixels and dimensions first: a's numbers must not change.
  b.StartPixelSample(99, 3);
  b.Get2D();
  b.Get1D();
  a.StartPixelSample(5, 11);
  b.StartPixelSample(5, 11);
  for (int d = 0; d < 5; ++d) {
    EXPECT_EQ(a.Get2D(), b.Get2D()) << a.ToString();
    EXPECT_EQ(a.Get1D(), b.Get1D()) << a.ToString();
  }
}

TEST(PixelSampler, DifferentSeedsGiveDifferentSamples) {
  PixelSampler a(16, 1), b(16, 2);
  int different = 0;
  for (uint32_t s = 0; s < 16; ++s) {
    a.StartPixelSample(0, s);
    b.StartPixelSample(0, s);
    different += !(a.Get2D() == b.Get2D());
  }
  EXPECT_GT(different, 12);
}

TEST(PixelSampler, EachDimensionPairIsStratifiedWithinAPixel) {
  constexpr int kSpp = 64;  // 8x8 cells, and 64x1, 1x64, ... elementary intervals
  PixelSampler sampler(kSpp, 2024);
  for (int pair = 0; pair < 4; ++pair) {
    for (int a = 0; a <= 6; ++a) {
      const int nx = 1 << a, ny = 1 << (6 - a);
      std::vector<int> count(kSpp, 0);
      for (uint32_t s = 0; s < kSpp; ++s) {
        sampler.StartPixelSample(1234, s);
        Vec2 u;
        for (int p = 0; p <= pair; ++p) u = sampler.Get2D();
        ++count[int(u.y * ny) * nx + int(u.x * nx)];
      }
      for (int c : count) ASSERT_EQ(c, 1) << "pair " << pair << " a " << a;
    }
  }
}

TEST(PixelSampler, PairsAreDecorrelated) {
  // The first and second pairs of one sample should not repeat each other.
  PixelSampler sampler(16, 3);
  int same = 0;
  for (uint32_t s = 0; s < 16; ++s) {
    sampler.StartPixelSample(8, s);
    const Vec2 first = sampler.Get2D(), second = sampler.Get2D();
    same += first == second;
  }
  EXPECT_EQ(same, 0);
}

TEST(PixelSampler, OneDimensionalMeanIsOneHalf) {
  PixelSampler sampler(256, 9);
  double sum = 0;
  for (uint32_t s = 0; s < 256; ++s) {
    sampler.StartPixelSample(77, s);
    sampler.Get2D();
    sum += sampler.Get1D();
  }
  EXPECT_NEAR(sum / 256, 0.5, 1e-2);
}

}  // namespace
}  // namespace farm
