#include "scene/principled.h"

#include <algorithm>
#include <cmath>

#include "math/math.h"
#include "sampling/warps.h"
#include "scene/fresnel.h"
#include "scene/ggx.h"

namespace farm {
namespace {

// The Fresnel reflectance of glTF's dielectric (ior 1.5) at normal incidence.
constexpr float kDielectricF0 = 0.04f;

float SchlickWeight(float cos) {
  const float m = std::clamp(1 - cos, 0.0f, 1.0f);
  const float m2 = m * m;
  return m2 * m2 * m;
}

Rgb F0Of(const PrincipledLobes& m) {
  return Rgb(kDielectricF0 * (1 - m.metallic)) + m.base_color * m.metallic;
}

Rgb Schlick(const Rgb& f0, float cos) { return f0 + (Rgb(1) + f0 * -1) * SchlickWeight(cos); }

std::optional<Vec3> HalfVector(const Vec3& wo, const Vec3& wi) {
  const Vec3 sum = wo + wi;
  const float len2 = LengthSquared(sum);
  if (!(len2 > 0)) return std::nullopt;
  return sum / std::sqrt(len2);
}

// The diffuse base's f times pi at the half vector's cosine wo.h.
Rgb DiffuseWeight(const PrincipledLobes& m, float wo_h) {
  return m.base_color * ((1 - m.metallic) * (1 - (kDielectricF0 + (1 - kDielectricF0) * SchlickWeight(wo_h))));
}

}  // namespace

Rgb PrincipledValue(const PrincipledLobes& m, const Vec3& wo, const Vec3& wi) {
  if (!(wo.z > 0) || !(wi.z > 0)) return {};
  const std::optional<Vec3> h = HalfVector(wo, wi);
  if (!h) return {};
  const float wo_h = Dot(wo, *h);
  Rgb f = DiffuseWeight(m, wo_h) * kInvPi;
  if (!m.specular)
    f += Schlick(F0Of(m), wo_h) * (GgxD(*h, m.alpha) * GgxG2(wo, wi, m.alpha) / (4 * wo.z * wi.z));
  return f;
}

float SpecularLobeProbability(const PrincipledLobes& m, const Vec3& wo) {
  const float cos = std::max(0.0f, wo.z);
  const float specular = Schlick(F0Of(m), cos).Luminance();
  const float diffuse = DiffuseWeight(m, cos).Luminance();
  return specular + diffuse > 0 ? specular / (specular + diffuse) : 1.0f;
}

float PrincipledPdf(const PrincipledLobes& m, const Vec3& wo, const Vec3& wi) {
  if (!(wo.z > 0) || !(wi.z > 0)) return 0;
  const float p_specular = SpecularLobeProbability(m, wo);
  const float diffuse = (1 - p_specular) * CosineHemispherePdf(wi.z);
  return m.specular ? diffuse : diffuse + p_specular * GgxReflectionPdf(wo, wi, m.alpha);
}

std::optional<PrincipledSample> SamplePrincipledSpecular(const PrincipledLobes& m, const Vec3& wo, Vec2 u) {
  if (!(wo.z > 0)) return std::nullopt;
  const Vec3 h = SampleGgxVisibleNormal(wo, m.alpha, u);
  const Vec3 wi = Reflect(wo, h);
  if (!(wi.z > 0)) return std::nullopt;
  // f cos / pdf = F D G2 / (4 wo.z wi.z) wi.z / (G1(wo) D / (4 wo.z)) = F G2 / G1(wo).
  const Rgb weight = Schlick(F0Of(m), Dot(wo, h)) * (GgxG2(wo, wi, m.alpha) / GgxG1(wo, m.alpha));
  return PrincipledSample{wi, weight, m.specular ? 0.0f : GgxReflectionPdf(wo, wi, m.alpha), m.specular};
}

std::optional<PrincipledSample> SamplePrincipled(const PrincipledLobes& m, const Vec3& wo, float u_lobe, Vec2 u) {
  if (!(wo.z > 0)) return std::nullopt;
  const float p_specular = SpecularLobeProbability(m, wo);
  if (m.specular && u_lobe < p_specular) {
    std::optional<PrincipledSample> s = SamplePrincipledSpecular(m, wo, u);
    if (s) s->weight = s->weight / p_specular;
    return s;
  }
  const Vec3 wi = u_lobe < p_specular ? Reflect(wo, SampleGgxVisibleNormal(wo, m.alpha, u)) : SampleCosineHemisphere(u);
  if (!(wi.z > 0)) return std::nullopt;
  // The density of the mixture, whichever lobe drew the direction (one-sample MIS).
  const float pdf = PrincipledPdf(m, wo, wi);
  if (!(pdf > 0)) return std::nullopt;
  return PrincipledSample{wi, PrincipledValue(m, wo, wi) * (wi.z / pdf), pdf, false};
}

Rgb PrincipledDiffuseWeight(const PrincipledLobes& m, const Vec3& wo, const Vec3& wi) {
  if (!(wo.z > 0) || !(wi.z > 0)) return {};
  const std::optional<Vec3> h = HalfVector(wo, wi);
  return h ? DiffuseWeight(m, Dot(wo, *h)) : Rgb();
}

Rgb PrincipledAlbedo(const PrincipledLobes& m) {
  return m.base_color * ((1 - m.metallic) * (1 - kDielectricF0)) + F0Of(m);
}

}  // namespace farm
