#include "media/henyey_greenstein.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include "math/math.h"
#include "media/test_quadrature.h"

namespace farm {
namespace {

constexpr std::array<float, 7> kGs = {-0.999f, -0.7f, -0.2f, 0.0f, 0.3f, 0.8f, 0.999f};

// The integral of f(cos theta) over the sphere, 2 pi times that over cos theta in [-1, 1],
// taken as c = 1 - e^y on [0, 1] and c = -1 + e^y on [-1, 0] (y from -40 to 0): the
// lobes of |g| = 0.999 peak over (1 - g)^2 / 2g ~ 5e-7 of cos theta at either end, which
// a grid in y resolves and a grid in c would not.
double OverTheSphere(const std::function<double(double)>& f) {
  const auto half = [&](double end) {
    return testing::Simpson([&](double y) { return f(end - std::copysign(std::exp(y), end)) * std::exp(y); }, -40, 0);
  };
  return 2 * std::numbers::pi * (half(1) + half(-1));
}

// The function takes cos theta as a float, whose spacing near +-1 (6e-8) is a tenth of the
// 0.999 lobes' width: rounding the quadrature's points moves their integrals by ~1e-3.
double Tolerance(float g) { return std::abs(g) > 0.99f ? 2e-3 : 1e-4; }

TEST(HenyeyGreenstein, IntegratesToOne) {
  for (const float g : kGs) {
    const double mass = OverTheSphere([g](double c) { return HenyeyGreenstein(float(c), g); });
    EXPECT_NEAR(mass, 1.0, Tolerance(g)) << "g=" << g;
  }
}

// The mean cosine of the scattering angle is g (what makes g the asymmetry).
TEST(HenyeyGreenstein, MeanCosineIsG) {
  for (const float g : kGs) {
    const double mean = OverTheSphere([g](double c) { return c * HenyeyGreenstein(float(c), g); });
    EXPECT_NEAR(mean, g, Tolerance(g)) << "g=" << g;
  }
}

// Samples: each one's pdf is the function at it (where the lobe is wider than the float
// rounding of a direction's cosine: |g| <= 0.8), and a histogram of cos theta over 20
// bins matches the function's integral over each bin (the closed-form CDF,
// (1 - g^2) / (2 g) (1 / sqrt(1 + g^2 - 2 g c) - 1 / (1 + g))), within 5 standard
// deviations of a binomial count.
TEST(HenyeyGreenstein, SamplingMatchesEvaluation) {
  const Vec3 wo = Normalize(Vec3(0.3f, -0.5f, 0.8f));
  std::mt19937 rng(1998);
  std::uniform_real_distribution<float> u(0, 1);
  constexpr int kBins = 20, kSamples = 400000;
  for (const float g : kGs) {
    const auto cdf = [g](double c) {
      if (g == 0) return (c + 1) / 2;
      const double gd = g;
      return (1 - gd * gd) / (2 * gd) * (1 / std::sqrt(1 + gd * gd - 2 * gd * c) - 1 / (1 + gd));
    };
    std::array<int, kBins> counts{};
    for (int i = 0; i < kSamples; ++i) {
      const PhaseSample s = SampleHenyeyGreenstein(wo, g, {u(rng), u(rng)});
      ASSERT_NEAR(Length(s.wi), 1.0f, 1e-5f);
      if (std::abs(g) <= 0.8f) {
        ASSERT_NEAR(s.pdf / HenyeyGreenstein(wo, s.wi, g), 1.0f, 2e-3f) << "g=" << g;
      }
      const double c = std::clamp(double(Dot(-s.wi, wo)), -1.0, 1.0);
      ++counts[std::min(kBins - 1, int((c + 1) / 2 * kBins))];
    }
    EXPECT_NEAR(cdf(1), 1.0, 1e-9) << "g=" << g;
    for (int b = 0; b < kBins; ++b) {
      const double p = cdf(-1 + 2.0 * (b + 1) / kBins) - cdf(-1 + 2.0 * b / kBins);
      const double sigma = std::sqrt(kSamples * p * (1 - p));
      EXPECT_NEAR(counts[b], kSamples * p, 5 * sigma + 1) << "g=" << g << " bin " << b;
    }
  }
}

TEST(HenyeyGreenstein, ForwardMeansAlongTheLight) {
  const Vec3 wo(0, 0, 1);
  // Light arriving along +z (from wi = -z) going on to +z is unscattered: the peak for g > 0.
  EXPECT_GT(HenyeyGreenstein(wo, Vec3(0, 0, -1), 0.8f), HenyeyGreenstein(wo, Vec3(0, 0, 1), 0.8f));
  EXPECT_NEAR(HenyeyGreenstein(wo, Vec3(1, 0, 0), 0), kInv4Pi, 1e-7f);
}

}  // namespace
}  // namespace farm
