#include "media/homogeneous_medium.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "media/test_quadrature.h"

namespace farm {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A slab of thickness d crossed at an angle theta from its normal: the path inside is
// d / cos theta, and Beer-Lambert says T = exp(-sigma_t d / cos theta), here in double.
TEST(HomogeneousMedium, SlabTransmittanceIsBeerLambert) {
  const HomogeneousMedium m = HomogeneousMedium::FromCoefficients({0.5f, 0.01f, 2}, {1.5f, 0.09f, 0}, 0.3f);
  for (const double d : {1e-4, 0.3, 1.0, 4.0}) {
    for (const double cos_theta : {1.0, 0.7, 0.2}) {
      const double path = d / cos_theta;
      const Rgb t = m.Transmittance(float(path));
      const double want[3] = {std::exp(-2.0 * path), std::exp(-0.1 * path), std::exp(-2.0 * path)};
      const double got[3] = {t.r, t.g, t.b};
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c] / want[c], 1.0, 1e-6) << "d=" << d << " cos=" << cos_theta << " channel " << c;
    }
  }
}

TEST(HomogeneousMedium, ChannelsWithoutExtinctionKeepEverythingToInfinity) {
  const HomogeneousMedium m = HomogeneousMedium::FromCoefficients({0, 1, 0}, {0, 0, 0}, 0);
  const Rgb t = m.Transmittance(kInf);
  EXPECT_EQ(t, Rgb(1, 0, 1));
  EXPECT_FALSE(m.IsVacuum());
  EXPECT_TRUE(HomogeneousMedium::FromCoefficients({}, {}, 0).IsVacuum());
}

TEST(HomogeneousMedium, AlbedoAndDensitySplitExtinction) {
  const HomogeneousMedium m = HomogeneousMedium::FromAlbedo({1, 0.25f, 0}, 4, -0.5f);
  EXPECT_EQ(m.sigma_s, Rgb(4, 1, 0));
  EXPECT_EQ(m.sigma_a, Rgb(0, 3, 4));
  EXPECT_EQ(m.sigma_t, Rgb(4, 4, 4));
  EXPECT_EQ(m.g, -0.5f);
}

// The free-flight density and the probability of passing t_max add up to 1, and sampled
// distances follow the density: their mean in a grey medium is 1 / sigma_t.
TEST(FreeFlight, DensityAndPassProbabilityAddUpToOne) {
  const HomogeneousMedium m = HomogeneousMedium::FromCoefficients({0.2f, 1, 0}, {0.3f, 2, 0}, 0);
  for (const float t_max : {0.1f, 1.0f, 10.0f}) {
    const double inside = testing::Simpson([&](double t) { return FreeFlightPdf(m, float(t)); }, 0, t_max);
    EXPECT_NEAR(inside + FreeFlightPassProbability(m, t_max), 1.0, 1e-5) << t_max;
  }
}

TEST(FreeFlight, SampledDistancesHaveTheExponentialMean) {
  const HomogeneousMedium m = HomogeneousMedium::FromAlbedo({0.5f, 0.5f, 0.5f}, 2, 0);
  std::mt19937 rng(15);
  std::uniform_real_distribution<float> u(0, 1);
  const int n = 200000;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const std::optional<DistanceSample> s = SampleFreeFlight(m, kInf, u(rng), u(rng));
    ASSERT_TRUE(s);
    EXPECT_NEAR(s->pdf, 2 * std::exp(-2 * s->t), 1e-5f * (1 + s->pdf));
    sum += s->t;
  }
  // The exponential's standard deviation equals its mean (0.5): 5 sigma of the mean of n.
  EXPECT_NEAR(sum / n, 0.5, 5 * 0.5 / std::sqrt(double(n)));
}

TEST(FreeFlight, PassesTheEndWithItsProbability) {
  const HomogeneousMedium m = HomogeneousMedium::FromCoefficients({1, 0, 0}, {0, 0, 0}, 0);
  std::mt19937 rng(16);
  std::uniform_real_distribution<float> u(0, 1);
  const int n = 100000;
  int passed = 0;
  for (int i = 0; i < n; ++i) passed += !SampleFreeFlight(m, 0.5f, u(rng), u(rng));
  const double p = FreeFlightPassProbability(m, 0.5f);
  EXPECT_NEAR(p, std::exp(-0.5), 1e-6);
  EXPECT_NEAR(double(passed) / n, p, 5 * std::sqrt(p * (1 - p) / n));
}

TEST(TruncatedFlight, DensityIntegratesToOneAndSamplesStayOnTheSegment) {
  const HomogeneousMedium m = HomogeneousMedium::FromCoefficients({0.01f, 3, 0}, {0.02f, 1, 0}, 0);
  for (const float t_max : {0.5f, 4.0f}) {
    const double mass = testing::Simpson([&](double t) { return TruncatedFlightPdf(m, t_max, float(t)); }, 0, t_max);
    EXPECT_NEAR(mass, 1.0, 1e-5) << t_max;
    for (const float uc : {0.1f, 0.9f}) {
      for (const float u : {0.0f, 0.5f, 0.999999f}) {
        const std::optional<DistanceSample> s = SampleTruncatedFlight(m, t_max, uc, u);
        ASSERT_TRUE(s);
        EXPECT_GE(s->t, 0);
        EXPECT_LE(s->t, t_max);
        EXPECT_FLOAT_EQ(s->pdf, TruncatedFlightPdf(m, t_max, s->t));
      }
    }
  }
  EXPECT_FALSE(SampleTruncatedFlight(HomogeneousMedium{}, 1, 0.5f, 0.5f));
}

}  // namespace
}  // namespace farm
