#include "spectral/uplift.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "spectral/colour_matching.h"
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

// Reflectances in [0, 1] stay physical: no wavelength reflects more than it receives, and
// none reflects less than nothing.
TEST(Uplift, ReflectancesStayWithinZeroAndOne) {
  for (const Rgb& c : {Rgb(1, 0, 0), Rgb(0, 1, 0), Rgb(0, 0, 1), Rgb(1, 1, 0), Rgb(0, 1, 1), Rgb(1, 0, 1),
                       Rgb(0.8f, 0.3f, 0.1f)}) {
    const SmitsSpectrum s(c);
    for (double l = kLambdaMin; l < kLambdaMax; l += 5) {
      EXPECT_GE(s.At(l), 0) << ToString(c) << " at " << l;
      EXPECT_LE(s.At(l), 1) << ToString(c) << " at " << l;
    }
  }
}

// The film's colour of a spectrum (what the mean of many paths at its wavelengths gives):
// ∫ S(λ) FilmResponse(λ) dλ by the trapezoid rule.
Rgb FilmColourOf(const SmitsSpectrum& s) {
  double sum[3] = {0, 0, 0};
  for (int i = 0; i <= kFilmSteps; ++i) {
    const double l = kLambdaMin + kFilmStep * i;
    const double w = ((i == 0 || i == kFilmSteps) ? 0.5 : 1.0) * kFilmStep * s.At(l);
    const Rgb r = FilmResponse(l);
    sum[0] += w * r.r, sum[1] += w * r.g, sum[2] += w * r.b;
  }
  return Rgb(float(sum[0]), float(sum[1]), float(sum[2]));
}

// The basis is fitted to the film (FilmResponse): greys come back exactly, colours near
// grey within 2% of their largest channel, and saturated ones as nearly as a spectrum within [0, 1] can
// make the film see them: the film's red channel sees little beyond 620 nm that its green
// does not also see, so a saturated red comes back at 0.88 with some green (measured; the
// bound is 0.15 of the colour's largest channel). Linear in the colour's level.
TEST(Uplift, ColoursComeBackFromTheFilmAsNearlyAsBoundedSpectraAllow) {
  struct Case {
    Rgb colour;
    float tolerance;  // of the largest channel
  };
  for (const Case& k : {Case{Rgb(1), 1e-4f}, Case{Rgb(0.25f), 1e-4f}, Case{Rgb(0.725f, 0.71f, 0.68f), 0.02f},
                        Case{Rgb(0.5f, 0.45f, 0.4f), 0.02f}, Case{Rgb(1, 0, 0), 0.15f}, Case{Rgb(0, 1, 0), 0.15f},
                        Case{Rgb(0, 0, 1), 0.15f}, Case{Rgb(1, 1, 0), 0.15f}, Case{Rgb(0, 1, 1), 0.15f},
                        Case{Rgb(1, 0, 1), 0.15f}, Case{Rgb(0.63f, 0.065f, 0.05f), 0.15f},
                        Case{Rgb(18.387f, 13.9873f, 6.75357f), 0.05f}}) {
    const Rgb& c = k.colour;
    const Rgb back = FilmColourOf(SmitsSpectrum(c));
    const float tolerance = k.tolerance * std::max({c.r, c.g, c.b});
    EXPECT_NEAR(back.r, c.r, tolerance) << ToString(c) << " -> " << ToString(back);
    EXPECT_NEAR(back.g, c.g, tolerance) << ToString(c) << " -> " << ToString(back);
    EXPECT_NEAR(back.b, c.b, tolerance) << ToString(c) << " -> " << ToString(back);
    std::printf("%s -> %s\n", ToString(c).c_str(), ToString(back).c_str());
  }
}

}  // namespace
}  // namespace farm
