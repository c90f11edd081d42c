#include "media/henyey_greenstein.h"

#include <algorithm>
#include <cmath>

#include "math/frame.h"
#include "math/math.h"

namespace farm {
namespace {

// Below this |g| the inverse CDF loses precision; the function is then uniform to within
// 3e-4 relative and is sampled as such (its pdf stays the exact function's).
constexpr float kIsotropicG = 1e-4f;

}  // namespace

float HenyeyGreenstein(float cos_theta, float g) {
  // 1 + g^2 - 2 g cos theta as (1 - g)^2 + 2 g (1 - cos theta), in double: for |g| near 1
  // the lobe's peak is (1 - g)^2 wide and the plain form cancels.
  const double gd = g;
  const double denom = (1 - gd) * (1 - gd) + 2 * gd * (1 - double(cos_theta));
  return float(double(kInv4Pi) * (1 - gd) * (1 + gd) / (denom * std::sqrt(std::max(denom, 0.0))));
}

float HenyeyGreenstein(const Vec3& wo, const Vec3& wi, float g) { return HenyeyGreenstein(Dot(-wi, wo), g); }

PhaseSample SampleHenyeyGreenstein(const Vec3& wo, float g, Vec2 u) {
  float cos_theta;
  if (std::abs(g) < kIsotropicG) {
    cos_theta = 1 - 2 * u.x;
  } else {
    // The inverse of the CDF of cos theta (in double: 1 - g^2 cancels for |g| near 1).
    const double gd = g;
    const double s = (1 - gd * gd) / (1 - gd + 2 * gd * double(u.x));
    cos_theta = float(std::clamp((1 + gd * gd - s * s) / (2 * gd), -1.0, 1.0));
  }
  const float sin_theta = SafeSqrt(1 - cos_theta * cos_theta);
  const float phi = 2 * kPi * u.y;
  // cos theta is measured from the direction the light travels, -wi, towards wo: build
  // -wi about wo, then flip.
  const Frame frame = Frame::FromZ(wo);
  const Vec3 travel = frame.FromLocal(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta));
  return {-travel, HenyeyGreenstein(cos_theta, g)};
}

}  // namespace farm
