#include "scene/blinn_phong.h"

#include <algorithm>
#include <cmath>

#include "math/math.h"
#include "scene/fresnel.h"

namespace farm {
namespace {

float HalfVectorPdf(float cos_h, float exponent) {
  return (exponent + 1) * kInv2Pi * std::pow(std::max(0.0f, cos_h), exponent);
}

}  // namespace

float BlinnPhongPdf(const Vec3& wo, const Vec3& wi, float exponent) {
  if (!(wo.z > 0) || !(wi.z > 0)) return 0;
  const Vec3 sum = wo + wi;
  const float len2 = LengthSquared(sum);
  if (!(len2 > 0)) return 0;
  const Vec3 h = sum / std::sqrt(len2);
  const float wo_h = Dot(wo, h);
  if (!(wo_h > 0)) return 0;
  return HalfVectorPdf(h.z, exponent) / (4 * wo_h);
}

float BlinnPhongValue(const Vec3& wo, const Vec3& wi, float exponent) {
  const float pdf = BlinnPhongPdf(wo, wi, exponent);
  return pdf > 0 ? pdf / std::max(wo.z, wi.z) : 0.0f;
}

std::optional<Vec3> SampleBlinnPhong(const Vec3& wo, Vec2 u, float exponent) {
  // Inverting the CDF of D's cos theta_h: cos = u^(1 / (e + 1)).
  const float cos_h = std::pow(u.x, 1 / (exponent + 1));
  const float sin_h = SafeSqrt(1 - cos_h * cos_h);
  const float phi = 2 * kPi * u.y;
  const Vec3 h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
  if (!(Dot(wo, h) > 0)) return std::nullopt;
  const Vec3 wi = Reflect(wo, h);
  if (!(wi.z > 0)) return std::nullopt;
  return wi;
}

}  // namespace farm
