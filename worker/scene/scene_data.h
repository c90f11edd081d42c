#pragma once

// What a built Scene holds, shared read-only by all render threads: film and sampling
// settings with defaults applied, camera, materials, shapes (geometry ID = index), the
// meshes instances place, lights, and the Embree BVH, plus the ray queries the
// integrators use.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "math/bounds.h"
#include "math/ray.h"
#include "math/vec3.h"
#include "media/medium.h"
#include "sampling/distribution.h"
#include "sampling/target_spheres.h"
#include "scene/accelerator.h"
#include "scene/antialiasing_settings.h"
#include "scene/camera.h"
#include "scene/cutout.h"
#include "scene/environment.h"
#include "scene/indirect_settings.h"
#include "scene/lights.h"
#include "scene/materials.h"
#include "scene/photon_settings.h"
#include "scene/pixel_filter.h"
#include "scene/shapes.h"
#include "texture/texture_system.h"

namespace farm {

struct ShapeRecord {
  std::string label;  // "shapes[3]", or "shapes[3] (\"floor\")" when named: for messages
  ShapeGeometry geometry;
  int material = 0;  // index into SceneData::materials; an instance's parts name their own
  // Shape.interior_medium: entered by crossing the surface from its front to its back.
  std::optional<Medium> interior_medium;
};

// A ray's closest hit, refined: p lies on the surface (projected back onto it, which is
// what makes small ray offsets safe) and n is the unit geometric normal of the front side,
// for ray offsets and for which side of the surface a direction is on. The rest is for
// shading (surface_geometry.h says how each kind of shape fills it in):
//
//   uv, has_uv  texture coordinates, v growing downwards in the image (glTF's): a mesh's
//               own, interpolated (has_uv false and uv 0 without them); a quad's position
//               along edge_u and edge_v; a sphere's longitude and latitude as an
//               equirectangular map's (u = 0.5 looking along -z, growing towards +x; v = 0
//               at +y)
//   ns          the unit shading normal: a mesh's normals interpolated (placed by the
//               inverse transpose), flipped onto n's side; n where there are none
//   dpdu, dpdv  dp/du and dp/dv, the surface's derivatives by the texture coordinates;
//               with tangents in the mesh, dpdu takes the tangent's direction (made
//               perpendicular to ns) and dpdv that of -bitangent (the bitangent w *
//               cross(ns, tangent) points up the image, towards decreasing v), each keeping
//               the length the texture coordinates give (1 without them); without texture
//               coordinates or tangents, an orthonormal frame about ns
//   material    index into SceneData::materials: the shape's, or the instanced part's
//   part        the part of an instanced mesh that was hit (0 for other shapes)
struct SurfaceHit {
  Vec3 p;
  Vec3 n;
  float t = 0;
  int shape = 0;
  uint32_t primitive = 0;
  Vec2 uv;
  bool has_uv = false;
  Vec3 ns;
  Vec3 dpdu, dpdv;
  int material = 0;
  uint32_t part = 0;
};

// A texture as materials read it: prepared by the worker's texture system, with its wrap.
struct SceneTexture {
  PreparedTexture prepared;
  TextureWrap wrap = TextureWrap::kRepeat;
};

std::string ToString(const SurfaceHit& hit);

struct SceneData {
  int width = 0;
  int height = 0;
  int tile_size = 0;
  // Ordinary pixels; edge pixels get AntialiasingSettings::edge_samples.
  uint32_t samples_per_pixel = 0;
  uint64_t seed = 0;
  AntialiasingSettings antialiasing;
  PixelFilter filter;  // film.filter
  IndirectSettings indirect;  // also holds sampling.light_samples
  // Sampling.specular: SPLIT (glass followed both ways at a camera path's first bounces)
  // rather than CHOOSE.
  bool split_specular = true;
  // Sampling.spectral ALWAYS: every camera path and photon traced at eight wavelengths from
  // its start (spectral_light.h), rather than in RGB until a dispersive surface.
  bool spectral_always = false;

  Camera camera;
  std::vector<Material> materials;
  std::vector<MaterialCapabilities> capabilities;  // of each material, by index
  std::vector<std::string> material_names;
  // Cut-out tests by material index; an empty one (the default) cuts nothing and costs
  // nothing (the accelerator filters only the geometry of materials that have one).
  std::vector<CutoutTest> cutouts;
  // What principled materials' TextureIndex values index, and the system that reads them
  // (null when no material has a texture).
  std::vector<SceneTexture> textures;
  const TextureSystem* texture_system = nullptr;
  std::vector<ShapeRecord> shapes;
  // Scene.meshes, in order, each built once and placed by the instances among shapes.
  std::vector<std::shared_ptr<const SceneMesh>> meshes;
  // Emissive shapes and emissive parts of instances first (in shape, then part order),
  // then Scene.lights in order, then the environment if it is not black.
  std::vector<Light> lights;
  DiscreteDistribution light_power;  // picks a light in proportion to its power
  // What rays that leave the scene see; null: black.
  std::shared_ptr<const Environment> environment;
  // Whether camera rays that leave the scene see it (else black, with alpha 0).
  bool environment_visible = false;
  int environment_light = -1;  // its index in lights, -1 if it is not a light

  Bounds3 bounds;  // of all geometry
  // Scene.medium, filling medium_ball (where light from infinitely far away enters: the
  // distant lights' disc's sphere) outside the shapes' interior media; none: vacuum.
  std::optional<Medium> medium;
  BoundingSphere medium_ball;
  // Whether the scene or any shape holds a medium: photon paths draw their media's random
  // numbers only then, so a scene without media traces what it traced before they existed.
  bool has_media = false;
  // Spheres around the specular shapes (mirror, glass, metal): caustic photons are aimed
  // at them. Empty: the scene needs no caustic map. The surface each bounds, by index: a
  // shape, and for an instance the part (a caustic path counts only for the target whose
  // surface it hits first: photon_emission.h).
  TargetSpheres specular_targets;
  struct TargetSurface {
    int shape = 0;
    uint32_t part = 0;
    bool operator==(const TargetSurface&) const = default;
  };
  std::vector<TargetSurface> specular_target_surfaces;
  // The surface each area light is, by its index in lights (the first ones): a shape, and
  // for an instance the part. In (shape, part) order.
  std::vector<TargetSurface> area_light_surfaces;
  // By light: the targets by the solid angle each subtends from one point of the light
  // (TargetSpheres::TableFrom), so that a caustic photon's pick is one table read; empty for
  // a sun or the environment and once the tables would hold more than
  // kMaxCausticAimEntries entries in all (those lights pick down the tree instead).
  std::vector<AliasTable> caustic_aim;
  static constexpr std::size_t kMaxCausticAimEntries = std::size_t{1} << 20;
  PhotonSettings photons;

  // Absolute floor of ray offsets (see math/ray.h), proportional to the scene's extent.
  float ray_epsilon = 0;
  Accelerator accelerator;

  std::optional<SurfaceHit> Intersect(const Ray& ray) const;
  // The first hit along ray as Intersect finds it, with only its distance and geometric
  // normal (the same t and n): for probes that ask which way a surface faces
  // (disc_coverage.h), without the shading normal, texture coordinates and derivatives.
  struct FacingHit {
    float t = 0;
    Vec3 n;
  };
  std::optional<FacingHit> IntersectFacing(const Ray& ray) const;
  // A hit Embree reported, refined; `point` is where it lies in the world (spheres and
  // quads take it; triangles project it onto their plane).
  SurfaceHit Refine(const RawHit& raw, const Vec3& point) const;
  // What the cut-out test reads of a candidate hit (cutout.h): its material and texture
  // coordinates, for a triangle without the rest of Refine's work.
  CutoutHit CutoutHitOf(const RawHit& raw, const Vec3& point) const;

  // Whether nothing blocks the segment between two surface points, each with its
  // geometric normal; the ends are offset off their surfaces toward each other.
  bool Visible(const Vec3& p0, const Vec3& n0, const Vec3& p1, const Vec3& n1) const;
  // Whether the front sides of two nearby surface points see each other: each end moves
  // off its own surface along its normal (n0, n1 point to the sides that matter), never
  // through it, which the choice by direction in Visible can do for close points on a
  // curved wall whose normals are quantised; and by as much as a convex surface turning
  // from n0 to n1 can bow out above the two (nothing for coplanar points), so that two
  // points of one ball see each other while a wall between two points of a floor blocks.
  bool FrontsSeeEachOther(const Vec3& p0, const Vec3& n0, const Vec3& p1, const Vec3& n1) const;
  // Whether nothing lies on the segment between two ray origins already off their surfaces.
  bool SegmentClear(const Vec3& o0, const Vec3& o1) const;
  // The index in lights of the area light a hit lies on, -1 if it lies on none: how a ray
  // that meets an emitter finds the light that light sampling would have drawn it from.
  int AreaLightOf(const SurfaceHit& hit) const;

  // The material of a hit as the scene declares it (MaterialAt, surface_shading.h, applies
  // its textures at the hit).
  const Material& material_of(const SurfaceHit& hit) const { return materials[hit.material]; }
  const MaterialCapabilities& capabilities_of(const SurfaceHit& hit) const { return capabilities[hit.material]; }

  // The memory the geometry takes: the meshes' arrays (each shared one once) and what
  // Embree holds (buffers and BVHs).
  std::size_t GeometryBytes() const;

  std::string ToString() const;
};

}  // namespace farm
