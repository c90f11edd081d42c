#pragma once

// For the tests: a spectrum's colour as the film estimates it.

#include <functional>

#include "spectral/colour_matching.h"

namespace farm {

// The sRGB of a spectrum as the film estimates it from n stratified paths.
inline Rgb SrgbOf(const std::function<double(double)>& spectrum, int n = 4096) {
  Xyz sum;
  for (int k = 0; k < n; ++k) {
    const SampledWavelengths w = SampleWavelengths((k + 0.5) / n);
    std::array<double, kWavelengthsPerPath> values{};
    for (int i = 0; i < kWavelengthsPerPath; ++i) values[i] = spectrum(w.lambda[i]);
    const Xyz xyz = XyzOf(w, values);
    sum.x += xyz.x / n;
    sum.y += xyz.y / n;
    sum.z += xyz.z / n;
  }
  return XyzToLinearSrgb(sum);
}

}  // namespace farm
