#pragma once

// The geometry kinds of a scene, as the renderer keeps them next to Embree's copy: enough
// to recover a precise hit point and the geometric normal of a hit, to sample points by
// area for lights, and (later) to emit photons. Each kind's front side is the side its
// geometric normal points to: outside for spheres, cross(edge_u, edge_v) for quads,
// counter-clockwise for triangles.

#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "math/bounds.h"
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

struct TriangleMesh {
  std::vector<Vec3> positions;
  std::vector<uint32_t> indices;  // three per triangle, counter-clockwise from the front

  int triangle_count() const { return static_cast<int>(indices.size() / 3); }
  void Corners(int triangle, Vec3& p0, Vec3& p1, Vec3& p2) const;
  // cross(p1 - p0, p2 - p0): length twice the area, direction the front.
  Vec3 ScaledNormal(int triangle) const;
  float TriangleArea(int triangle) const;
  std::string ToString() const;
};

// Meshes are shared (not copied) between the shape that owns the geometry and the light
// that samples it.
using ShapeGeometry = std::variant<SphereShape, QuadShape, std::shared_ptr<const TriangleMesh>>;

std::string ToString(const ShapeGeometry& geometry);

// The smallest axis-aligned box around the geometry.
Bounds3 BoundsOf(const ShapeGeometry& geometry);

// A sphere around the geometry: the sphere itself for spheres, else the box's sphere.
BoundingSphere BoundingSphereOf(const ShapeGeometry& geometry);

}  // namespace farm
