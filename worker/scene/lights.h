#pragma once

// Area lights: the emissive shapes of the scene, as a closed set of value types dispatched
// with std::visit. Each kind samples a point of its surface as seen from a shading point
// (next-event estimation) and reports its power (to be picked in proportion to it, and,
// later, to share out photons).
//
//   sphere  samples the cone of directions the sphere subtends (every sample visible and
//           front-facing); area sampling if the shading point is inside
//   quad    uniform by area
//   mesh    a triangle in proportion to its area, then uniform within it
//
// Emission is one-sided (front only), with constant radiance L, so power = pi * area * L.

#include <memory>
#include <optional>
#include <string>
#include <variant>

#include "math/rgb.h"
#include "math/vec3.h"
#include "sampling/distribution.h"
#include "scene/shapes.h"

namespace farm {

struct SphereLight {
  SphereShape sphere;
  Rgb radiance;
};

struct QuadLight {
  QuadShape quad;
  Rgb radiance;
};

struct TriangleMeshLight {
  std::shared_ptr<const TriangleMesh> mesh;
  DiscreteDistribution triangles;  // by area
  float area = 0;
  Rgb radiance;

  static TriangleMeshLight Make(std::shared_ptr<const TriangleMesh> mesh, const Rgb& radiance);
};

using Light = std::variant<SphereLight, QuadLight, TriangleMeshLight>;

// A point of a light chosen for a shading point.
struct LightSample {
  Rgb radiance;  // emitted toward the shading point
  Vec3 wi;       // unit direction from the shading point to p
  Vec3 p, n;     // the point on the light and its front normal
  float distance = 0;
  float pdf = 0;  // per unit solid angle at the shading point, > 0
};

// A sample of the light's emission toward `ref`, or nothing if the sample carries no light
// (the back of the light faces ref, or the density is degenerate).
std::optional<LightSample> SampleLi(const Light& light, const Vec3& ref, Vec2 u);

// Total emitted power (radiant flux), per channel.
Rgb Power(const Light& light);

std::string ToString(const Light& light);

}  // namespace farm
