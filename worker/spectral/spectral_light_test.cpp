#include "spectral/spectral_light.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "contract/rules.h"

namespace farm {
namespace {

constexpr int kN = 4000;

// The planner says how many wavelengths a path carries from the contract's value.
TEST(SpectralLight, CarriesTheContractsWavelengthsPerPath) {
  EXPECT_EQ(kWavelengthsPerPath, int(contract::SceneLimits().spectral_wavelengths_per_path()));
}

// Each wavelength alone is drawn with MonochromePath's density: the k-th is the one
// MonochromePath::Sample draws from u + k/4 (mod 1), so the four are distinct and spread.
TEST(SpectralLight, CompanionsAreTheRotatedDrawsOfTheHero) {
  for (const double u : {0.0, 0.1, 0.26, 0.5, 0.75, 0.999999}) {
    const SpectralLight light = SpectralLight::Hero(Rgb(1), u);
    ASSERT_EQ(light.count(), kWavelengthsPerPath);
    EXPECT_DOUBLE_EQ(light.hero_nm(), MonochromePath::Sample(u).lambda_nm);
    // Each wavelength alone, as the hero of its own rotation, gives the same estimate.
    Rgb sum;
    for (int k = 0; k < kWavelengthsPerPath; ++k) {
      double uk = u + double(k) / kWavelengthsPerPath;
      if (uk >= 1) uk -= 1;
      sum += SpectralLight::Hero(Rgb(1), uk).HeroOnly().ToRgb();
    }
    const Rgb mean = light.ToRgb(), expected = sum / float(kWavelengthsPerPath);
    EXPECT_NEAR(mean.r, expected.r, 1e-5 * (1 + expected.r)) << u;
    EXPECT_NEAR(mean.g, expected.g, 1e-5 * (1 + expected.g)) << u;
    EXPECT_NEAR(mean.b, expected.b, 1e-5 * (1 + expected.b)) << u;
  }
}

// White light at a path's wavelengths averages to white, and each sample is much closer to
// it than one wavelength's: the colour noise hero wavelengths remove (a fortieth of it with
// four wavelengths, less than a hundredth with eight: measured).
TEST(SpectralLight, HeroWavelengthsOfWhiteAreWhiteWithATenthOfOnesColourNoise) {
  double sum[2][3] = {}, sum2[2][3] = {};
  for (int i = 0; i < kN; ++i) {
    const SpectralLight four = SpectralLight::Hero(Rgb(1), (i + 0.5) / kN);
    const Rgb c[2] = {four.ToRgb(), four.HeroOnly().ToRgb()};
    for (int k = 0; k < 2; ++k) {
      const float v[3] = {c[k].r, c[k].g, c[k].b};
      for (int ch = 0; ch < 3; ++ch) sum[k][ch] += v[ch], sum2[k][ch] += double(v[ch]) * v[ch];
    }
  }
  for (int ch = 0; ch < 3; ++ch) {
    const double mean_four = sum[0][ch] / kN, mean_one = sum[1][ch] / kN;
    EXPECT_NEAR(mean_four, 1, 0.01) << "channel " << ch;
    EXPECT_NEAR(mean_one, 1, 0.01) << "channel " << ch;
    const double var_four = sum2[0][ch] / kN - mean_four * mean_four;
    const double var_one = sum2[1][ch] / kN - mean_one * mean_one;
    EXPECT_LT(var_four, var_one / 10) << "channel " << ch;
    std::printf("channel %d: variance of white %.4f at a path's wavelengths, %.4f at one\n", ch, var_four, var_one);
  }
}

// Light reflected by a colour: the mean of Times(colour) is the colour (within the uplift's
// round trip, as MonochromePath's test allows), and Over divides every wavelength.
TEST(SpectralLight, TimesAColourKeepsItsHueAndOverDivides) {
  const Rgb orange(0.8f, 0.4f, 0.2f);
  Rgb sum;
  for (int i = 0; i < kN; ++i) {
    const SpectralLight light = SpectralLight::Hero(Rgb(2), (i + 0.5) / kN).Times(orange, 2);
    sum += light.ToRgb();
    const Rgb a = light.Over(4).ToRgb(), b = light.ToRgb() / 4.0f;
    EXPECT_NEAR(a.r, b.r, 1e-6);
    EXPECT_NEAR(a.g, b.g, 1e-6);
    EXPECT_NEAR(a.b, b.b, 1e-6);
  }
  const Rgb mean = sum / float(kN);
  EXPECT_NEAR(mean.r, orange.r, 0.12);
  EXPECT_NEAR(mean.g, orange.g, 0.12);
  EXPECT_NEAR(mean.b, orange.b, 0.12);
  EXPECT_GT(mean.r, mean.g);
  EXPECT_GT(mean.g, mean.b);
}

// One wavelength carries exactly what MonochromePath says of it.
TEST(SpectralLight, OneWavelengthIsTheMonochromePath) {
  const MonochromePath at{550};
  const Rgb rgb(0.3f, 0.6f, 0.9f);
  const Rgb a = SpectralLight::One(rgb, at).ToRgb(), b = at.ToRgb(at.ValueOf(rgb));
  EXPECT_EQ(a.r, b.r);
  EXPECT_EQ(a.g, b.g);
  EXPECT_EQ(a.b, b.b);
  EXPECT_EQ(SpectralLight::One(rgb, at).count(), 1);
}

}  // namespace
}  // namespace farm
