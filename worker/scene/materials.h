#pragma once

// Surface materials: a closed set of value types dispatched with std::visit (they are
// evaluated at every shading point, so no virtual calls). n below is the geometric normal
// of the shape's front side.
//
//   lambert     reflectance rho in [0,1]       ideal diffuse f = rho / pi, two-sided
//   glossy      diffuse kd, specular ks,       Blinn-Phong: kd / pi plus ks times the
//               exponent e in [1, 1e5],        energy-normalised lobe of blinn_phong.h;
//               kd + ks <= 1 per channel       two-sided; sampled by picking a lobe in
//                                              proportion to the luminance of kd and ks
//   mirror      reflectance                    perfect specular reflection, two-sided
//   dielectric  ior in [1, 10] (inside         smooth glass: reflects with Fresnel's R and
//               relative to outside),          transmits with 1 - R (one of the two chosen
//               transmittance (default 1)      at random by those weights), total internal
//                                              reflection; the front side is the outside;
//                                              transmitted light is tinted by transmittance
//   conductor   eta, k per channel             smooth metal, exact complex Fresnel
//   emissive    radiance L >= 0                emits L from the front only, reflects nothing
//
// Mirror, dielectric and conductor are specular: their BSDF is a delta function, so
// EvaluateBsdf gives 0 for them and only SampleBsdf moves light across them; photon maps
// never store photons on them. Lambert and glossy are the non-specular ("diffuse") kinds.

#include <optional>
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

struct GlossyMaterial {
  Rgb diffuse;
  Rgb specular;
  float exponent = 1;
};

struct MirrorMaterial {
  Rgb reflectance;
};

struct DielectricMaterial {
  float ior = 1.5f;
  Rgb transmittance{1};
};

struct ConductorMaterial {
  Rgb eta;
  Rgb k;
};

struct EmissiveMaterial {
  Rgb radiance;
};

using Material = std::variant<LambertMaterial, GlossyMaterial, MirrorMaterial, DielectricMaterial,
                              ConductorMaterial, EmissiveMaterial>;

// Throws SceneError naming `field` (e.g. "materials[2]") if no kind is set or a value is out
// of range.
Material MaterialFromProto(const renderfarm::v1::Material& material, const std::string& field);

// What a path carries: radiance (camera paths) or flux (photons). They differ at a
// refraction, where radiance is scaled by (eta_from / eta_to)^2 as the beam's solid angle
// is compressed, while flux is conserved.
enum class TransportMode { kRadiance, kImportance };

// BSDF value for light arriving along wi and leaving along wo (both unit, pointing away from
// the surface). Only the non-specular part: zero for specular materials.
Rgb EvaluateBsdf(const Material& material, const Vec3& n, const Vec3& wo, const Vec3& wi);

// Density over solid angle with which SampleBsdf picks wi given wo (non-specular kinds).
float BsdfPdf(const Material& material, const Vec3& n, const Vec3& wo, const Vec3& wi);

struct BsdfSample {
  Vec3 wi;
  // f cos(theta_i) / pdf: what the path's throughput (or a photon's power) is multiplied by.
  Rgb weight;
  float pdf = 0;          // for non-specular samples; 0 for specular ones (a delta)
  bool specular = false;  // a mirror reflection or refraction
};

// Samples the direction light arrives from (camera paths) or leaves to (photons), given the
// other direction wo, from three uniform numbers (u_lobe picks reflect/transmit or the lobe,
// u the direction). Nothing if the material absorbs the sample or emits only.
std::optional<BsdfSample> SampleBsdf(const Material& material, const Vec3& n, const Vec3& wo,
                                     float u_lobe, Vec2 u, TransportMode mode);

// Radiance emitted along w (unit, away from the surface) from a surface whose front normal
// is n: nonzero only on the front side of emissive materials.
Rgb Emitted(const Material& material, const Vec3& n, const Vec3& w);

// Whether the BSDF is a delta function (mirror, dielectric, conductor).
bool IsSpecular(const Material& material);

// Whether the material has a non-specular reflection, so that direct light and photon
// estimates apply where it is hit (Lambert, glossy).
bool Reflects(const Material& material);

// The share of a non-specular material's reflection that is diffuse, in [0, 1] (1 for
// Lambert): photons are stored on glossy surfaces with this probability.
float DiffuseFraction(const Material& material);

// Hemispherical reflectance at normal incidence, for the albedo AOV (transmittance for
// glass, emitters black).
Rgb Albedo(const Material& material);

std::string ToString(const Material& material);

}  // namespace farm
