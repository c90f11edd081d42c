#include "scene/shapes.h"

#include "math/math.h"
#include "sampling/warps.h"

namespace farm {

float SphereShape::Area() const { return 4 * kPi * radius * radius; }

std::string SphereShape::ToString() const {
  return "Sphere{center=" + farm::ToString(center) + ", radius=" + std::to_string(radius) + "}";
}

QuadShape QuadShape::Make(const Vec3& origin, const Vec3& edge_u, const Vec3& edge_v) {
  return {origin, edge_u, edge_v, Normalize(Cross(edge_u, edge_v))};
}

float QuadShape::Area() const { return Length(Cross(edge_u, edge_v)); }

SurfacePoint QuadShape::SampleArea(Vec2 u) const {
  return {SampleParallelogram(origin, edge_u, edge_v, u), normal};
}

std::string QuadShape::ToString() const {
  return "Quad{origin=" + farm::ToString(origin) + ", edge_u=" + farm::ToString(edge_u) +
         ", edge_v=" + farm::ToString(edge_v) + "}";
}

void TriangleMesh::Corners(int triangle, Vec3& p0, Vec3& p1, Vec3& p2) const {
  const std::size_t i = std::size_t(triangle) * 3;
  p0 = positions[indices[i]];
  p1 = positions[indices[i + 1]];
  p2 = positions[indices[i + 2]];
}

Vec3 TriangleMesh::ScaledNormal(int triangle) const {
  Vec3 p0, p1, p2;
  Corners(triangle, p0, p1, p2);
  return Cross(p1 - p0, p2 - p0);
}

float TriangleMesh::TriangleArea(int triangle) const {
  return 0.5f * Length(ScaledNormal(triangle));
}

std::string TriangleMesh::ToString() const {
  return "TriangleMesh{vertices=" + std::to_string(positions.size()) +
         ", triangles=" + std::to_string(triangle_count()) + "}";
}

std::string ToString(const ShapeGeometry& geometry) {
  struct Visitor {
    std::string operator()(const SphereShape& s) const { return s.ToString(); }
    std::string operator()(const QuadShape& q) const { return q.ToString(); }
    std::string operator()(const std::shared_ptr<const TriangleMesh>& m) const {
      return m ? m->ToString() : "TriangleMesh{null}";
    }
  };
  return std::visit(Visitor{}, geometry);
}

Bounds3 BoundsOf(const ShapeGeometry& geometry) {
  struct Visitor {
    Bounds3 operator()(const SphereShape& s) const {
      Bounds3 b;
      b.Extend(s.center - Vec3(s.radius, s.radius, s.radius));
      b.Extend(s.center + Vec3(s.radius, s.radius, s.radius));
      return b;
    }
    Bounds3 operator()(const QuadShape& q) const {
      Bounds3 b;
      for (const Vec3& p : {q.origin, q.origin + q.edge_u, q.origin + q.edge_v,
                            q.origin + q.edge_u + q.edge_v})
        b.Extend(p);
      return b;
    }
    Bounds3 operator()(const std::shared_ptr<const TriangleMesh>& m) const {
      Bounds3 b;
      if (m)
        for (const Vec3& p : m->positions) b.Extend(p);
      return b;
    }
  };
  return std::visit(Visitor{}, geometry);
}

BoundingSphere BoundingSphereOf(const ShapeGeometry& geometry) {
  if (const auto* s = std::get_if<SphereShape>(&geometry)) return {s->center, s->radius};
  return BoundingSphere::Of(BoundsOf(geometry));
}

}  // namespace farm
