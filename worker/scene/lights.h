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
//   spot    a point light whose intensity I falls off between an inner and an outer cone
//           as glTF's KHR_lights_punctual says: I * s^2, s = clamp((cos - cos_outer) /
//           (cos_inner - cos_outer), 0, 1) (a hard edge when the cones are equal); a delta
//           light, power 2 pi I ((1 - cos_inner) + (cos_inner - cos_outer) / 3). Photons
//           leave with directions sampled exactly by that falloff, each carrying the power.
//   sun     irradiance E on a surface facing it, from infinitely far away. With an angular
//           diameter 2 alpha > 0, a disc of constant radiance E / (pi sin^2 alpha) (so a
//           facing surface still receives E), sampled uniformly over its cone: soft
//           shadows. At 0 a delta light (hard shadows).
//   environment  the radiance of everything infinitely far away (scene/environment.h),
//           importance-sampled over directions.
//
// Light from infinitely far away (sun, environment) enters the scene through a disc: for
// a direction of travel w, the disc perpendicular to w that covers the scene's bounding
// sphere, outside it on the side the light comes from (DistantDisc). A photon picks w by
// the light's density over directions and a point uniformly on that disc, so its power is
// L(w) / pdf(w) times the disc's area (E times the area for a delta sun), and the light's
// power is the disc's area times the integral of its radiance over directions.
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
#include "scene/environment.h"
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

// The smooth falloff of a spot light about its axis (KHR_lights_punctual).
struct SpotCone {
  Vec3 axis;  // unit, where the light shines
  float cos_inner = 1, cos_outer = 0;

  // The intensity's factor along w (unit, away from the light), in [0, 1].
  float Falloff(const Vec3& w) const;
  // The integral of Falloff over all directions.
  float SolidAngle() const;
  // A direction sampled in proportion to Falloff: every sample carries the same weight,
  // SolidAngle().
  Vec3 Sample(Vec2 u) const;
};

struct SpotLight {
  Vec3 position;
  Rgb intensity;  // on the axis, power per steradian
  SpotCone cone;
};

// Where light from infinitely far away enters the scene (see the top of the file).
struct DistantDisc {
  Vec3 center;  // of the scene's bounding sphere
  float radius = 0;  // the sphere's, with a margin against rounding

  static DistantDisc Around(const BoundingSphere& scene);
  // The disc's centre for light travelling along w.
  Vec3 CenterFor(const Vec3& w) const { return center - w * (radius * 1.05f); }
  float Area() const;
  // A distance that takes a shadow ray from any point of the scene out of the sphere.
  float Beyond() const { return 2.5f * radius; }
};

struct SunLight {
  Vec3 direction;  // unit, the way the light travels (the disc's axis)
  Rgb irradiance;  // on a surface facing the sun
  // 1 - cos of the disc's angular radius (computed in double: it is tiny); 0 for a delta
  // light.
  float one_minus_cos = 0;
  Rgb radiance;  // of the disc; unused by a delta light
  DistantDisc disc;

  static SunLight Make(const Vec3& direction, const Rgb& irradiance, double angular_diameter_degrees,
                       const BoundingSphere& scene);
};

struct EnvironmentLight {
  std::shared_ptr<const Environment> environment;
  DistantDisc disc;
};

#ifdef FARM_TEST_UNHANDLED_LIGHT  // test hook only: see the comment at the top
struct UnhandledLight {};
#define FARM_LIGHT_TEST_KIND , UnhandledLight
#else
#define FARM_LIGHT_TEST_KIND
#endif

using Light = std::variant<SphereLight, QuadLight, TriangleMeshLight, PointLight, SpotLight, SunLight,
                           EnvironmentLight FARM_LIGHT_TEST_KIND>;

// A light as the contract describes it; `light` has passed contract::CheckRules and the
// scene's rules (scene/scene_rules.h): its kind is set and a sun's or spot's direction is
// not zero. `scene` bounds all geometry (for the sun's disc).
Light LightFromProto(const renderfarm::v1::Light& light, const BoundingSphere& scene);

// Light arriving at a shading point from one point of a light.
struct LightSample {
  Rgb radiance;  // emitted toward the shading point; for delta lights the irradiance
                 // on a surface facing the light (I / d^2 times a spot's falloff, or E)
  Vec3 wi;       // unit direction from the shading point to p
  Vec3 p, n;     // the point on the light and its front normal (zero for delta lights)
  float distance = 0;
  float pdf = 0;  // per unit solid angle at the shading point, > 0; 1 for delta lights
  bool delta = false;  // point, spot and a sun without a disc: one direction, no density
};

// A sample of the light's emission toward `ref`, or nothing if the sample carries no light
// (the back of the light faces ref, or the density is degenerate).
std::optional<LightSample> SampleLi(const Light& light, const Vec3& ref, Vec2 u);

// What SampleLi gives for the direction wi (unit) from ref, found some other way (a ray
// traced from ref along wi meets the light at p, where its front normal is n; p and n are
// not read for distant lights): the radiance and SampleLi's density of wi, for multiple
// importance sampling against that other way. Nothing where SampleLi never draws wi: a
// delta light, the back of an area light, outside the sun's disc.
std::optional<LightSample> LightSampleAlong(const Light& light, const Vec3& ref, const Vec3& wi, const Vec3& p,
                                            const Vec3& n);

// A photon leaving a light: origin, direction and the power it carries, Le cos / (pdf of
// origin * pdf of direction), before dividing by the probability of picking the light and
// the number of photons.
struct LightEmission {
  Vec3 p;
  Vec3 n;  // front normal at p, to offset the ray; zero for point, spot and distant lights
  Vec3 w;  // unit
  Rgb power;
};

// Origins uniform by area (point and spot lights: the point; sun and environment: uniform
// on the disc for the sampled direction), directions cosine-weighted about the front normal
// (point lights: uniform on the sphere; spots: by their falloff; sun: uniform in its cone;
// environment: by its density), so every photon of a light but the environment carries
// its full power. Nothing if degenerate.
std::optional<LightEmission> SampleLe(const Light& light, Vec2 u_origin, Vec2 u_direction);

// A point on a light's surface (or the point or spot light's position) with its density
// by area, for emission aimed elsewhere (caustic photons). Not for distant lights.
struct LightOrigin {
  Vec3 p;
  Vec3 n;            // front normal; zero for point and spot lights
  float pdf_area = 1;  // 1 for point and spot lights (a delta)
  Rgb emission;      // radiance of area lights (front side only), intensity of point lights
  bool is_point = false;
  std::optional<SpotCone> cone;  // a spot's: emission along w is scaled by its falloff
};

// Light from infinitely far away: a direction of travel and the radiance arriving along it
// over the direction's density (the irradiance E for a delta sun), which times the area of
// the disc it crosses is a photon's power.
struct DistantDirection {
  Vec3 w;
  Rgb weight;
};
std::optional<DistantDirection> SampleDistantDirection(const SunLight& sun, Vec2 u);
std::optional<DistantDirection> SampleDistantDirection(const EnvironmentLight& environment, Vec2 u);
std::optional<LightOrigin> SampleLightOrigin(const Light& light, Vec2 u);

// Total emitted power (radiant flux), per channel.
Rgb Power(const Light& light);

// Point, spot and a sun without a disc: light from a single point or direction, without a
// density.
bool IsDeltaLight(const Light& light);

std::string ToString(const DistantDisc& disc);
std::string ToString(const Light& light);

}  // namespace farm
