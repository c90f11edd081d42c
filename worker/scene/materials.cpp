#include "scene/materials.h"

#include <algorithm>
#include <cmath>

#include "math/frame.h"
#include "math/math.h"
#include "renderfarm/v1/scene.pb.h"
#include "sampling/warps.h"
#include "scene/blinn_phong.h"
#include "scene/fresnel.h"
#include "scene/scene.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

Rgb ColorFromProto(const pb::Color& c) {
  return {static_cast<float>(c.r()), static_cast<float>(c.g()), static_cast<float>(c.b())};
}

void CheckColor(const Rgb& c, float min, float max, const std::string& field) {
  for (float v : {c.r, c.g, c.b})
    if (!std::isfinite(v) || v < min || v > max)
      throw SceneError(field + ": component " + std::to_string(v) + " outside [" +
                       std::to_string(min) + ", " +
                       (std::isinf(max) ? std::string("inf") : std::to_string(max)) + "]");
}

Rgb CheckedColor(const pb::Color& c, float min, float max, const std::string& field) {
  const Rgb rgb = ColorFromProto(c);
  CheckColor(rgb, min, max, field);
  return rgb;
}

float CheckedScalar(double v, double min, double max, const std::string& field) {
  if (!std::isfinite(v) || v < min || v > max)
    throw SceneError(field + ": " + std::to_string(v) + " outside [" + std::to_string(min) +
                     ", " + std::to_string(max) + "]");
  return static_cast<float>(v);
}

// Probability of picking the diffuse lobe of a glossy material.
float DiffuseLobeProbability(const GlossyMaterial& m) {
  const float d = m.diffuse.Luminance(), s = m.specular.Luminance();
  return d + s > 0 ? d / (d + s) : 0.0f;
}

}  // namespace

Material MaterialFromProto(const pb::Material& material, const std::string& field) {
  switch (material.kind_case()) {
    case pb::Material::kLambert:
      return LambertMaterial{
          CheckedColor(material.lambert().reflectance(), 0, 1, field + ".lambert.reflectance")};
    case pb::Material::kEmissive:
      return EmissiveMaterial{
          CheckedColor(material.emissive().radiance(), 0, INFINITY, field + ".emissive.radiance")};
    case pb::Material::kGlossy: {
      const pb::Glossy& g = material.glossy();
      GlossyMaterial m;
      m.diffuse = CheckedColor(g.diffuse(), 0, 1, field + ".glossy.diffuse");
      m.specular = CheckedColor(g.specular(), 0, 1, field + ".glossy.specular");
      CheckColor(m.diffuse + m.specular, 0, 1.0f + 1e-6f, field + ".glossy: diffuse + specular");
      m.exponent = CheckedScalar(g.exponent(), 1, 1e5, field + ".glossy.exponent");
      return m;
    }
    case pb::Material::kMirror:
      return MirrorMaterial{
          CheckedColor(material.mirror().reflectance(), 0, 1, field + ".mirror.reflectance")};
    case pb::Material::kDielectric: {
      const pb::Dielectric& d = material.dielectric();
      DielectricMaterial m;
      m.ior = CheckedScalar(d.ior(), 1, 10, field + ".dielectric.ior");
      if (d.has_transmittance())
        m.transmittance =
            CheckedColor(d.transmittance(), 0, 1, field + ".dielectric.transmittance");
      return m;
    }
    case pb::Material::kConductor: {
      const pb::Conductor& c = material.conductor();
      ConductorMaterial m;
      m.eta = CheckedColor(c.eta(), 1e-3f, 100, field + ".conductor.eta");
      m.k = CheckedColor(c.k(), 0, 100, field + ".conductor.k");
      return m;
    }
    case pb::Material::KIND_NOT_SET:
      break;
  }
  throw SceneError(field +
                   ": no material kind set (lambert, emissive, glossy, mirror, dielectric or "
                   "conductor)");
}

Rgb EvaluateBsdf(const Material& material, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  // Non-specular kinds reflect on both sides but never across the surface.
  const bool same_side = (Dot(n, wo) > 0) == (Dot(n, wi) > 0);
  if (!same_side) return {};
  if (const auto* m = std::get_if<LambertMaterial>(&material)) return m->reflectance * kInvPi;
  if (const auto* m = std::get_if<GlossyMaterial>(&material)) {
    const Frame frame = Frame::FromZ(FaceForward(n, wo));
    const float lobe = BlinnPhongValue(frame.ToLocal(wo), frame.ToLocal(wi), m->exponent);
    return m->diffuse * kInvPi + m->specular * lobe;
  }
  return {};
}

float BsdfPdf(const Material& material, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  const Vec3 ns = FaceForward(n, wo);
  const float cos_i = Dot(ns, wi);
  if (!(cos_i > 0)) return 0;
  if (std::holds_alternative<LambertMaterial>(material)) return CosineHemispherePdf(cos_i);
  if (const auto* m = std::get_if<GlossyMaterial>(&material)) {
    const Frame frame = Frame::FromZ(ns);
    const float p_diffuse = DiffuseLobeProbability(*m);
    return p_diffuse * CosineHemispherePdf(cos_i) +
           (1 - p_diffuse) * BlinnPhongPdf(frame.ToLocal(wo), frame.ToLocal(wi), m->exponent);
  }
  return 0;
}

std::optional<BsdfSample> SampleBsdf(const Material& material, const Vec3& n, const Vec3& wo,
                                     float u_lobe, Vec2 u, TransportMode mode) {
  struct Visitor {
    const Vec3 &n, &wo;
    float u_lobe;
    Vec2 u;
    TransportMode mode;

    std::optional<BsdfSample> operator()(const LambertMaterial& m) const {
      const Frame frame = Frame::FromZ(FaceForward(n, wo));
      const Vec3 local = SampleCosineHemisphere(u);
      if (!(local.z > 0)) return std::nullopt;
      return BsdfSample{frame.FromLocal(local), m.reflectance, CosineHemispherePdf(local.z), false};
    }

    std::optional<BsdfSample> operator()(const GlossyMaterial& m) const {
      const Frame frame = Frame::FromZ(FaceForward(n, wo));
      const Vec3 wo_local = frame.ToLocal(wo);
      if (!(wo_local.z > 0)) return std::nullopt;
      const float p_diffuse = DiffuseLobeProbability(m);
      if (m.diffuse.IsBlack() && m.specular.IsBlack()) return std::nullopt;
      Vec3 wi_local;
      if (u_lobe < p_diffuse) {
        wi_local = SampleCosineHemisphere(u);
      } else {
        const std::optional<Vec3> w = SampleBlinnPhong(wo_local, u, m.exponent);
        if (!w) return std::nullopt;
        wi_local = *w;
      }
      if (!(wi_local.z > 0)) return std::nullopt;
      // The density of the mixture, whichever lobe drew the direction (one-sample MIS).
      const float pdf = p_diffuse * CosineHemispherePdf(wi_local.z) +
                        (1 - p_diffuse) * BlinnPhongPdf(wo_local, wi_local, m.exponent);
      if (!(pdf > 0)) return std::nullopt;
      const Rgb f = m.diffuse * kInvPi +
                    m.specular * BlinnPhongValue(wo_local, wi_local, m.exponent);
      return BsdfSample{frame.FromLocal(wi_local), f * (wi_local.z / pdf), pdf, false};
    }

    std::optional<BsdfSample> operator()(const MirrorMaterial& m) const {
      return BsdfSample{Reflect(wo, FaceForward(n, wo)), m.reflectance, 0, true};
    }

    std::optional<BsdfSample> operator()(const ConductorMaterial& m) const {
      const Vec3 ns = FaceForward(n, wo);
      const float cos_o = Dot(ns, wo);
      const Rgb fresnel(FresnelConductor(cos_o, m.eta.r, m.k.r),
                        FresnelConductor(cos_o, m.eta.g, m.k.g),
                        FresnelConductor(cos_o, m.eta.b, m.k.b));
      return BsdfSample{Reflect(wo, ns), fresnel, 0, true};
    }

    std::optional<BsdfSample> operator()(const DielectricMaterial& m) const {
      const float cos_o = Dot(n, wo);
      const bool outside = cos_o > 0;  // the front side is the outside
      // eta: index on the far side of the interface relative to wo's side.
      const float eta = outside ? m.ior : 1 / m.ior;
      const Vec3 ns = outside ? n : -n;
      const float reflectance = FresnelDielectric(std::abs(cos_o), eta);
      // Reflect or transmit with probabilities R and 1 - R: the Fresnel factor cancels in
      // the weight, so a path's throughput never exceeds the tint.
      if (u_lobe < reflectance) return BsdfSample{Reflect(wo, ns), Rgb(1), 0, true};
      const std::optional<Vec3> wt = Refract(wo, ns, eta);
      if (!wt) return BsdfSample{Reflect(wo, ns), Rgb(1), 0, true};  // TIR (R = 1 anyway)
      Rgb weight = m.transmittance;
      // Radiance arriving from the far side is divided by eta^2 (the beam's solid angle
      // widens on the way out of the denser medium, narrows on the way in); photon flux
      // is conserved, so importance transport leaves it alone.
      if (mode == TransportMode::kRadiance) weight = weight / (eta * eta);
      return BsdfSample{*wt, weight, 0, true};
    }

    std::optional<BsdfSample> operator()(const EmissiveMaterial&) const { return std::nullopt; }
  };
  return std::visit(Visitor{n, wo, u_lobe, u, mode}, material);
}

Rgb Emitted(const Material& material, const Vec3& n, const Vec3& w) {
  if (const auto* e = std::get_if<EmissiveMaterial>(&material))
    return Dot(n, w) > 0 ? e->radiance : Rgb();
  return {};
}

bool IsSpecular(const Material& material) {
  return std::holds_alternative<MirrorMaterial>(material) ||
         std::holds_alternative<DielectricMaterial>(material) ||
         std::holds_alternative<ConductorMaterial>(material);
}

bool Reflects(const Material& material) {
  return std::holds_alternative<LambertMaterial>(material) ||
         std::holds_alternative<GlossyMaterial>(material);
}

float DiffuseFraction(const Material& material) {
  if (std::holds_alternative<LambertMaterial>(material)) return 1;
  if (const auto* m = std::get_if<GlossyMaterial>(&material)) return DiffuseLobeProbability(*m);
  return 0;
}

Rgb Albedo(const Material& material) {
  struct Visitor {
    Rgb operator()(const LambertMaterial& m) const { return m.reflectance; }
    Rgb operator()(const GlossyMaterial& m) const { return m.diffuse + m.specular; }
    Rgb operator()(const MirrorMaterial& m) const { return m.reflectance; }
    Rgb operator()(const DielectricMaterial& m) const { return m.transmittance; }
    Rgb operator()(const ConductorMaterial& m) const {
      return {FresnelConductor(1, m.eta.r, m.k.r), FresnelConductor(1, m.eta.g, m.k.g),
              FresnelConductor(1, m.eta.b, m.k.b)};
    }
    Rgb operator()(const EmissiveMaterial&) const { return {}; }
  };
  return std::visit(Visitor{}, material);
}

std::string ToString(const Material& material) {
  struct Visitor {
    std::string operator()(const LambertMaterial& m) const {
      return "Lambert{reflectance=" + ToString(m.reflectance) + "}";
    }
    std::string operator()(const GlossyMaterial& m) const {
      return "Glossy{diffuse=" + ToString(m.diffuse) + ", specular=" + ToString(m.specular) +
             ", exponent=" + std::to_string(m.exponent) + "}";
    }
    std::string operator()(const MirrorMaterial& m) const {
      return "Mirror{reflectance=" + ToString(m.reflectance) + "}";
    }
    std::string operator()(const DielectricMaterial& m) const {
      return "Dielectric{ior=" + std::to_string(m.ior) +
             ", transmittance=" + ToString(m.transmittance) + "}";
    }
    std::string operator()(const ConductorMaterial& m) const {
      return "Conductor{eta=" + ToString(m.eta) + ", k=" + ToString(m.k) + "}";
    }
    std::string operator()(const EmissiveMaterial& m) const {
      return "Emissive{radiance=" + ToString(m.radiance) + "}";
    }
  };
  return std::visit(Visitor{}, material);
}

}  // namespace farm
