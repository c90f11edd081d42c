#pragma once

// Fresnel reflectance of smooth interfaces, exact for unpolarised light (the average of the
// s- and p-polarised reflectances), and the reflection and refraction directions that go
// with them. Directions point away from the surface; normals are unit length.

#include <optional>

#include "math/vec3.h"

namespace farm {

// Reflectance of a dielectric interface for light arriving at angle acos(cos_i) to the
// normal on the side it comes from; eta = n_transmitted / n_incident. A negative cos_i
// means the light arrives from the other side: eta is inverted and cos_i negated. Returns
// 1 past the critical angle (total internal reflection). Transmittance is 1 - R.
float FresnelDielectric(float cos_i, float eta);

// Reflectance of a conductor with complex index eta + i k relative to the outside, for
// cos_i in [0, 1]. With k = 0 it equals FresnelDielectric.
float FresnelConductor(float cos_i, float eta, float k);

// w mirrored about n: the specular reflection of w (both pointing away from the surface).
inline Vec3 Reflect(const Vec3& w, const Vec3& n) { return n * (2 * Dot(w, n)) - w; }

// The direction of the ray transmitted from w's side of the surface through to the other,
// for n on w's side (Dot(w, n) > 0) and eta = n_other / n_w's side; nothing on total
// internal reflection.
std::optional<Vec3> Refract(const Vec3& w, const Vec3& n, float eta);

}  // namespace farm
