#pragma once

// Hero-wavelength sampling (Wilkie et al., "Hero Wavelength Spectral Sampling", EGSR 2014):
// one uniformly drawn hero wavelength and companions at equal offsets through the visible
// range, wrapped around its ends. Four wavelengths a path stratify the spectrum at the
// cost of one random number; past a dispersive interface Wilkie et al. keep the hero alone,
// since each companion would leave in a direction of its own.

#include <array>

namespace farm {

inline constexpr double kLambdaMin = 360;  // nm
inline constexpr double kLambdaMax = 830;
inline constexpr int kWavelengthsPerPath = 4;

struct SampledWavelengths {
  std::array<double, kWavelengthsPerPath> lambda{};  // nm; lambda[0] is the hero
  // The density each wavelength was drawn with, per nm (uniform over the range).
  double pdf = 0;
};

// u in [0, 1).
SampledWavelengths SampleWavelengths(double u);

}  // namespace farm
