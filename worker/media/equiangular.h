#pragma once

// Equiangular sampling (Kulla and Fajardo, "Importance Sampling Techniques for Path
// Tracing in Participating Media", 2012): for light from a point p scattered towards a
// ray o + t w, the 1 / distance^2 falloff dominates the integrand near the point of the
// ray closest to p; sampling t with density proportional to 1 / (h^2 + (t - delta)^2)
// (h the distance from p to the ray's line, delta where the closest point lies along it)
// cancels it, which is uniform in the angle the ray's points subtend at p.

#include <optional>

#include "math/vec3.h"
#include "media/homogeneous_medium.h"

namespace farm {

// t in [t_min, t_max] (t_max may be infinite) along origin + t direction (unit) for a
// light at p, with its density; nothing if the segment is empty or passes through p.
// When p lies on the ray's line (h vanishes against the distances involved) the density
// is the limit, proportional to 1 / (t - delta)^2.
std::optional<DistanceSample> SampleEquiangular(const Vec3& origin, const Vec3& direction, float t_min, float t_max,
                                                const Vec3& p, float u);

// The density SampleEquiangular gives t (0 off the segment, or where it returns nothing):
// what multiple importance sampling weighs a distance drawn some other way against.
float EquiangularPdf(const Vec3& origin, const Vec3& direction, float t_min, float t_max, const Vec3& p, float t);

}  // namespace farm
