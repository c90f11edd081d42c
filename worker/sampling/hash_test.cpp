#include "sampling/hash.h"

#include <gtest/gtest.h>

#include <bit>
#include <set>

namespace farm {
namespace {

TEST(Hash, DependsOnEveryArgumentAndItsOrder) {
  EXPECT_NE(Hash(1, 2, 3), Hash(1, 2, 4));
  EXPECT_NE(Hash(1, 2, 3), Hash(2, 1, 3));
  EXPECT_NE(Hash(0), Hash(0, 0));
  EXPECT_EQ(Hash(7, 8), Hash(7, 8));
}

TEST(Hash, MixBitsAvalanches) {
  // Flipping one input bit flips about half of the output bits, on average.
  double total = 0;
  int count = 0;
  for (uint64_t v = 1; v < 200; ++v)
    for (int bit = 0; bit < 64; ++bit, ++count)
      total += std::popcount(MixBits(v) ^ MixBits(v ^ (uint64_t(1) << bit)));
  EXPECT_NEAR(total / count, 32.0, 0.5);
}

TEST(Hash, SequentialInputsDoNotCollide) {
  std::set<uint64_t> seen;
  for (uint64_t pixel = 0; pixel < 10000; ++pixel) seen.insert(Hash(42, pixel, 0));
  EXPECT_EQ(seen.size(), 10000u);
}

}  // namespace
}  // namespace farm
