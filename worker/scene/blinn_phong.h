#pragma once

// The glossy lobe of the Blinn-Phong material, in a local frame whose z is the normal on
// the side of wo (wo.z > 0).
//
// Directions are sampled through the half vector h, distributed as
// D(h) = (e + 1) / (2 pi) cos^e(theta_h) (a density over h that integrates to 1), so that
// the density of wi = reflect(wo, h) is D(h) / (4 wo.h). The lobe's value is that density
// divided by max(cos theta_o, cos theta_i) (the denominator of Ashikhmin and Shirley):
//
//   f_glossy(wo, wi) = D(h) / (4 (wo.h) max(wo.z, wi.z))
//
// It is symmetric in wo and wi (reciprocal), and its albedo, the integral of f cos theta_i,
// is at most the integral of the sampling density, <= 1: the lobe is energy-normalised for
// every exponent and angle, where the classic (e + 8) / (8 pi) factor is only an
// approximation. A sampled direction carries the weight f cos / pdf = wi.z / max(wo.z, wi.z)
// <= 1, so photons never gain power at a glossy bounce.

#include <optional>

#include "math/vec3.h"

namespace farm {

// Density over solid angle of SampleBlinnPhong's directions; 0 below the horizon.
float BlinnPhongPdf(const Vec3& wo, const Vec3& wi, float exponent);

// f_glossy above (without the specular colour).
float BlinnPhongValue(const Vec3& wo, const Vec3& wi, float exponent);

// A direction about the mirror direction of wo, or nothing if it falls below the horizon
// (the lobe's share of light that a real surface would shadow; the path ends there).
std::optional<Vec3> SampleBlinnPhong(const Vec3& wo, Vec2 u, float exponent);

}  // namespace farm
