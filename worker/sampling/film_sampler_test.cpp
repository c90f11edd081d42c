#include "sampling/film_sampler.h"

#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "sampling/sobol.h"

namespace farm {
namespace {

struct Point {
  double x, y;  // in units of the square's side
};

// Each elementary interval of area 2^-m (2^a by 2^(m-a) cells of the unit square) holds
// exactly one of the 2^m points: a (0,m,2)-net in base 2.
bool IsZeroNet(const std::vector<Point>& points, int m) {
  if (points.size() != (std::size_t(1) << m)) return false;
  for (int a = 0; a <= m; ++a) {
    const int nx = 1 << a, ny = 1 << (m - a);
    std::vector<int> count(std::size_t(nx) * ny, 0);
    for (const Point& p : points) ++count[std::size_t(int(p.y * ny)) * nx + int(p.x * nx)];
    for (int c : count)
      if (c != 1) return false;
  }
  return true;
}

// Samples 0..n-1 of every pixel of a 2^k square image, in the unit square.
std::vector<Point> AllSamples(const FilmSampler& sampler, int n, std::uint64_t seed) {
  const int side = 1 << sampler.resolution_bits();
  std::vector<Point> points;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
      for (int j = 0; j < n; ++j) {
        const Vec2 u = sampler.Sample(x, y, j, seed);
        points.push_back({(x + double(u.x)) / side, (y + double(u.y)) / side});
      }
  return points;
}

TEST(FilmSampler, CoversTheImageWithTheSmallestSquare) {
  EXPECT_EQ(FilmSampler(1, 1).resolution_bits(), 0);
  EXPECT_EQ(FilmSampler(2, 1).resolution_bits(), 1);
  EXPECT_EQ(FilmSampler(5, 3).resolution_bits(), 3);
  EXPECT_EQ(FilmSampler(512, 512).resolution_bits(), 9);
  EXPECT_EQ(FilmSampler(300, 513).resolution_bits(), 10);
  EXPECT_THROW(FilmSampler(0, 4), std::invalid_argument);
  EXPECT_THROW(FilmSampler(4, 70000), std::invalid_argument);
}

TEST(FilmSampler, SobolBits64ExtendsTheThirtyTwoBitSequence) {
  for (std::uint32_t i : {0u, 1u, 2u, 3u, 77u, 123456u, 0xffffffffu})
    for (int dim : {0, 1}) EXPECT_EQ(std::uint32_t(SobolBits64(i, dim) >> 32), SobolBits(i, dim)) << i << " " << dim;
}

// Brute force: of the 4^k points of block j, the one that lands in pixel (x, y) (its top k
// bits of x and y) is the one SequenceIndex names, for every pixel and block.
TEST(FilmSampler, SequenceIndexIsThePointOfTheBlockInThePixel) {
  for (int k : {0, 1, 2, 3, 5}) {
    const FilmSampler sampler(1 << k, 1 << k);
    const std::uint64_t block = std::uint64_t(1) << (2 * k);
    for (std::uint32_t j : {0u, 1u, 2u, 7u, 12u, 1000u}) {
      std::map<std::pair<int, int>, std::uint64_t> landing;
      for (std::uint64_t i = j * block; i < (j + 1) * block; ++i) {
        const auto top = [k](std::uint64_t f) { return k == 0 ? 0 : int(f >> (64 - k)); };
        ASSERT_TRUE(landing.emplace(std::pair{top(SobolBits64(i, 0)), top(SobolBits64(i, 1))}, i).second)
            << "two points of block " << j << " in one pixel, k " << k;
      }
      for (const auto& [pixel, index] : landing)
        ASSERT_EQ(sampler.SequenceIndex(pixel.first, pixel.second, j), index)
            << "pixel " << pixel.first << "," << pixel.second << " block " << j << " k " << k;
    }
  }
}

// The samples 0..n-1 of all pixels together, scrambled, are a (0, 2k + log2 n, 2)-net over
// the image: stratified across pixels, not only within each.
TEST(FilmSampler, AllPixelsSamplesTogetherAreANetOverTheImage) {
  for (std::uint64_t seed : {1ull, 2ull, 0xdeadbeefull})
    for (int k : {0, 1, 3, 4})
      for (int log_n : {0, 1, 2, 4}) {
        const FilmSampler sampler(1 << k, 1 << k);
        EXPECT_TRUE(IsZeroNet(AllSamples(sampler, 1 << log_n, seed), 2 * k + log_n))
            << sampler.ToString() << " n " << (1 << log_n) << " seed " << seed;
      }
}

// So a row of pixels holds its share of samples in every horizontal band finer than a
// pixel: with 4 samples a pixel, an aligned run of 8 pixels in a row has exactly one sample
// in each band 1/32 of a pixel tall. Independent per-pixel sets would not.
TEST(FilmSampler, AnAlignedRunOfPixelsIsStratifiedAcrossThePixels) {
  const FilmSampler sampler(64, 64);
  for (std::uint64_t seed : {3ull, 4ull})
    for (int row : {0, 17, 40})
      for (int start : {0, 8, 48}) {
        std::vector<int> bands(32, 0);
        for (int x = start; x < start + 8; ++x)
          for (std::uint32_t j = 0; j < 4; ++j) ++bands[int(sampler.Sample(x, row, j, seed).y * 32)];
        for (int count : bands) ASSERT_EQ(count, 1) << "row " << row << " start " << start << " seed " << seed;
      }
}

// Each pixel's own first n samples are a (0, log2 n, 2)-net within it, as the per-pixel
// sampler's were: the box filter's estimate of a pixel keeps its stratification.
TEST(FilmSampler, EachPixelsOwnSamplesAreANetWithinIt) {
  const FilmSampler sampler(300, 200);
  for (std::uint64_t seed : {5ull, 6ull})
    for (auto [x, y] : {std::pair{0, 0}, {1, 0}, {17, 93}, {299, 199}, {128, 64}})
      for (int log_n : {1, 3, 6}) {
        std::vector<Point> points;
        for (std::uint32_t j = 0; j < (1u << log_n); ++j) {
          const Vec2 u = sampler.Sample(x, y, j, seed);
          points.push_back({u.x, u.y});
        }
        EXPECT_TRUE(IsZeroNet(points, log_n)) << "pixel " << x << "," << y << " n " << (1 << log_n);
      }
}

// A pixel's samples do not depend on the image beyond the square it fixes: a 5x3 image's
// pixels sample as the same pixels of an 8x8 one.
TEST(FilmSampler, DependsOnlyOnTheSquareSeedPixelAndSample) {
  const FilmSampler small(5, 3), square(8, 8);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x)
      for (std::uint32_t j : {0u, 1u, 11u}) EXPECT_EQ(small.Sample(x, y, j, 42), square.Sample(x, y, j, 42));
}

// Scrambling makes each sample uniform over its pixel: over many seeds (rounds) the mean
// and the variance of one sample's offset are those of the uniform distribution, 1/2 and
// 1/12, and the two coordinates are uncorrelated.
TEST(FilmSampler, EachSampleIsUniformOverItsPixelAcrossSeeds) {
  const FilmSampler sampler(512, 512);
  constexpr int kSeeds = 1 << 14;
  for (auto [x, y, j] : {std::tuple{0, 0, 0u}, {200, 311, 0u}, {200, 311, 5u}}) {
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
    for (int s = 0; s < kSeeds; ++s) {
      const Vec2 u = sampler.Sample(x, y, j, s);
      sx += u.x, sy += u.y, sxx += u.x * u.x, syy += u.y * u.y, sxy += u.x * u.y;
    }
    const double mx = sx / kSeeds, my = sy / kSeeds;
    // Standard errors: mean sqrt(1/12 / 16384) = 0.0023, variance about 0.0006.
    EXPECT_NEAR(mx, 0.5, 0.01);
    EXPECT_NEAR(my, 0.5, 0.01);
    EXPECT_NEAR(sxx / kSeeds - mx * mx, 1.0 / 12, 0.003);
    EXPECT_NEAR(syy / kSeeds - my * my, 1.0 / 12, 0.003);
    EXPECT_NEAR(sxy / kSeeds - mx * my, 0.0, 0.003);
  }
}

}  // namespace
}  // namespace farm
