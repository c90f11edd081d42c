#pragma once

// How much of a photon estimate's disc is surface that can hold the photons it counts.
//
// A k-nearest estimate divides the photons' power by the disc's area, pi r^2. Where the
// disc hangs over an edge (the foot of a wall, a corner, a block's rim, where a box stands
// on the floor) part of that area is no surface at all, so the estimate is low there, by up
// to a half at a wall's foot and three quarters in a corner, in a band as wide as the
// radius: light the image loses along every edge, and a bias that shrinks only as fast as
// the radius does. Dividing by the area of surface the disc covers instead removes it:
// of m photons around p, the m - 1 nearest are spread over the surfaces within the
// farthest's distance, so their power over the area of p's surface in that ball is the
// irradiance without bias wherever it is smooth.

#include <cstdint>
#include <functional>

#include "math/vec3.h"
#include "scene/scene_data.h"

namespace farm {

// Probe points a coverage takes: stratified over the disc.
inline constexpr uint32_t kDiscCoverageProbes = 16;

// The share of the disc of radius r about the surface point p, in the plane normal to n (p's
// geometric normal, on the side that is lit), that is surface facing within 60 degrees of n
// and reached from p along it, each probe point weighted by weight(u) for u = its distance
// / r (a filter kernel times pi: 1 everywhere gives the share of the area): 1 in the middle
// of a wall, about 1/2 at its foot or at a block's rim, 1/4 in a corner. A probe point
// counts when the segment to it from p, lifted off the surface by a tenth of r, is clear
// (no wall rises in between) and a ray from the lifted point straight down meets a surface
// facing like n within r (the surface goes on; a sphere's falls away less than that over
// the disc). seed scrambles the probe points, so the result depends only on the
// arguments. At least 1 / kDiscCoverageProbes (p's own surface is there); 1 when the scene
// has no surface at p (photons placed by hand, with no geometry under them).
// weight empty means 1.
float DiscCoverage(const SceneData& scene, const Vec3& p, const Vec3& n, float r, uint32_t seed,
                   const std::function<float(float u)>& weight = {});

}  // namespace farm
