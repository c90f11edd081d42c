#pragma once

// The GGX (Trowbridge-Reitz) microfacet distribution of the principled material, in a local
// frame whose z is the (shading) normal, with Smith's height-correlated masking-shadowing
// and sampling by visible normals (Heitz, "Sampling the GGX Distribution of Visible
// Normals", JCGT 2018). alpha is the distribution's width (the principled material's
// roughness squared), at least kMinGgxAlpha.
//
//   D(h)        = alpha^2 / (pi ((alpha^2 - 1) cos^2 theta_h + 1)^2)   (normals' density,
//                 projected: the integral of D(h) cos theta_h over the hemisphere is 1)
//   Lambda(w)   = (sqrt(1 + alpha^2 tan^2 theta_w) - 1) / 2
//   G1(w)       = 1 / (1 + Lambda(w))                      masking of one direction
//   G2(wo, wi)  = 1 / (1 + Lambda(wo) + Lambda(wi))        height-correlated, both
//
// Visible normals seen from wo have the density D_wo(h) = G1(wo) max(0, wo.h) D(h) / wo.z;
// reflecting wo about such an h gives wi with the density
//
//   pdf(wi) = D_wo(h) / (4 wo.h) = G1(wo) D(h) / (4 wo.z),   h = normalize(wo + wi)
//
// over the whole sphere: a sampled wi can fall below the horizon (the share of light that
// the microsurface would reflect again, which a single-scattering model loses), so pdf
// integrates to 1 over the sphere, and to less over the upper hemisphere
// (ggx_test.cpp checks both numerically).

#include "math/vec3.h"

namespace farm {

// Narrower lobes are clamped to this: D's peak, 1 / (pi alpha^2), stays far inside float
// range and a sampled lobe of roughness 0 is a mirror to within 1e-4 radians.
inline constexpr float kMinGgxAlpha = 1e-4f;

float GgxD(const Vec3& h, float alpha);
// Infinite (so G1 and G2 are 0) for a direction at or below the horizon.
float GgxLambda(const Vec3& w, float alpha);
float GgxG1(const Vec3& w, float alpha);
float GgxG2(const Vec3& wo, const Vec3& wi, float alpha);

// A microfacet normal visible from wo (wo.z > 0), distributed as D_wo, from u in [0,1)^2.
Vec3 SampleGgxVisibleNormal(const Vec3& wo, float alpha, Vec2 u);

// pdf(wi) above: the density of reflect(wo, h) for h drawn by SampleGgxVisibleNormal;
// 0 when wo is below the horizon or wi is not a reflection of wo about an upper normal.
float GgxReflectionPdf(const Vec3& wo, const Vec3& wi, float alpha);

}  // namespace farm
