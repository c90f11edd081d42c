#pragma once

// Warps from uniform samples u in [0,1)^2 onto the domains the renderer samples, each with
// its density. Conventions: local directions have z up; densities over directions are per
// unit solid angle, densities over surfaces per unit area.

#include <string>

#include "math/vec3.h"

namespace farm {

// Barycentrics (b0, b1, b2) uniform over a triangle by area. Heitz's low-distortion map
// ("A Low-Distortion Map Between Triangle and Square", 2019): continuous and keeps
// stratification better than the classic sqrt warp. Density 1/area.
Vec3 SampleUniformTriangle(Vec2 u);

// Point of a parallelogram with corner `origin` and edges eu, ev; density 1/|eu x ev|.
inline Vec3 SampleParallelogram(const Vec3& origin, const Vec3& eu, const Vec3& ev, Vec2 u) {
  return origin + eu * u.x + ev * u.y;
}

Vec3 SampleUniformSphere(Vec2 u);
float UniformSpherePdf();

// Directions within angle theta_max of +z, uniform in solid angle.
Vec3 SampleUniformCone(Vec2 u, float cos_theta_max);
float UniformConePdf(float cos_theta_max);

// Shirley-Chiu concentric map of the square onto the unit disk (area preserving, low
// distortion), and Malley's cosine-weighted hemisphere over it. Photon emission and
// gathering will use these.
Vec2 SampleUniformDiskConcentric(Vec2 u);
Vec3 SampleCosineHemisphere(Vec2 u);
float CosineHemispherePdf(float cos_theta);

// A point of a sphere seen from `ref`, for direct lighting by a sphere light.
struct SphereSample {
  Vec3 p;            // on the sphere
  Vec3 n;            // outward unit normal at p
  float pdf = 0;     // per unit solid angle as seen from ref
  bool in_cone = false;  // whether the cone (true) or the area fallback (false) was used
};

// Samples the cone of directions the sphere subtends from ref, uniformly in solid angle,
// and returns the nearest point of the sphere along the chosen direction (pbrt-v4's method,
// with a small-angle form that avoids 1 - cos(theta_max) cancelling for distant spheres).
// Every point returned is visible from ref and faces it. If ref is inside the sphere, the
// sphere is sampled uniformly by area instead and the density converted to solid angle
// (it is 0 where the conversion is degenerate, which the caller must skip).
SphereSample SampleSphereFromPoint(const Vec3& center, float radius, const Vec3& ref, Vec2 u);

// Density that SampleSphereFromPoint gives the direction w (unit) from ref: the uniform cone
// density if w lies in the subtended cone and ref outside the sphere, else 0 (for ref
// inside, the area density converted to solid angle along w).
float SphereFromPointPdf(const Vec3& center, float radius, const Vec3& ref, const Vec3& w);

}  // namespace farm
