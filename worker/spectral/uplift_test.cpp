#include "spectral/uplift.h"

#include <gtest/gtest.h>

#include "spectral/test_srgb.h"

namespace farm {
namespace {

Rgb RoundTrip(const Rgb& rgb) {
  const SmitsSpectrum s(rgb);
  return SrgbOf([&](double l) { return s.At(l); });
}

TEST(Uplift, WhiteIsFlatAndComesBackWhite) {
  const SmitsSpectrum white(Rgb(1));
  for (double l = kLambdaMin; l < kLambdaMax; l += 5) EXPECT_NEAR(white.At(l), 1, 1e-3) << l;
  const Rgb rgb = RoundTrip(Rgb(1));
  EXPECT_NEAR(rgb.r, 1, 0.01) << ToString(rgb);
  EXPECT_NEAR(rgb.g, 1, 0.01) << ToString(rgb);
  EXPECT_NEAR(rgb.b, 1, 0.01) << ToString(rgb);
}

// The uplift is linear in a grey's level, and black is no light at all.
TEST(Uplift, GreysScaleTheFlatSpectrum) {
  EXPECT_EQ(SmitsSpectrum(Rgb(0)).At(550), 0);
  EXPECT_NEAR(SmitsSpectrum(Rgb(0.25f)).At(550), 0.25, 1e-3);
}

// Reflectances in [0, 1] stay physical: no wavelength reflects more than it receives by
// more than Smits' table's own 1.5% overshoot, and none reflects less than nothing.
TEST(Uplift, ReflectancesStayWithinZeroAndOne) {
  for (const Rgb& c : {Rgb(1, 0, 0), Rgb(0, 1, 0), Rgb(0, 0, 1), Rgb(1, 1, 0), Rgb(0, 1, 1), Rgb(1, 0, 1),
                       Rgb(0.8f, 0.3f, 0.1f)}) {
    const SmitsSpectrum s(c);
    for (double l = kLambdaMin; l < kLambdaMax; l += 5) {
      EXPECT_GE(s.At(l), 0) << ToString(c) << " at " << l;
      EXPECT_LE(s.At(l), 1.015) << ToString(c) << " at " << l;
    }
  }
}

// Saturated primaries and secondaries come back with every channel within 0.12 of what went
// in. Smits fitted his basis to other primaries than sRGB's, so the round trip is not exact:
// measured, the worst channels are red's red (1.108) and cyan's red (-0.108); the others
// are within 0.065.
TEST(Uplift, SaturatedColoursRoundTripWithinTwelveHundredths) {
  for (const Rgb& c : {Rgb(1, 0, 0), Rgb(0, 1, 0), Rgb(0, 0, 1), Rgb(1, 1, 0), Rgb(0, 1, 1), Rgb(1, 0, 1)}) {
    const Rgb back = RoundTrip(c);
    EXPECT_NEAR(back.r, c.r, 0.12) << ToString(c) << " -> " << ToString(back);
    EXPECT_NEAR(back.g, c.g, 0.12) << ToString(c) << " -> " << ToString(back);
    EXPECT_NEAR(back.b, c.b, 0.12) << ToString(c) << " -> " << ToString(back);
  }
}

}  // namespace
}  // namespace farm
