#include "scene/ggx.h"

#include <cmath>
#include <limits>

#include "math/math.h"

namespace farm {

float GgxD(const Vec3& h, float alpha) {
  if (!(h.z > 0)) return 0;
  const float a2 = alpha * alpha;
  const float d = (a2 - 1) * h.z * h.z + 1;
  return a2 / (kPi * d * d);
}

float GgxLambda(const Vec3& w, float alpha) {
  // Below the horizon a direction sees nothing of the surface's front: G1 = 0.
  if (!(w.z > 0)) return std::numeric_limits<float>::infinity();
  const float cos2 = w.z * w.z;
  // alpha^2 tan^2 = alpha^2 sin^2 / cos^2, with sin^2 from x and y (exact near the pole).
  const float a2_tan2 = alpha * alpha * (w.x * w.x + w.y * w.y) / cos2;
  return (std::sqrt(1 + a2_tan2) - 1) / 2;
}

float GgxG1(const Vec3& w, float alpha) { return 1 / (1 + GgxLambda(w, alpha)); }

float GgxG2(const Vec3& wo, const Vec3& wi, float alpha) {
  return 1 / (1 + GgxLambda(wo, alpha) + GgxLambda(wi, alpha));
}

Vec3 SampleGgxVisibleNormal(const Vec3& wo, float alpha, Vec2 u) {
  // Stretch the view direction into the configuration where the distribution is the unit
  // hemisphere, sample the projected disc of visible normals there (a half disc warped
  // by how much the hemisphere is seen edge-on), and unstretch the normal.
  const Vec3 v = Normalize(Vec3(alpha * wo.x, alpha * wo.y, wo.z));
  const float len2 = v.x * v.x + v.y * v.y;
  const Vec3 t1 = len2 > 0 ? Vec3(-v.y, v.x, 0) / std::sqrt(len2) : Vec3(1, 0, 0);
  const Vec3 t2 = Cross(v, t1);
  const float r = std::sqrt(u.x);
  const float phi = 2 * kPi * u.y;
  const float p1 = r * std::cos(phi);
  const float s = (1 + v.z) / 2;
  const float p2 = (1 - s) * SafeSqrt(1 - p1 * p1) + s * r * std::sin(phi);
  const Vec3 n = t1 * p1 + t2 * p2 + v * SafeSqrt(1 - p1 * p1 - p2 * p2);
  return Normalize(Vec3(alpha * n.x, alpha * n.y, std::max(0.0f, n.z)));
}

float GgxReflectionPdf(const Vec3& wo, const Vec3& wi, float alpha) {
  if (!(wo.z > 0)) return 0;
  const Vec3 sum = wo + wi;
  const float len2 = LengthSquared(sum);
  if (!(len2 > 0)) return 0;
  const Vec3 h = sum / std::sqrt(len2);
  if (!(Dot(wo, h) > 0)) return 0;
  return GgxG1(wo, alpha) * GgxD(h, alpha) / (4 * wo.z);
}

}  // namespace farm
