#include "scene/materials.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "math/frame.h"
#include "math/math.h"
#include "contract/rules.h"
#include "renderfarm/v1/scene.pb.h"
#include "sampling/warps.h"
#include "scene/blinn_phong.h"
#include "scene/fresnel.h"
#include "scene/ggx.h"
#include "scene/proto_values.h"
#include "util/overloaded.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

// Probability of picking the diffuse lobe of a glossy material.
float DiffuseLobeProbability(const GlossyMaterial& m) {
  const float d = m.diffuse.Luminance(), s = m.specular.Luminance();
  return d + s > 0 ? d / (d + s) : 0.0f;
}

// The local frame of a principled material's lobes: about its shading normal, turned to
// the side of the geometric normal n that wo is on (a normal map's normal can lean away).
Frame PrincipledFrame(const PrincipledMaterial& m, const Vec3& n, const Vec3& wo) {
  const Vec3 front = FaceForward(n, wo);
  if (!(LengthSquared(m.shading_normal) > 0)) return Frame::FromZ(front);
  return Frame::FromZ(Dot(m.shading_normal, front) < 0 ? -m.shading_normal : m.shading_normal);
}

// A principled sample in world space, as a BsdfSample.
std::optional<BsdfSample> ToWorld(const Frame& frame, const std::optional<PrincipledSample>& s) {
  if (!s) return std::nullopt;
  return BsdfSample{frame.FromLocal(s->wi), s->weight, s->pdf, s->specular};
}

// A smooth dielectric's two ways on from wo: the mirror direction, reflected with Fresnel's
// R, and the refracted one (none under total internal reflection) with its weight per unit
// of transmitted light.
struct DielectricLobes {
  Vec3 reflected;
  float reflectance = 1;
  std::optional<Vec3> transmitted;
  Rgb transmitted_weight;
};

DielectricLobes DielectricLobesOf(const DielectricMaterial& m, const Vec3& n, const Vec3& wo, TransportMode mode) {
  const float cos_o = Dot(n, wo);
  const bool outside = cos_o > 0;  // the front side is the outside
  // eta: index on the far side of the interface relative to wo's side.
  const float eta = outside ? m.ior : 1 / m.ior;
  const Vec3 ns = outside ? n : -n;
  DielectricLobes lobes{Reflect(wo, ns), FresnelDielectric(std::abs(cos_o), eta), Refract(wo, ns, eta), Rgb()};
  if (!lobes.transmitted) {
    lobes.reflectance = 1;  // TIR (R = 1 anyway)
    return lobes;
  }
  lobes.transmitted_weight = m.transmittance;
  // Radiance arriving from the far side is divided by eta^2 (the beam's solid angle widens
  // on the way out of the denser medium, narrows on the way in); photon flux is conserved,
  // so importance transport leaves it alone.
  if (mode == TransportMode::kRadiance) lobes.transmitted_weight = lobes.transmitted_weight / (eta * eta);
  return lobes;
}

// A dispersion as the contract describes it, about the index ior at the d line.
Dispersion DispersionFromProto(const pb::Dispersion& d, double ior) {
  switch (d.law_case()) {
    case pb::Dispersion::kAbbeNumber:
      return CauchyFromAbbe(ior, d.abbe_number());
    case pb::Dispersion::kGlass:
      break;
    case pb::Dispersion::LAW_NOT_SET:
      throw std::invalid_argument("dispersion: no law (the scene was not checked)");
  }
  const char* name = "BK7";
  switch (d.glass()) {
    case pb::GLASS_UNSPECIFIED:
    case pb::GLASS_BK7:
      break;
    case pb::GLASS_FUSED_SILICA:
      name = "fused-silica";
      break;
    case pb::GLASS_DIAMOND:
      name = "diamond";
      break;
    case pb::GLASS_SF11:
      name = "flint-SF11";
      break;
    default:
      throw std::invalid_argument("dispersion.glass: unknown glass " + std::to_string(d.glass()));
  }
  return *NamedGlass(name);
}

PrincipledMaterial PrincipledFromProto(const pb::Principled& p) {
  PrincipledMaterial m;
  if (p.has_base_color()) m.lobes.base_color = RgbOf(p.base_color());
  m.lobes.metallic = static_cast<float>(p.metallic());
  m.roughness = static_cast<float>(p.roughness());
  m.lobes.alpha = std::max(kMinGgxAlpha, m.roughness * m.roughness);
  m.lobes.specular = p.roughness() < contract::SceneLimits().principled_specular_roughness();
  if (p.has_emission()) m.emission = RgbOf(p.emission());
  m.normal_scale = static_cast<float>(contract::OrDefault<pb::Principled>(p.normal_scale(), "normal_scale"));
  m.alpha_mask = p.alpha_mode() == pb::ALPHA_MODE_MASK;
  m.opacity = static_cast<float>(1 - p.transparency());
  m.alpha_cutoff = static_cast<float>(contract::OrDefault<pb::Principled>(p.alpha_cutoff(), "alpha_cutoff"));
  return m;
}

// Whether a principled material's diffuse base can reflect anything: not for a smooth full
// metal whose metallic no texture can lower (its lobe, a delta, is all there is).
bool PrincipledReflects(const PrincipledMaterial& m) {
  return !(m.lobes.specular && m.lobes.metallic == 1 && m.metallic_roughness_texture == kNoTexture);
}

// The share of a principled material's non-specular reflection that is diffuse, from its
// factors at normal incidence: 1 when its lobe counts as a delta.
float PrincipledDiffuseFraction(const PrincipledMaterial& m) {
  if (m.lobes.specular) return 1;
  const float p_specular = SpecularLobeProbability(m.lobes, Vec3(0, 0, 1));
  return 1 - p_specular;
}

}  // namespace

Material MaterialFromProto(const pb::Material& material) {
  switch (material.kind_case()) {
    case pb::Material::kLambert:
      return LambertMaterial{RgbOf(material.lambert().reflectance())};
    case pb::Material::kEmissive:
      return EmissiveMaterial{RgbOf(material.emissive().radiance()), RgbOf(material.emissive().reflectance())};
    case pb::Material::kGlossy: {
      const pb::Glossy& g = material.glossy();
      return GlossyMaterial{RgbOf(g.diffuse()), RgbOf(g.specular()),
                            static_cast<float>(g.exponent())};
    }
    case pb::Material::kMirror:
      return MirrorMaterial{RgbOf(material.mirror().reflectance())};
    case pb::Material::kDielectric: {
      const pb::Dielectric& d = material.dielectric();
      DielectricMaterial m;
      m.ior = static_cast<float>(d.ior());
      if (d.has_transmittance()) m.transmittance = RgbOf(d.transmittance());
      if (d.has_dispersion()) m.dispersion = DispersionFromProto(d.dispersion(), d.ior());
      return m;
    }
    case pb::Material::kConductor:
      return ConductorMaterial{RgbOf(material.conductor().eta()),
                               RgbOf(material.conductor().k())};
    case pb::Material::kPrincipled:
      return PrincipledFromProto(material.principled());
    case pb::Material::KIND_NOT_SET:
      break;
  }
  throw std::logic_error("MaterialFromProto: a material without a kind (CheckRules refuses it)");
}

MaterialCapabilities CapabilitiesOf(const Material& material) {
  return std::visit(
      Overloaded{
          [](const LambertMaterial&) { return MaterialCapabilities{false, true, false, 1}; },
          [](const GlossyMaterial& m) {
            return MaterialCapabilities{false, true, false, DiffuseLobeProbability(m)};
          },
          [](const OneOf<MirrorMaterial, DielectricMaterial, ConductorMaterial> auto&) {
            return MaterialCapabilities{true, false, false, 0};
          },
          [](const EmissiveMaterial& m) {
            const bool reflects = !m.reflectance.IsBlack();
            return MaterialCapabilities{false, reflects, !m.radiance.IsBlack(), reflects ? 1.0f : 0.0f};
          },
          [](const PrincipledMaterial& m) {
            return MaterialCapabilities{m.lobes.specular, PrincipledReflects(m), !m.emission.IsBlack(),
                                        PrincipledDiffuseFraction(m)};
          },
      },
      material);
}

Rgb EvaluateBsdf(const Material& material, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  // Non-specular kinds reflect on both sides but never across the surface.
  const bool same_side = (Dot(n, wo) > 0) == (Dot(n, wi) > 0);
  if (!same_side) return {};
  return std::visit(
      Overloaded{
          [](const LambertMaterial& m) { return m.reflectance * kInvPi; },
          [](const EmissiveMaterial& m) { return m.reflectance * kInvPi; },
          [&](const GlossyMaterial& m) {
            const Frame frame = Frame::FromZ(FaceForward(n, wo));
            const float lobe = BlinnPhongValue(frame.ToLocal(wo), frame.ToLocal(wi), m.exponent);
            return m.diffuse * kInvPi + m.specular * lobe;
          },
          [&](const PrincipledMaterial& m) {
            const Frame frame = PrincipledFrame(m, n, wo);
            return PrincipledValue(m.lobes, frame.ToLocal(wo), frame.ToLocal(wi));
          },
          [](const OneOf<MirrorMaterial, DielectricMaterial, ConductorMaterial> auto&) { return Rgb(); },
      },
      material);
}

float BsdfPdf(const Material& material, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  const Vec3 ns = FaceForward(n, wo);
  const float cos_i = Dot(ns, wi);
  if (!(cos_i > 0)) return 0;
  return std::visit(
      Overloaded{
          [&](const OneOf<LambertMaterial, EmissiveMaterial> auto&) { return CosineHemispherePdf(cos_i); },
          [&](const GlossyMaterial& m) {
            const Frame frame = Frame::FromZ(ns);
            const float p_diffuse = DiffuseLobeProbability(m);
            return p_diffuse * CosineHemispherePdf(cos_i) +
                   (1 - p_diffuse) * BlinnPhongPdf(frame.ToLocal(wo), frame.ToLocal(wi), m.exponent);
          },
          [&](const PrincipledMaterial& m) {
            const Frame frame = PrincipledFrame(m, n, wo);
            return PrincipledPdf(m.lobes, frame.ToLocal(wo), frame.ToLocal(wi));
          },
          [](const OneOf<MirrorMaterial, DielectricMaterial, ConductorMaterial> auto&) { return 0.0f; },
      },
      material);
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
      // Reflect or transmit with probabilities R and 1 - R: the Fresnel factor cancels in
      // the weight, so a path's throughput never exceeds the tint.
      const DielectricLobes lobes = DielectricLobesOf(m, n, wo, mode);
      if (u_lobe < lobes.reflectance || !lobes.transmitted) return BsdfSample{lobes.reflected, Rgb(1), 0, true};
      return BsdfSample{*lobes.transmitted, lobes.transmitted_weight, 0, true};
    }

    std::optional<BsdfSample> operator()(const EmissiveMaterial& m) const {
      if (m.reflectance.IsBlack()) return std::nullopt;
      return (*this)(LambertMaterial{m.reflectance});
    }

    std::optional<BsdfSample> operator()(const PrincipledMaterial& m) const {
      const Frame frame = PrincipledFrame(m, n, wo);
      return ToWorld(frame, SamplePrincipled(m.lobes, frame.ToLocal(wo), u_lobe, u));
    }
  };
  return std::visit(Visitor{n, wo, u_lobe, u, mode}, material);
}

std::optional<BsdfSample> SampleSpecular(const Material& material, const Vec3& n, const Vec3& wo,
                                         float u_lobe, Vec2 u, TransportMode mode) {
  return std::visit(
      Overloaded{
          [&](const OneOf<MirrorMaterial, DielectricMaterial, ConductorMaterial> auto&) {
            return SampleBsdf(material, n, wo, u_lobe, u, mode);
          },
          [&](const PrincipledMaterial& m) -> std::optional<BsdfSample> {
            if (!m.lobes.specular) return std::nullopt;
            const Frame frame = PrincipledFrame(m, n, wo);
            return ToWorld(frame, SamplePrincipledSpecular(m.lobes, frame.ToLocal(wo), u));
          },
          [](const OneOf<LambertMaterial, GlossyMaterial, EmissiveMaterial> auto&) {
            return std::optional<BsdfSample>();
          },
      },
      material);
}

std::optional<SpecularSplit> SplitSpecular(const Material& material, const Vec3& n, const Vec3& wo,
                                           TransportMode mode) {
  return std::visit(
      Overloaded{
          [&](const DielectricMaterial& m) -> std::optional<SpecularSplit> {
            const DielectricLobes lobes = DielectricLobesOf(m, n, wo, mode);
            SpecularSplit split{BsdfSample{lobes.reflected, Rgb(lobes.reflectance), 0, true}, std::nullopt};
            if (lobes.transmitted)
              split.transmitted =
                  BsdfSample{*lobes.transmitted, lobes.transmitted_weight * (1 - lobes.reflectance), 0, true};
            return split;
          },
          [](const OneOf<LambertMaterial, GlossyMaterial, MirrorMaterial, ConductorMaterial, EmissiveMaterial,
                         PrincipledMaterial> auto&) { return std::optional<SpecularSplit>(); },
      },
      material);
}

bool IsDispersive(const Material& material) {
  const auto* d = std::get_if<DielectricMaterial>(&material);
  return d != nullptr && d->dispersion.has_value();
}

Material AtWavelength(const Material& material, double lambda_nm) {
  const auto* d = std::get_if<DielectricMaterial>(&material);
  if (d == nullptr || !d->dispersion) return material;
  DielectricMaterial at = *d;
  at.ior = static_cast<float>(ScaledIndexAt(*d->dispersion, d->ior, lambda_nm));
  at.dispersion.reset();
  return at;
}

Rgb Emission(const Material& material) {
  return std::visit(
      Overloaded{
          [](const EmissiveMaterial& e) { return e.radiance; },
          [](const PrincipledMaterial& m) { return m.emission; },
          [](const OneOf<LambertMaterial, GlossyMaterial, MirrorMaterial, DielectricMaterial,
                         ConductorMaterial> auto&) { return Rgb(); },
      },
      material);
}

Rgb Emitted(const Material& material, const Vec3& n, const Vec3& w) {
  return Dot(n, w) > 0 ? Emission(material) : Rgb();
}

Rgb DiffuseReflectance(const Material& material, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  return std::visit(
      Overloaded{
          [](const OneOf<LambertMaterial, EmissiveMaterial> auto& m) { return m.reflectance; },
          [](const GlossyMaterial& m) { return m.diffuse; },
          [&](const PrincipledMaterial& m) {
            const Frame frame = PrincipledFrame(m, n, wo);
            return PrincipledDiffuseWeight(m.lobes, frame.ToLocal(wo), frame.ToLocal(wi));
          },
          [](const OneOf<MirrorMaterial, DielectricMaterial, ConductorMaterial> auto&) { return Rgb(); },
      },
      material);
}

std::optional<BsdfSample> SampleGlossyLobe(const Material& material, const Vec3& n, const Vec3& wo, Vec2 u) {
  return std::visit(
      Overloaded{
          [&](const GlossyMaterial& m) -> std::optional<BsdfSample> {
            if (m.specular.IsBlack()) return std::nullopt;
            const Frame frame = Frame::FromZ(FaceForward(n, wo));
            const Vec3 wo_local = frame.ToLocal(wo);
            if (!(wo_local.z > 0)) return std::nullopt;
            const std::optional<Vec3> w = SampleBlinnPhong(wo_local, u, m.exponent);
            if (!w || !(w->z > 0)) return std::nullopt;
            // blinn_phong.h: a sampled direction carries f cos / pdf = wi.z / max(wo.z, wi.z).
            return BsdfSample{frame.FromLocal(*w), m.specular * (w->z / std::max(wo_local.z, w->z)),
                              BlinnPhongPdf(wo_local, *w, m.exponent), false};
          },
          [&](const PrincipledMaterial& m) -> std::optional<BsdfSample> {
            if (m.lobes.specular) return std::nullopt;
            const Frame frame = PrincipledFrame(m, n, wo);
            return ToWorld(frame, SamplePrincipledSpecular(m.lobes, frame.ToLocal(wo), u));
          },
          [](const OneOf<LambertMaterial, MirrorMaterial, DielectricMaterial, ConductorMaterial,
                         EmissiveMaterial> auto&) { return std::optional<BsdfSample>(); },
      },
      material);
}

float GlossyLobePdf(const Material& material, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  return std::visit(
      Overloaded{
          [&](const GlossyMaterial& m) {
            if (m.specular.IsBlack()) return 0.0f;
            const Frame frame = Frame::FromZ(FaceForward(n, wo));
            return BlinnPhongPdf(frame.ToLocal(wo), frame.ToLocal(wi), m.exponent);
          },
          [&](const PrincipledMaterial& m) {
            if (m.lobes.specular) return 0.0f;
            const Frame frame = PrincipledFrame(m, n, wo);
            const Vec3 wi_local = frame.ToLocal(wi);
            // SamplePrincipledSpecular draws nothing below the horizon.
            return wi_local.z > 0 ? GgxReflectionPdf(frame.ToLocal(wo), wi_local, m.lobes.alpha) : 0.0f;
          },
          [](const OneOf<LambertMaterial, MirrorMaterial, DielectricMaterial, ConductorMaterial,
                         EmissiveMaterial> auto&) { return 0.0f; },
      },
      material);
}

Vec3 ShadingNormalOf(const Material& material, const Vec3& ns) {
  const auto* m = std::get_if<PrincipledMaterial>(&material);
  return m && LengthSquared(m->shading_normal) > 0 ? m->shading_normal : ns;
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
    Rgb operator()(const EmissiveMaterial& m) const { return m.reflectance; }
    Rgb operator()(const PrincipledMaterial& m) const { return PrincipledAlbedo(m.lobes); }
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
      return "Dielectric{ior=" + std::to_string(m.ior) + ", transmittance=" + ToString(m.transmittance) +
             (m.dispersion ? ", dispersion=" + ToString(*m.dispersion) : std::string()) + "}";
    }
    std::string operator()(const ConductorMaterial& m) const {
      return "Conductor{eta=" + ToString(m.eta) + ", k=" + ToString(m.k) + "}";
    }
    std::string operator()(const EmissiveMaterial& m) const {
      return "Emissive{radiance=" + ToString(m.radiance) + ", reflectance=" + ToString(m.reflectance) + "}";
    }
    std::string operator()(const PrincipledMaterial& m) const {
      return "Principled{base_color=" + ToString(m.lobes.base_color) + ", metallic=" + std::to_string(m.lobes.metallic) +
             ", roughness=" + std::to_string(m.roughness) + (m.lobes.specular ? " (specular)" : "") +
             ", emission=" + ToString(m.emission) + "}";
    }
  };
  return std::visit(Visitor{}, material);
}

}  // namespace farm
