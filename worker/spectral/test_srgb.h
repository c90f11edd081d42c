#pragma once

// For the tests: a spectrum's colour, the linear sRGB of its XYZ.

#include <functional>

#include "spectral/colour_matching.h"

namespace farm {

// The linear sRGB of a spectrum: its XYZ by the midpoint rule over n intervals of the
// visible range, with Y = 1 for the spectrum that is 1 everywhere.
inline Rgb SrgbOf(const std::function<double(double)>& spectrum, int n = 4096) {
  const double step = (kLambdaMax - kLambdaMin) / n;
  const double scale = step / YIntegral();
  Xyz sum;
  for (int k = 0; k < n; ++k) {
    const double lambda = kLambdaMin + (k + 0.5) * step;
    const Xyz m = ColourMatching(lambda);
    const double v = spectrum(lambda);
    sum.x += v * m.x * scale;
    sum.y += v * m.y * scale;
    sum.z += v * m.z * scale;
  }
  return XyzToLinearSrgb(sum);
}

}  // namespace farm
