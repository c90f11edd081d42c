#include "spectral/monochrome.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "spectral/test_srgb.h"
#include "spectral/wavelengths.h"

namespace farm {
namespace {

// The mean over n stratified wavelengths of a monochrome path's RGB carrying rgb's uplift.
Rgb MeanOver(const Rgb& rgb, int n = 4000) {
  double r = 0, g = 0, b = 0;
  for (int i = 0; i < n; ++i) {
    const MonochromePath path = MonochromePath::Sample((i + 0.5) / n);
    const Rgb c = path.ToRgb(path.ValueOf(rgb));
    r += c.r, g += c.g, b += c.b;
  }
  return Rgb(static_cast<float>(r / n), static_cast<float>(g / n), static_cast<float>(b / n));
}

TEST(MonochromePath, WhiteLightSplitIntoWavelengthsAddsUpToWhite) {
  for (const float level : {1.0f, 0.25f, 7.0f}) {
    const Rgb mean = MeanOver(Rgb(level));
    EXPECT_NEAR(mean.r, level, 0.01 * level);
    EXPECT_NEAR(mean.g, level, 0.01 * level);
    EXPECT_NEAR(mean.b, level, 0.01 * level);
  }
}

TEST(MonochromePath, AColourKeepsItsHueWithinTheUpliftsRoundTrip) {
  const Rgb orange(0.8f, 0.4f, 0.2f);
  const Rgb mean = MeanOver(orange);
  ExpectColourNear(mean, orange, 0.12f);
  EXPECT_GT(mean.r, mean.g);
  EXPECT_GT(mean.g, mean.b);
}

TEST(MonochromePath, EveryWavelengthIsNonNegativeAndRainbowColoured) {
  for (double lambda = kLambdaMin; lambda <= kLambdaMax; lambda += 1) {
    const Rgb c = MonochromePath{lambda}.ToRgb(1);
    EXPECT_GE(c.r, 0) << lambda;
    EXPECT_GE(c.g, 0) << lambda;
    EXPECT_GE(c.b, 0) << lambda;
  }
  const Rgb violet = MonochromePath{440}.ToRgb(1), green = MonochromePath{530}.ToRgb(1),
            red = MonochromePath{640}.ToRgb(1);
  EXPECT_GT(violet.b, violet.g);
  EXPECT_GT(violet.b, violet.r * 0.5);
  EXPECT_GT(green.g, green.r);
  EXPECT_GT(green.g, green.b);
  EXPECT_GT(red.r, 4 * red.g);
  EXPECT_GT(red.r, 4 * red.b);
}

TEST(MonochromePath, DrawingWhereTheChannelsSeeLightMoreThanHalvesTheColourNoiseOfWhite) {
  // Per channel, the variance over wavelengths of white's estimate as drawn (Pdf) against
  // the same estimate with wavelengths drawn uniformly over 360-830 nm.
  constexpr int kN = 20000;
  ChannelSpread drawn_spread, uniform_spread;
  for (int i = 0; i < kN; ++i) {
    const double u = (i + 0.5) / kN;
    const MonochromePath drawn = MonochromePath::Sample(u), uniform{kLambdaMin + u * (kLambdaMax - kLambdaMin)};
    drawn_spread.Add(drawn.ToRgb(1));
    uniform_spread.Add(uniform.ToRgb(1) * static_cast<float>(uniform.Pdf() * (kLambdaMax - kLambdaMin)));
  }
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(drawn_spread.Mean(c), 1, 0.005) << "channel " << c;
    EXPECT_NEAR(uniform_spread.Mean(c), 1, 0.005) << "channel " << c;
    EXPECT_LT(drawn_spread.Variance(c), 0.5 * uniform_spread.Variance(c)) << "channel " << c;
    std::printf("channel %d: variance of white %.3f drawn, %.3f uniform\n", c, drawn_spread.Variance(c),
                uniform_spread.Variance(c));
  }
}

}  // namespace
}  // namespace farm
