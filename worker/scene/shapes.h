#pragma once

// The geometry kinds of a scene, as the renderer keeps them next to Embree's copy: enough
// to recover a precise hit point, the geometric normal and the shading attributes of a
// hit, to sample points by area for lights, and to emit photons. Each kind's front side is
// the side its geometric normal points to: outside for spheres, cross(edge_u, edge_v) for
// quads, counter-clockwise for triangles. An instance places a mesh of Scene.meshes, whose
// parts are stored (and built into Embree geometry) once however often they are placed.

#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "math/bounds.h"
#include "math/transform.h"
#include "math/vec3.h"

namespace farm {

// A point on a surface with its front-facing unit normal.
struct SurfacePoint {
  Vec3 p;
  Vec3 n;
};

struct SphereShape {
  Vec3 center;
  float radius = 0;

  float Area() const;
  std::string ToString() const;
};

struct QuadShape {
  Vec3 origin, edge_u, edge_v;
  Vec3 normal;  // normalize(cross(edge_u, edge_v))

  static QuadShape Make(const Vec3& origin, const Vec3& edge_u, const Vec3& edge_v);
  float Area() const;
  SurfacePoint SampleArea(Vec2 u) const;  // uniform, density 1 / Area()
  std::string ToString() const;
};

// A vertex tangent as glTF gives it: xyz points along increasing u; the bitangent is
// w * cross(normal, xyz), w = 1 or -1.
struct Tangent {
  Vec3 xyz;
  float w = 1;
};

struct TriangleMesh {
  std::vector<Vec3> positions;
  std::vector<uint32_t> indices;  // three per triangle, counter-clockwise from the front
  // Optional vertex attributes (docs/mesh-format.md), each empty or one per position.
  std::vector<Vec3> normals;      // shading normals, of any length (0: none at that vertex)
  std::vector<Vec2> texcoords;    // u, v; v grows downwards in the image, as in glTF
  std::vector<Tangent> tangents;

  int triangle_count() const { return static_cast<int>(indices.size() / 3); }
  // What the mesh's arrays hold, in bytes (not counting Embree's copy).
  std::size_t MemoryBytes() const;
  void Corners(int triangle, Vec3& p0, Vec3& p1, Vec3& p2) const;
  // cross(p1 - p0, p2 - p0): length twice the area, direction the front.
  Vec3 ScaledNormal(int triangle) const;
  std::string ToString() const;
};

// A mesh of Scene.meshes: its parts, each one file's triangles with one material, in
// object space.
struct SceneMesh {
  struct Part {
    std::shared_ptr<const TriangleMesh> triangles;
    int material = 0;  // index into SceneData::materials
    Bounds3 bounds;    // in object space
  };
  std::string name;
  std::vector<Part> parts;
  Bounds3 bounds;  // of every part, in object space
};

// A SceneMesh placed in the world (Shape.instance).
struct InstanceShape {
  std::shared_ptr<const SceneMesh> mesh;
  Placement placement;

  std::string ToString() const;
};

// Meshes are shared (not copied) between the shape that owns the geometry, the light that
// samples it and, for instances, every other shape that places the same mesh.
using ShapeGeometry = std::variant<SphereShape, QuadShape, std::shared_ptr<const TriangleMesh>, InstanceShape>;

std::string ToString(const ShapeGeometry& geometry);

// The smallest axis-aligned box around the geometry (for an instance, a box around its
// mesh's box placed).
Bounds3 BoundsOf(const ShapeGeometry& geometry);
Bounds3 BoundsOf(const TriangleMesh& mesh);

// A box around b's corners placed.
Bounds3 Place(const Bounds3& b, const Placement& placement);

// A sphere around the geometry: the sphere itself for spheres, else the box's sphere.
BoundingSphere BoundingSphereOf(const ShapeGeometry& geometry);

}  // namespace farm
