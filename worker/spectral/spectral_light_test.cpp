#include "spectral/spectral_light.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "contract/rules.h"
#include "spectral/test_srgb.h"

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
  ChannelSpread all, hero;
  for (int i = 0; i < kN; ++i) {
    const SpectralLight light = SpectralLight::Hero(Rgb(1), (i + 0.5) / kN);
    all.Add(light.ToRgb());
    hero.Add(light.HeroOnly().ToRgb());
  }
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(all.Mean(ch), 1, 0.01) << "channel " << ch;
    EXPECT_NEAR(hero.Mean(ch), 1, 0.01) << "channel " << ch;
    EXPECT_LT(all.Variance(ch), hero.Variance(ch) / 10) << "channel " << ch;
    std::printf("channel %d: variance of white %.4f at a path's wavelengths, %.4f at one\n", ch, all.Variance(ch),
                hero.Variance(ch));
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
  ExpectColourNear(mean, orange, 0.12f);
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
