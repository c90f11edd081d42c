#include "spectral/colour_matching.h"

#include <gtest/gtest.h>

#include "spectral/test_srgb.h"

namespace farm {
namespace {

// The CIE 1931 tables integrate to 106.857 (ȳ, 360-830 nm at 1 nm), and x̄, z̄ to the
// same by the definition of the equal-energy white (x = y = 1/3): the fit keeps each within
// 1%.
TEST(ColourMatching, FitIntegratesLikeTheCieTables) {
  constexpr double cie_y = 106.857;
  EXPECT_NEAR(YIntegral(), cie_y, 0.01 * cie_y);
  Xyz sum;
  for (double l = kLambdaMin + 0.05; l < kLambdaMax; l += 0.1) {
    const Xyz m = ColourMatching(l);
    sum.x += m.x * 0.1;
    sum.z += m.z * 0.1;
  }
  EXPECT_NEAR(sum.x, cie_y, 0.01 * cie_y);
  EXPECT_NEAR(sum.z, cie_y, 0.01 * cie_y);
}

// Peaks of the tabulated functions: x̄ 1.0622 at 599 nm, ȳ 1.0 at 555 nm, z̄ 1.7826 at
// 446 nm (CIE 1931); the fit is within 3% there.
TEST(ColourMatching, FitPeaksWhereTheCieTablesDo) {
  EXPECT_NEAR(ColourMatching(599).x, 1.0622, 0.03);
  EXPECT_NEAR(ColourMatching(555).y, 1.0, 0.03);
  EXPECT_NEAR(ColourMatching(446).z, 1.7826, 0.05);
}

TEST(ColourMatching, UniformSpectrumIsWhite) {
  const Rgb rgb = SrgbOf([](double) { return 1.0; });
  EXPECT_NEAR(rgb.r, 1, 0.01) << ToString(rgb);
  EXPECT_NEAR(rgb.g, 1, 0.01) << ToString(rgb);
  EXPECT_NEAR(rgb.b, 1, 0.01) << ToString(rgb);
}

// Light at one wavelength is a spectral colour: 610 nm is red-orange (red channel
// largest, blue negative, out of sRGB's gamut), 530 nm green, 450 nm blue.
TEST(ColourMatching, MonochromaticLightHasItsHue) {
  auto at = [](double l) {
    const Xyz m = ColourMatching(l);
    return XyzToLinearSrgb(m);
  };
  const Rgb red = at(610), green = at(530), blue = at(450);
  EXPECT_GT(red.r, red.g) << ToString(red);
  EXPECT_LT(red.b, 0) << ToString(red);
  EXPECT_GT(green.g, green.r) << ToString(green);
  EXPECT_GT(green.g, green.b) << ToString(green);
  EXPECT_GT(blue.b, blue.r) << ToString(blue);
  EXPECT_GT(blue.b, blue.g) << ToString(blue);
}

}  // namespace
}  // namespace farm
