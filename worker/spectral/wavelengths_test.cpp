#include "spectral/wavelengths.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace farm {
namespace {

// Every wavelength lies in the range, and the four are a quarter of it apart (modulo its
// length): the rotation that stratifies them.
TEST(Wavelengths, HeroAndCompanionsAreEvenlySpacedAndWrapped) {
  constexpr double range = kLambdaMax - kLambdaMin;
  for (double u : {0.0, 0.1, 0.26, 0.5, 0.75, 0.999999}) {
    const SampledWavelengths w = SampleWavelengths(u);
    EXPECT_DOUBLE_EQ(w.pdf, 1 / range);
    EXPECT_NEAR(w.lambda[0], kLambdaMin + u * range, 1e-9);
    for (int i = 0; i < kWavelengthsPerPath; ++i) {
      EXPECT_GE(w.lambda[i], kLambdaMin) << u;
      EXPECT_LT(w.lambda[i], kLambdaMax) << u;
      double gap = w.lambda[i] - w.lambda[0];
      if (gap < 0) gap += range;
      EXPECT_NEAR(gap, i * range / kWavelengthsPerPath, 1e-9) << u << " " << i;
    }
  }
}

// Over stratified u the wavelengths fill the range uniformly: each of 47 bins of 10 nm gets
// the same count.
TEST(Wavelengths, StratifiedHerosCoverTheRangeUniformly) {
  constexpr int n = 47 * 100;
  std::array<int, 47> bins{};
  for (int k = 0; k < n; ++k) {
    for (double l : SampleWavelengths((k + 0.5) / n).lambda) ++bins[static_cast<size_t>((l - kLambdaMin) / 10)];
  }
  for (int count : bins) EXPECT_EQ(count, n * kWavelengthsPerPath / 47);
}

}  // namespace
}  // namespace farm
