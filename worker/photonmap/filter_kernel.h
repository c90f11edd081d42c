#pragma once

// Radial filter kernels for the photon radiance estimate, as densities over the unit disc:
// the integral of FilterKernel(u) over {|x| <= 1} is exactly 1 for every filter, so an
// estimate sum_p K(d_p / r) * flux_p / r^2 returns the exact irradiance for a uniform
// photon density whatever the filter (checked numerically in the tests).

#include <cmath>
#include <numbers>

#include "photonmap/radiance_estimate.h"

namespace farm {

// Jensen's Gaussian constants (Realistic Image Synthesis Using Photon Mapping, 7.2.2,
// after Pavicic). His alpha = 0.918 is a normalisation; by our integration it makes the
// kernel integrate to 0.53 over the disc rather than 1, so we normalise exactly instead
// and alpha drops out.
inline constexpr float kGaussianBeta = 1.953f;

// u = distance / radius, in [0, 1]. cone_k >= 1 (Jensen's k).
inline float FilterKernel(PhotonFilter filter, float u, float cone_k) {
  constexpr float kPi = std::numbers::pi_v<float>;
  switch (filter) {
    case PhotonFilter::kBox:
      return 1 / kPi;
    case PhotonFilter::kCone:
      // integral of (1 - u/k) over the unit disc = pi (1 - 2 / (3k))
      return (1 - u / cone_k) / (kPi * (1 - 2 / (3 * cone_k)));
    case PhotonFilter::kGaussian: {
      const float b = kGaussianBeta;
      const float denom = 1 - std::exp(-b);
      // integral over the unit disc of the shape below: pi * (1 - (1 - 2/b (1 - e^{-b/2})) / denom)
      const float norm = kPi * (1 - (1 - 2 / b * (1 - std::exp(-b / 2))) / denom);
      return (1 - (1 - std::exp(-b * u * u / 2)) / denom) / norm;
    }
  }
  return 0;
}

}  // namespace farm
