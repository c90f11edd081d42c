#include "spectral/monochrome.h"

#include <algorithm>
#include <array>

#include "spectral/colour_matching.h"
#include "spectral/uplift.h"
#include "spectral/wavelengths.h"

namespace farm {
namespace {

constexpr double kRange = kLambdaMax - kLambdaMin;

Rgb ClippedSrgbMatching(double lambda) {
  const Rgb c = XyzToLinearSrgb(ColourMatching(lambda));
  return Rgb(std::max(0.0f, c.r), std::max(0.0f, c.g), std::max(0.0f, c.b));
}

// ∫ of each clipped matching function over the visible range (trapezoids of 0.5 nm, fine
// against the fit's smooth lobes), computed once.
const std::array<double, 3>& ClippedIntegrals() {
  static const std::array<double, 3> integrals = [] {
    constexpr int kSteps = 940;
    std::array<double, 3> sum{};
    for (int i = 0; i <= kSteps; ++i) {
      const double w = (i == 0 || i == kSteps) ? 0.5 : 1.0;
      const Rgb c = ClippedSrgbMatching(kLambdaMin + kRange * i / kSteps);
      sum[0] += w * c.r;
      sum[1] += w * c.g;
      sum[2] += w * c.b;
    }
    for (double& s : sum) s *= kRange / kSteps;
    return sum;
  }();
  return integrals;
}

}  // namespace

MonochromePath MonochromePath::Sample(double u) { return MonochromePath{kLambdaMin + u * kRange}; }

Rgb MonochromePath::ToRgb(double value) const {
  const Rgb c = ClippedSrgbMatching(lambda_nm);
  const std::array<double, 3>& integral = ClippedIntegrals();
  // Divided by the density 1 / kRange.
  const double k = value * kRange;
  return Rgb(static_cast<float>(k * c.r / integral[0]), static_cast<float>(k * c.g / integral[1]),
             static_cast<float>(k * c.b / integral[2]));
}

double MonochromePath::ValueOf(const Rgb& rgb) const { return SmitsSpectrum(rgb).At(lambda_nm); }

}  // namespace farm
