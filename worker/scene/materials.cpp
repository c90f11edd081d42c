#include "scene/materials.h"

#include <cmath>

#include "math/math.h"
#include "renderfarm/v1/scene.pb.h"
#include "scene/scene.h"

namespace farm {
namespace {

Rgb ColorFromProto(const renderfarm::v1::Color& c) {
  return {static_cast<float>(c.r()), static_cast<float>(c.g()), static_cast<float>(c.b())};
}

void CheckColor(const Rgb& c, float max, const std::string& field) {
  for (float v : {c.r, c.g, c.b})
    if (!std::isfinite(v) || v < 0 || v > max)
      throw SceneError(field + ": component " + std::to_string(v) + " outside [0, " +
                       (std::isinf(max) ? std::string("inf") : std::to_string(max)) + "]");
}

}  // namespace

Material MaterialFromProto(const renderfarm::v1::Material& material, const std::string& field) {
  using M = renderfarm::v1::Material;
  switch (material.kind_case()) {
    case M::kLambert: {
      const Rgb rho = ColorFromProto(material.lambert().reflectance());
      CheckColor(rho, 1.0f, field + ".lambert.reflectance");
      return LambertMaterial{rho};
    }
    case M::kEmissive: {
      const Rgb radiance = ColorFromProto(material.emissive().radiance());
      CheckColor(radiance, INFINITY, field + ".emissive.radiance");
      return EmissiveMaterial{radiance};
    }
    case M::KIND_NOT_SET:
      break;
  }
  throw SceneError(field + ": no material kind set (lambert or emissive)");
}

Rgb EvaluateBsdf(const Material& material, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  struct Visitor {
    const Vec3 &n, &wo, &wi;
    Rgb operator()(const LambertMaterial& m) const {
      const bool same_side = (Dot(n, wo) > 0) == (Dot(n, wi) > 0);
      return same_side ? m.reflectance * kInvPi : Rgb();
    }
    Rgb operator()(const EmissiveMaterial&) const { return {}; }
  };
  return std::visit(Visitor{n, wo, wi}, material);
}

Rgb Emitted(const Material& material, const Vec3& n, const Vec3& w) {
  if (const auto* e = std::get_if<EmissiveMaterial>(&material))
    return Dot(n, w) > 0 ? e->radiance : Rgb();
  return {};
}

bool Reflects(const Material& material) {
  return std::holds_alternative<LambertMaterial>(material);
}

std::string ToString(const Material& material) {
  struct Visitor {
    std::string operator()(const LambertMaterial& m) const {
      return "Lambert{reflectance=" + ToString(m.reflectance) + "}";
    }
    std::string operator()(const EmissiveMaterial& m) const {
      return "Emissive{radiance=" + ToString(m.radiance) + "}";
    }
  };
  return std::visit(Visitor{}, material);
}

}  // namespace farm
