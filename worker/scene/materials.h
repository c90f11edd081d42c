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
//               transmittance (default 1),     at random by those weights), total internal
//               dispersion (optional)          reflection; the front side is the outside;
//                                              transmitted light is tinted by transmittance;
//                                              a dispersive one is seen at one wavelength
//   conductor   eta, k per channel             smooth metal, exact complex Fresnel
//   emissive    radiance L >= 0, reflectance   emits L from the front only; reflects as a
//               rho (default 0)                lambert of rho (a light fixture lit by the room)
//   principled  base colour, metallic,         glTF's metallic-roughness BRDF (principled.h):
//               roughness, emission,           GGX sampled by visible normals over a
//               textures (read at a hit:       diffuse base, blended towards a metal of the
//               surface_shading.h), a          base colour by metallic; two-sided; emits
//               shading normal                 its emission from the front
//
// Mirror, dielectric and conductor are specular: their BSDF is a delta function, so
// EvaluateBsdf gives 0 for them and only SampleBsdf moves light across them; photon maps
// never store photons on them. Lambert and glossy are the non-specular ("diffuse") kinds,
// and so is an emissive material with a reflectance.
// A principled material is specular when its roughness factor is below
// SceneLimits.principled_specular_roughness (its GGX lobe then counts as a delta, which
// only SampleBsdf and SampleSpecular draw), non-specular otherwise, and also non-specular
// through its diffuse base unless it is a smooth full metal with no metallic texture: a
// smooth painted surface is both, shaded for its base and followed through its lobe.
// What each kind can do is its MaterialCapabilities, computed by one exhaustive visit.
//
// Every function here dispatches with std::visit and one overload per kind, with no
// catch-all: a new kind that one of them does not handle does not compile. The test
// ExhaustiveDispatch.* (scene/CMakeLists.txt) shows it by compiling this file's .cpp with
// FARM_TEST_UNHANDLED_MATERIAL, which adds a kind nothing handles, and requiring failure.

#include <optional>
#include <string>
#include <variant>

#include "math/rgb.h"
#include "math/vec3.h"
#include "scene/dispersion.h"
#include "scene/principled.h"

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
  float ior = 1.5f;  // at the d line (587.56 nm) when dispersive
  Rgb transmittance{1};
  // The law the index follows about ior (ScaledIndexAt); none: the same at every wavelength.
  std::optional<Dispersion> dispersion;
};

struct ConductorMaterial {
  Rgb eta;
  Rgb k;
};

struct EmissiveMaterial {
  Rgb radiance;
  Rgb reflectance;  // as a Lambert's; black: reflects nothing
};

// A texture of SceneData::textures a principled material reads (-1: none).
using TextureIndex = int;
inline constexpr TextureIndex kNoTexture = -1;

struct PrincipledMaterial {
  PrincipledLobes lobes;  // the factors; at a hit, with the textures applied
  float roughness = 0;    // perceptual (lobes.alpha is its square)
  Rgb emission;
  // Unit, or zero for the geometric normal: the normal the lobes are evaluated about at a
  // hit (smooth shading, the normal map).
  Vec3 shading_normal;
  // Textures, which multiply the factors: base colour (RGB) and opacity (alpha);
  // metallic (blue) and roughness (green); a tangent-space normal map; emission.
  TextureIndex base_color_texture = kNoTexture;
  TextureIndex metallic_roughness_texture = kNoTexture;
  TextureIndex normal_texture = kNoTexture;
  TextureIndex emission_texture = kNoTexture;
  float normal_scale = 1;
  // alpha_mode MASK: where opacity (1 - transparency, times the base colour texture's
  // alpha) is below alpha_cutoff, the surface is not there. (MaterialFromProto sets
  // normal_scale and alpha_cutoff with the contract's defaults.)
  bool alpha_mask = false;
  float opacity = 1;
  float alpha_cutoff = 0;
};

#ifdef FARM_TEST_UNHANDLED_MATERIAL  // test hook only: see the comment at the top
struct UnhandledMaterial {};
#define FARM_MATERIAL_TEST_KIND , UnhandledMaterial
#else
#define FARM_MATERIAL_TEST_KIND
#endif

using Material = std::variant<LambertMaterial, GlossyMaterial, MirrorMaterial, DielectricMaterial,
                              ConductorMaterial, EmissiveMaterial, PrincipledMaterial FARM_MATERIAL_TEST_KIND>;

// A material as the contract describes it; `material` has passed contract::CheckRules
// (scene/scene_rules.h), so its kind is set and its values are in range.
Material MaterialFromProto(const renderfarm::v1::Material& material);

// What a material can do (Mitsuba's BSDF flags), for the integrators and the photon tracer.
// A principled material can both be specular and reflect (see the top of the file).
struct MaterialCapabilities {
  // A delta BSDF (mirror, dielectric, conductor, smooth principled): only SampleBsdf and
  // SampleSpecular move light across it; caustic photons are aimed at it.
  bool specular = false;
  // A non-specular reflection (Lambert, glossy, principled): direct light and photon
  // estimates apply where it is hit, and the scene needs a global photon map.
  bool reflects = false;
  // Emits a positive radiance: a shape with it is an area light.
  bool emits = false;
  // The share of the non-specular reflection that is diffuse, in [0, 1] (1 for Lambert):
  // photons are stored on glossy surfaces with this probability, or with 1/2 if that is
  // more (photon_tracer.cpp's kMinPhotonKeep).
  float diffuse_fraction = 0;
};
MaterialCapabilities CapabilitiesOf(const Material& material);

// Whether light through the material goes its own way at each wavelength (a dispersive
// dielectric): a path crossing it is traced at one wavelength from there on
// (spectral/monochrome.h).
bool IsDispersive(const Material& material);

// The material at one wavelength: a dispersive dielectric with its index at lambda_nm and
// no dispersion; any other as it is.
Material AtWavelength(const Material& material, double lambda_nm);

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

// Only the specular (delta) part of the BSDF, for a camera path that goes on past a surface
// whose non-specular part is shaded on its own: what SampleBsdf draws for mirror,
// dielectric and conductor; a smooth principled material's lobe alone, weighted without
// the lobe choice; nothing for the other kinds.
std::optional<BsdfSample> SampleSpecular(const Material& material, const Vec3& n, const Vec3& wo,
                                         float u_lobe, Vec2 u, TransportMode mode);

// Both ways a smooth dielectric sends a path on, each weighted by its share: the reflection
// by Fresnel's R, the refraction by 1 - R times what SampleBsdf weighs it by (the tint, and
// 1 / eta^2 for radiance), so that the two add up to SampleBsdf's expected weight; under
// total internal reflection only the reflection, of weight 1. Nothing for every other kind
// (one specular lobe or none): such a path goes on as SampleSpecular draws it.
struct SpecularSplit {
  BsdfSample reflected;
  std::optional<BsdfSample> transmitted;
};
std::optional<SpecularSplit> SplitSpecular(const Material& material, const Vec3& n, const Vec3& wo,
                                           TransportMode mode);

// Radiance emitted from the front side (black for everything but emissive materials and
// principled ones with an emission).
Rgb Emission(const Material& material);

// Radiance emitted along w (unit, away from the surface) from a surface whose front normal
// is n: Emission on the front side, nothing behind.
Rgb Emitted(const Material& material, const Vec3& n, const Vec3& w);

// The diffuse lobe's f times pi for this pair of directions (kd for Lambert and glossy):
// what a diffuse gather ray sampled with density cos / pi is weighted by. Black for kinds
// without one.
Rgb DiffuseReflectance(const Material& material, const Vec3& n, const Vec3& wo, const Vec3& wi);

// A direction from the glossy lobe alone (glossy's Blinn-Phong lobe, a rough principled
// material's GGX lobe), weighted by that lobe's f cos / pdf, for the glossy bounce of
// final gathering; nothing for every other kind, or when the direction falls below the
// horizon.
std::optional<BsdfSample> SampleGlossyLobe(const Material& material, const Vec3& n, const Vec3& wo, Vec2 u);

// The density with which SampleGlossyLobe draws wi; 0 for kinds without a glossy lobe (a
// smooth principled material's counts as a delta), and below the horizon.
float GlossyLobePdf(const Material& material, const Vec3& n, const Vec3& wo, const Vec3& wi);

// The normal a material is shaded about at a hit whose shading normal is ns: a principled
// material's own once MaterialAt has set it (the normal map's), else ns.
Vec3 ShadingNormalOf(const Material& material, const Vec3& ns);

// Hemispherical reflectance at normal incidence, for the albedo AOV (transmittance for
// glass, emitters black).
Rgb Albedo(const Material& material);

std::string ToString(const Material& material);

}  // namespace farm
