#pragma once

// The BRDF of glTF 2.0's metallic-roughness material (the specification's appendix B), in a
// local frame whose z is the shading normal on the side of wo (wo.z > 0):
//
//   F(c)      = c + (1 - c) (1 - |wo.h|)^5                   Schlick, h = normalize(wo + wi)
//   specular  = D(h) G2(wo, wi) / (4 wo.z wi.z)              GGX, ggx.h; alpha = roughness^2
//   f         = (1 - metallic) (1 - F(0.04)) base / pi       the diffuse base
//             + F(mix(0.04, base, metallic)) specular        the dielectric and metal lobes
//
// which is the appendix's mix(dielectric_brdf, metal_brdf, metallic) written out: the two
// Fresnel-weighted specular lobes add to one with F0 = mix(0.04, base, metallic). f is
// reciprocal (|wo.h| = |wi.h|). It is single-scattering: light the microsurface reflects
// more than once is lost, so a white metal reflects less than all the light, the more the
// rougher (principled_test.cpp's kSingleScatteringLoss: from 0.6% at roughness 0.25 to 69%
// at roughness 1, head on). And it is glTF's, not energy conserving: the diffuse base is
// weighted by 1 - F(wo.h) rather than by what the lobe leaves, so a white dielectric
// reflects up to 17% more than it receives at grazing angles (kMaxDielectricGain).
//
// Sampling picks the specular lobe with the probability SpecularLobeProbability (its
// Fresnel weight at wo against the diffuse base's, by luminance), draws a visible normal
// for it and the cosine hemisphere for the base; the density is the mixture of the two.
//
// Below SceneLimits.principled_specular_roughness (`specular` set) the specular lobe counts
// as a delta function, as a mirror does: it is left out of Value and Pdf (light samples and
// photon estimates never see it) and only SampleSpecular draws it.

#include <optional>

#include "math/rgb.h"
#include "math/vec3.h"

namespace farm {

struct PrincipledLobes {
  Rgb base_color{1};
  float metallic = 0;
  float alpha = 0;        // GGX width: roughness^2, at least kMinGgxAlpha
  bool specular = false;  // the specular lobe counts as a delta function
};

// f(wo, wi) above without the specular lobe when it counts as a delta; 0 below either
// horizon.
Rgb PrincipledValue(const PrincipledLobes& m, const Vec3& wo, const Vec3& wi);

// The density with which PrincipledSample draws wi (its non-delta part when `specular`).
float PrincipledPdf(const PrincipledLobes& m, const Vec3& wo, const Vec3& wi);

// The probability of drawing the specular lobe at wo, in [0, 1].
float SpecularLobeProbability(const PrincipledLobes& m, const Vec3& wo);

struct PrincipledSample {
  Vec3 wi;
  Rgb weight;             // f cos / pdf
  float pdf = 0;          // 0 for a delta sample
  bool specular = false;  // drawn from the specular lobe when it counts as a delta
};

// A direction from the whole BRDF: u_lobe picks the lobe, u the direction. Nothing when
// the sampled direction falls below the horizon (the single-scattering loss).
std::optional<PrincipledSample> SamplePrincipled(const PrincipledLobes& m, const Vec3& wo, float u_lobe, Vec2 u);

// A direction from the specular lobe alone, weighted by its f cos / pdf (no lobe choice):
// for the camera path that continues through a smooth principled surface whose diffuse
// base is shaded on its own.
std::optional<PrincipledSample> SamplePrincipledSpecular(const PrincipledLobes& m, const Vec3& wo, Vec2 u);

// The diffuse base's reflectance for this pair of directions: its f times pi, what a
// cosine-distributed gather ray is weighted by.
Rgb PrincipledDiffuseWeight(const PrincipledLobes& m, const Vec3& wo, const Vec3& wi);

// Hemispherical reflectance at normal incidence, approximated by the Fresnel weights at
// normal incidence: (1 - metallic) 0.96 base + F0. At most 1 per channel.
Rgb PrincipledAlbedo(const PrincipledLobes& m);

}  // namespace farm
