#pragma once

// Test helpers of the BSDF tests: stratified 2D points and directions by angle, in a local
// frame whose z is the normal.

#include <cmath>
#include <cstdint>

#include "math/math.h"
#include "math/vec3.h"
#include "sampling/sobol.h"

namespace farm {

// Point i of an Owen-scrambled Sobol (0,2)-sequence; seeds give independent streams.
inline Vec2 Sobol2(uint32_t i, uint32_t seed) { return {SobolSample(i, 0, seed), SobolSample(i, 1, seed * 7 + 1)}; }

// The unit direction theta degrees from the normal, at azimuth phi degrees from x.
inline Vec3 Dir(float theta_degrees, float phi_degrees = 0) {
  const float t = static_cast<float>(Radians(theta_degrees)), p = static_cast<float>(Radians(phi_degrees));
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

}  // namespace farm
