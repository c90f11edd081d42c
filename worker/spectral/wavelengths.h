#pragma once

// The visible range spectral rendering draws wavelengths from, and how many a path
// carries in spectral mode (spectral_light.h).

namespace farm {

inline constexpr double kLambdaMin = 360;  // nm
inline constexpr double kLambdaMax = 830;
inline constexpr int kWavelengthsPerPath = 8;

}  // namespace farm
