#pragma once

// Scalar helpers shared by the renderer. Shading math is in float (see vec3.h for why).

#include <algorithm>
#include <cmath>
#include <numbers>

namespace farm {

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kInvPi = std::numbers::inv_pi_v<float>;
inline constexpr float kInv2Pi = 0.5f * std::numbers::inv_pi_v<float>;
inline constexpr float kInv4Pi = 0.25f * std::numbers::inv_pi_v<float>;

// The largest float below 1: uniform samples must stay in [0, 1) so that warps which map
// u = 1 onto a boundary (index = floor(u * n)) never step past the end.
inline constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

template <typename T>
constexpr T Sqr(T x) {
  return x * x;
}

template <typename T>
constexpr T Lerp(T t, T a, T b) {
  return (1 - t) * a + t * b;
}

// sqrt that treats small negative arguments (rounding error) as zero instead of NaN.
inline float SafeSqrt(float x) { return std::sqrt(std::max(0.0f, x)); }
inline double SafeSqrt(double x) { return std::sqrt(std::max(0.0, x)); }

inline float SafeAcos(float x) { return std::acos(std::clamp(x, -1.0f, 1.0f)); }

constexpr double Radians(double degrees) { return degrees * (std::numbers::pi / 180.0); }

}  // namespace farm
