#pragma once

// Surface materials: a closed set of value types dispatched with std::visit (they are
// evaluated at every shading point, so no virtual calls).
//
//   lambert   reflectance rho (linear RGB in [0,1])   ideal diffuse: f = rho / pi, on both
//                                                     sides of the surface ("two-sided")
//   emissive  radiance L (linear RGB, >= 0)           emits L from the front side only,
//                                                     reflects nothing; makes its shape an
//                                                     area light
//
// Later kinds (glossy, mirror, glass, metal) add sampling of the BSDF, which photon tracing
// needs, next to Evaluate.

#include <string>
#include <variant>

#include "math/rgb.h"
#include "math/vec3.h"

namespace renderfarm::v1 {
class Material;
}

namespace farm {

struct LambertMaterial {
  Rgb reflectance;
};

struct EmissiveMaterial {
  Rgb radiance;
};

using Material = std::variant<LambertMaterial, EmissiveMaterial>;

// Throws SceneError naming `field` (e.g. "materials[2]") if no kind is set or a value is out
// of range.
Material MaterialFromProto(const renderfarm::v1::Material& material, const std::string& field);

// BSDF value for light arriving along wi and leaving along wo (both unit, pointing away from
// the surface) at a surface with geometric normal n. Two-sided: either side reflects, but
// light cannot cross the surface (wo and wi on opposite sides give zero).
Rgb EvaluateBsdf(const Material& material, const Vec3& n, const Vec3& wo, const Vec3& wi);

// Radiance emitted along w (unit, away from the surface) from a surface whose front normal
// is n: nonzero only on the front side of emissive materials.
Rgb Emitted(const Material& material, const Vec3& n, const Vec3& w);

// Whether the material reflects light (and so needs direct lighting where it is hit).
bool Reflects(const Material& material);

std::string ToString(const Material& material);

}  // namespace farm
