#include "spectral/colour_matching.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace farm {
namespace {

// A Gaussian lobe with a different width on each side of its peak (Wyman et al., eq. 1).
double Lobe(double lambda, double mean, double sigma_below, double sigma_above) {
  const double t = (lambda - mean) / (lambda < mean ? sigma_below : sigma_above);
  return std::exp(-0.5 * t * t);
}

// ∫ x̄, ȳ, z̄ over the sampled range, by the midpoint rule at 0.1 nm: the lobes are smooth
// on that scale, so the error is far below the fit's own.
Xyz Integrals() {
  constexpr int steps = 4700;
  constexpr double dl = (kLambdaMax - kLambdaMin) / steps;
  Xyz sum;
  for (int i = 0; i < steps; ++i) {
    const Xyz m = ColourMatching(kLambdaMin + (i + 0.5) * dl);
    sum.x += m.x * dl;
    sum.y += m.y * dl;
    sum.z += m.z * dl;
  }
  return sum;
}

const Xyz& IntegralsOnce() {
  static const Xyz integrals = Integrals();
  return integrals;
}

}  // namespace

Xyz ColourMatching(double l) {
  return {1.056 * Lobe(l, 599.8, 37.9, 31.0) + 0.362 * Lobe(l, 442.0, 16.0, 26.7) - 0.065 * Lobe(l, 501.1, 20.4, 26.2),
          0.821 * Lobe(l, 568.8, 46.9, 40.5) + 0.286 * Lobe(l, 530.9, 16.3, 31.1),
          1.217 * Lobe(l, 437.0, 11.8, 36.0) + 0.681 * Lobe(l, 459.0, 26.0, 13.8)};
}

double YIntegral() { return IntegralsOnce().y; }

Rgb XyzToLinearSrgb(const Xyz& xyz) {
  // D65's XYZ (Y = 1) over the equal-energy white's under the fit.
  const Xyz& e = IntegralsOnce();
  const double x = xyz.x * 0.95047 * e.y / e.x;
  const double y = xyz.y;
  const double z = xyz.z * 1.08883 * e.y / e.z;
  // IEC 61966-2-1's matrix from XYZ to linear sRGB.
  return Rgb(static_cast<float>(3.2404542 * x - 1.5371385 * y - 0.4985314 * z),
             static_cast<float>(-0.9692660 * x + 1.8760108 * y + 0.0415560 * z),
             static_cast<float>(0.0556434 * x - 0.2040259 * y + 1.0572252 * z));
}

namespace {

Rgb ClippedSrgbMatching(double lambda) {
  const Rgb c = XyzToLinearSrgb(ColourMatching(lambda));
  return Rgb(std::max(0.0f, c.r), std::max(0.0f, c.g), std::max(0.0f, c.b));
}

std::array<double, 3> ClippedIntegrals() {
  std::array<double, 3> integral{};
  for (int i = 0; i <= kFilmSteps; ++i) {
    const Rgb c = ClippedSrgbMatching(kLambdaMin + kFilmStep * i);
    const double w = (i == 0 || i == kFilmSteps) ? 0.5 : 1.0;
    integral[0] += w * c.r * kFilmStep;
    integral[1] += w * c.g * kFilmStep;
    integral[2] += w * c.b * kFilmStep;
  }
  return integral;
}

}  // namespace

Rgb FilmResponse(double lambda_nm) {
  static const std::array<double, 3> integral = ClippedIntegrals();
  const Rgb c = ClippedSrgbMatching(lambda_nm);
  return Rgb(static_cast<float>(c.r / integral[0]), static_cast<float>(c.g / integral[1]),
             static_cast<float>(c.b / integral[2]));
}

}  // namespace farm
