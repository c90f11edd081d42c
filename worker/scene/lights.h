#pragma once

// Lights, as a closed set of value types dispatched with std::visit. Each kind samples
// light arriving at a shading point (next-event estimation, SampleLi), samples the emission
// of a photon (SampleLe) and reports its power, by which lights are picked for both.
//
//   sphere  emissive sphere; SampleLi samples the cone the sphere subtends (every sample
//           visible and front-facing), area sampling if the point is inside
//   quad    emissive quad, uniform by area
//   mesh    emissive mesh, or emissive part of an instanced mesh (its triangles placed):
//           a triangle in proportion to its area, then uniform within it
//   point   intensity I in all directions from a point: a delta light, power 4 pi I
//   sun     irradiance E along a direction from infinitely far away: a delta light. Photons
//           leave a disc perpendicular to the direction that covers the scene's bounding
//           sphere, so its power is E times the disc's area.
//
// Area lights emit constant radiance L from their front only: power = pi * area * L.
//
// Every function here dispatches with std::visit and one overload per kind, with no
// catch-all, so a new kind that one of them does not handle does not compile (the test
// ExhaustiveDispatch.* compiles lights.cpp with FARM_TEST_UNHANDLED_LIGHT, which adds a
// kind nothing handles, and requires failure).

#include <memory>
#include <optional>
#include <string>
#include <variant>

#include "math/bounds.h"
#include "math/rgb.h"
#include "math/vec3.h"
#include "sampling/distribution.h"
#include "scene/shapes.h"

namespace renderfarm::v1 {
class Light;
}

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
  // An instance's placement of the mesh (its triangles stay in object space); none for a
  // mesh already in the world.
  std::optional<Placement> placement;
  DiscreteDistribution triangles;  // by area in the world
  float area = 0;
  Rgb radiance;

  static TriangleMeshLight Make(std::shared_ptr<const TriangleMesh> mesh, const Rgb& radiance,
                                std::optional<Placement> placement = std::nullopt);
  // Triangle i's corners in the world, counter-clockwise from the front.
  void Corners(int i, Vec3& p0, Vec3& p1, Vec3& p2) const;
};

struct PointLight {
  Vec3 position;
  Rgb intensity;  // power per steradian
};

struct SunLight {
  Vec3 direction;  // unit, the way the light travels
  Rgb irradiance;  // on a surface facing the sun
  // The emission disc: perpendicular to direction, centred on the line through the scene's
  // bounding sphere's centre, outside that sphere on the sun's side.
  Vec3 disc_center;
  float disc_radius = 0;

  // Fits the disc around `scene`, a sphere around all geometry.
  static SunLight Make(const Vec3& direction, const Rgb& irradiance, const BoundingSphere& scene);
};

#ifdef FARM_TEST_UNHANDLED_LIGHT  // test hook only: see the comment at the top
struct UnhandledLight {};
#define FARM_LIGHT_TEST_KIND , UnhandledLight
#else
#define FARM_LIGHT_TEST_KIND
#endif

using Light = std::variant<SphereLight, QuadLight, TriangleMeshLight, PointLight,
                           SunLight FARM_LIGHT_TEST_KIND>;

// A light as the contract describes it; `light` has passed contract::CheckRules and the
// scene's rules (scene/scene_rules.h): its kind is set and a sun's direction is not zero.
// `scene` bounds all geometry (for the sun's disc).
Light LightFromProto(const renderfarm::v1::Light& light, const BoundingSphere& scene);

// Light arriving at a shading point from one point of a light.
struct LightSample {
  Rgb radiance;  // emitted toward the shading point; for delta lights the irradiance
                 // on a surface facing the light (I / d^2, or E)
  Vec3 wi;       // unit direction from the shading point to p
  Vec3 p, n;     // the point on the light and its front normal (zero for delta lights)
  float distance = 0;
  float pdf = 0;  // per unit solid angle at the shading point, > 0; 1 for delta lights
  bool delta = false;  // point and sun: a single direction, no density
};

// A sample of the light's emission toward `ref`, or nothing if the sample carries no light
// (the back of the light faces ref, or the density is degenerate).
std::optional<LightSample> SampleLi(const Light& light, const Vec3& ref, Vec2 u);

// A photon leaving a light: origin, direction and the power it carries, Le cos / (pdf of
// origin * pdf of direction), before dividing by the probability of picking the light and
// the number of photons.
struct LightEmission {
  Vec3 p;
  Vec3 n;  // front normal at p, to offset the ray; zero for point lights and the sun
  Vec3 w;  // unit
  Rgb power;
};

// Origins uniform by area (point lights: the point; sun: uniform on the disc), directions
// cosine-weighted about the front normal (point lights: uniform on the sphere; sun: its
// direction), so every photon of a light carries its full power. Nothing if degenerate.
std::optional<LightEmission> SampleLe(const Light& light, Vec2 u_origin, Vec2 u_direction);

// A point on a light's surface (or the point light's position) with its density by area,
// for emission aimed elsewhere (caustic photons). Not for the sun.
struct LightOrigin {
  Vec3 p;
  Vec3 n;            // front normal; zero for point lights
  float pdf_area = 1;  // 1 for point lights (a delta)
  Rgb emission;      // radiance of area lights (front side only), intensity of point lights
  bool is_point = false;
};
std::optional<LightOrigin> SampleLightOrigin(const Light& light, Vec2 u);

// Total emitted power (radiant flux), per channel.
Rgb Power(const Light& light);

// Point and sun: light from a single point or direction, without a density.
bool IsDeltaLight(const Light& light);

std::string ToString(const Light& light);

}  // namespace farm
