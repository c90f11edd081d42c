#include "scene/fresnel.h"

#include <algorithm>
#include <cmath>
#include <complex>

#include "math/math.h"

namespace farm {

float FresnelDielectric(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, -1.0f, 1.0f);
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
  }
  const float sin2_t = (1 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1) return 1;  // total internal reflection
  const float cos_t = SafeSqrt(1 - sin2_t);
  const float r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return (r_parallel * r_parallel + r_perpendicular * r_perpendicular) / 2;
}

float FresnelConductor(float cos_i, float eta, float k) {
  // The dielectric formulas with a complex index (Snell's law in the complex plane), which
  // is exact for a smooth absorbing medium; std::complex keeps it short and readable.
  using C = std::complex<float>;
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  const C n(eta, k);
  const float sin2_i = 1 - cos_i * cos_i;
  const C sin2_t = sin2_i / (n * n);
  const C cos_t = std::sqrt(C(1) - sin2_t);
  const C r_parallel = (n * cos_i - cos_t) / (n * cos_i + cos_t);
  const C r_perpendicular = (cos_i - n * cos_t) / (cos_i + n * cos_t);
  return (std::norm(r_parallel) + std::norm(r_perpendicular)) / 2;
}

std::optional<Vec3> Refract(const Vec3& w, const Vec3& n, float eta) {
  const float cos_i = Dot(n, w);
  const float sin2_t = std::max(0.0f, 1 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1) return std::nullopt;
  const float cos_t = SafeSqrt(1 - sin2_t);
  return Normalize(-w / eta + n * (cos_i / eta - cos_t));
}

}  // namespace farm
