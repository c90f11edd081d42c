#include "sampling/warps.h"

#include <cmath>

#include "math/frame.h"
#include "math/math.h"

namespace farm {

Vec3 SampleUniformTriangle(Vec2 u) {
  float b0, b1;
  if (u.x < u.y) {
    b0 = u.x / 2;
    b1 = u.y - b0;
  } else {
    b1 = u.y / 2;
    b0 = u.x - b1;
  }
  return {b0, b1, 1 - b0 - b1};
}

Vec3 SampleUniformSphere(Vec2 u) {
  const float z = 1 - 2 * u.x;
  const float r = SafeSqrt(1 - z * z);
  const float phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

float UniformSpherePdf() { return kInv4Pi; }

Vec3 SampleUniformCone(Vec2 u, float cos_theta_max) {
  const float cos_theta = (1 - u.x) + u.x * cos_theta_max;
  const float sin_theta = SafeSqrt(1 - cos_theta * cos_theta);
  const float phi = 2 * kPi * u.y;
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

float UniformConePdf(float cos_theta_max) { return 1 / (2 * kPi * (1 - cos_theta_max)); }

Vec2 SampleUniformDiskConcentric(Vec2 u) {
  const float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
  if (ox == 0 && oy == 0) return {0, 0};
  float r, theta;
  if (std::abs(ox) > std::abs(oy)) {
    r = ox;
    theta = (kPi / 4) * (oy / ox);
  } else {
    r = oy;
    theta = kPi / 2 - (kPi / 4) * (ox / oy);
  }
  return {r * std::cos(theta), r * std::sin(theta)};
}

Vec3 SampleCosineHemisphere(Vec2 u) {
  const Vec2 d = SampleUniformDiskConcentric(u);
  return {d.x, d.y, SafeSqrt(1 - d.x * d.x - d.y * d.y)};
}

float CosineHemispherePdf(float cos_theta) { return cos_theta * kInvPi; }

namespace {

// Below sin^2(1.5 degrees) the float expressions 1 - cos lose most of their digits; pbrt-v4
// switches to the Taylor form sin^2/2 there.
constexpr float kSmallSin2 = 0.00068523f;

// 1 - cos(theta_max) of the cone a sphere subtends, computed without cancellation.
float OneMinusCosThetaMax(float sin2_theta_max) {
  if (sin2_theta_max < kSmallSin2) return sin2_theta_max / 2;
  return 1 - SafeSqrt(1 - sin2_theta_max);
}

}  // namespace

SphereSample SampleSphereFromPoint(const Vec3& center, float radius, const Vec3& ref, Vec2 u) {
  const Vec3 to_center = center - ref;
  const float dist2 = LengthSquared(to_center);
  SphereSample s;
  if (dist2 <= radius * radius) {
    // Inside: uniform by area; pdf_solid_angle = pdf_area * dist^2 / |cos at the light|.
    s.n = SampleUniformSphere(u);
    s.p = center + s.n * radius;
    const Vec3 d = s.p - ref;
    const float len2 = LengthSquared(d);
    const float cos_light = len2 > 0 ? AbsDot(s.n, d) / std::sqrt(len2) : 0.0f;
    const float area = 4 * kPi * radius * radius;
    s.pdf = cos_light > 0 ? len2 / (cos_light * area) : 0.0f;
    return s;
  }
  const float dist = std::sqrt(dist2);
  const float sin_theta_max = radius / dist;
  const float sin2_theta_max = sin_theta_max * sin_theta_max;
  const float cos_theta_max = SafeSqrt(1 - sin2_theta_max);
  float one_minus_cos_max = 1 - cos_theta_max;

  // theta: angle at ref between the direction to the centre and the sampled direction.
  float cos_theta = (cos_theta_max - 1) * u.x + 1;
  float sin2_theta = 1 - cos_theta * cos_theta;
  if (sin2_theta_max < kSmallSin2) {
    sin2_theta = sin2_theta_max * u.x;
    cos_theta = std::sqrt(1 - sin2_theta);
    one_minus_cos_max = OneMinusCosThetaMax(sin2_theta_max);
  }
  // alpha: angle at the centre between the direction back to ref and the sampled point,
  // from the law of sines on the triangle (ref, centre, nearest hit point).
  const float cos_alpha = sin2_theta / sin_theta_max +
                          cos_theta * SafeSqrt(1 - sin2_theta / sin2_theta_max);
  const float sin_alpha = SafeSqrt(1 - cos_alpha * cos_alpha);
  const float phi = u.y * 2 * kPi;
  const Frame frame = Frame::FromZ(to_center / dist);
  const Vec3 w(sin_alpha * std::cos(phi), sin_alpha * std::sin(phi), cos_alpha);
  s.n = frame.FromLocal(-w);
  s.p = center + s.n * radius;
  s.pdf = 1 / (2 * kPi * one_minus_cos_max);
  s.in_cone = true;
  return s;
}

float SphereFromPointPdf(const Vec3& center, float radius, const Vec3& ref, const Vec3& w) {
  const Vec3 to_center = center - ref;
  const float dist2 = LengthSquared(to_center);
  if (dist2 <= radius * radius) {
    // Inside: the ray along w leaves through exactly one point of the sphere.
    const float b = Dot(-to_center, w);
    const float c = dist2 - radius * radius;
    const float t = -b + SafeSqrt(b * b - c);
    const Vec3 p = ref + w * t;
    const Vec3 n = Normalize(p - center);
    const float cos_light = AbsDot(n, w);
    return cos_light > 0 ? t * t / (cos_light * 4 * kPi * radius * radius) : 0.0f;
  }
  const float sin2_theta_max = radius * radius / dist2;
  // Inside the cone by the sine of the angle to the centre, not its cosine: a distant
  // sphere's narrow cone has cosines that round to within a few percent of their distance
  // from 1, which turned away directions sampled at its rim. The slack keeps directions
  // to the rim inside after rounding.
  if (!(Dot(w, to_center) > 0)) return 0;
  if (LengthSquared(Cross(w, to_center)) / dist2 > sin2_theta_max * (1 + 1e-4f)) return 0;
  return 1 / (2 * kPi * OneMinusCosThetaMax(sin2_theta_max));
}

}  // namespace farm
