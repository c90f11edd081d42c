#pragma once

// What a built Scene holds, shared read-only by all render threads: film and sampling
// settings with defaults applied, camera, materials, shapes (geometry ID = index), lights,
// and the Embree BVH, plus the ray queries the integrators use.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "math/bounds.h"
#include "math/ray.h"
#include "math/vec3.h"
#include "sampling/distribution.h"
#include "scene/accelerator.h"
#include "scene/antialiasing_settings.h"
#include "scene/camera.h"
#include "scene/indirect_settings.h"
#include "scene/lights.h"
#include "scene/materials.h"
#include "scene/photon_settings.h"
#include "scene/shapes.h"
#include "texture/texture_system.h"

namespace farm {

struct ShapeRecord {
  std::string label;  // "shapes[3]", or "shapes[3] (\"floor\")" when named: for messages
  ShapeGeometry geometry;
  int material = 0;  // index into SceneData::materials
  int light = -1;    // index into SceneData::lights if the shape emits
};

// A ray's closest hit, refined: p lies on the surface (projected back onto it, which is
// what makes small ray offsets safe) and n is the unit geometric normal of the front side.
// For shading: texture coordinates (glTF's, v growing downwards; has_uv false without
// them), the unit shading normal ns (n until meshes carry normals), dp/du and dp/dv, and
// the index of the hit's material (the shape's).
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
  IndirectSettings indirect;  // also holds sampling.light_samples

  Camera camera;
  std::vector<Material> materials;
  std::vector<MaterialCapabilities> capabilities;  // of each material, by index
  std::vector<std::string> material_names;
  // What principled materials' TextureIndex values index, and the system that reads them
  // (null when no material has a texture).
  std::vector<SceneTexture> textures;
  const TextureSystem* texture_system = nullptr;
  std::vector<ShapeRecord> shapes;
  std::vector<Light> lights;  // emissive shapes first, then Scene.lights in order
  DiscreteDistribution light_power;  // picks a light in proportion to its power

  Bounds3 bounds;  // of all geometry
  // Spheres around the specular shapes (mirror, glass, metal): caustic photons are aimed
  // at them. Empty: the scene needs no caustic map.
  std::vector<BoundingSphere> specular_targets;
  PhotonSettings photons;

  // Absolute floor of ray offsets (see math/ray.h), proportional to the scene's extent.
  float ray_epsilon = 0;
  Accelerator accelerator;

  std::optional<SurfaceHit> Intersect(const Ray& ray) const;

  // Whether nothing blocks the segment between two surface points, each with its
  // geometric normal; the ends are offset off their surfaces toward each other.
  bool Visible(const Vec3& p0, const Vec3& n0, const Vec3& p1, const Vec3& n1) const;
  // Whether the front sides of two nearby surface points see each other: each end moves
  // off its own surface along its normal (n0, n1 point to the sides that matter), never
  // through it, which the choice by direction in Visible can do for close points on a
  // curved wall whose normals are quantised.
  bool FrontsSeeEachOther(const Vec3& p0, const Vec3& n0, const Vec3& p1, const Vec3& n1) const;
  // Whether nothing lies on the segment between two ray origins already off their surfaces.
  bool SegmentClear(const Vec3& o0, const Vec3& o1) const;

  // The material of a hit as the scene declares it (MaterialAt, surface_shading.h, applies
  // its textures at the hit).
  const Material& material_of(const SurfaceHit& hit) const { return materials[hit.material]; }
  const MaterialCapabilities& capabilities_of(const SurfaceHit& hit) const { return capabilities[hit.material]; }

  std::string ToString() const;
};

}  // namespace farm
