#pragma once

// The Henyey-Greenstein phase function, with the convention of the whole worker: both
// directions point away from the scattering point. wo is where the scattered light goes
// (towards the camera), wi where it comes from (towards the light), so light travelling
// along -wi turns by the angle theta with cos theta = dot(-wi, wo):
//
//   p(cos theta) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos theta)^(3/2)),
//
// which integrates to 1 over the sphere; g > 0 scatters forwards (wi close to -wo).

#include "math/vec3.h"

namespace farm {

// p for light arriving along -wi and leaving along wo (unit vectors).
float HenyeyGreenstein(const Vec3& wo, const Vec3& wi, float g);
// p as a function of cos theta.
float HenyeyGreenstein(float cos_theta, float g);

struct PhaseSample {
  Vec3 wi;
  float pdf = 0;  // per unit solid angle; equal to the phase function (exact sampling)
};

// wi with density exactly HenyeyGreenstein(wo, wi, g), by inverting the CDF of cos theta.
PhaseSample SampleHenyeyGreenstein(const Vec3& wo, float g, Vec2 u);

}  // namespace farm
