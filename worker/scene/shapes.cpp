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

std::size_t TriangleMesh::MemoryBytes() const {
  return positions.size() * sizeof(Vec3) + indices.size() * sizeof(uint32_t) + normals.size() * sizeof(Vec3) +
         texcoords.size() * sizeof(Vec2) + tangents.size() * sizeof(Tangent);
}

std::string TriangleMesh::ToString() const {
  return "TriangleMesh{vertices=" + std::to_string(positions.size()) +
         ", triangles=" + std::to_string(triangle_count()) + (normals.empty() ? "" : ", normals") +
         (texcoords.empty() ? "" : ", texcoords") + (tangents.empty() ? "" : ", tangents") + "}";
}

Bounds3 Place(const Bounds3& b, const Placement& placement) {
  Bounds3 placed;
  if (b.empty()) return placed;
  for (int corner = 0; corner < 8; ++corner)
    placed.Extend(placement.Point({corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y,
                                   corner & 4 ? b.max.z : b.min.z}));
  return placed;
}

Bounds3 BoundsOf(const TriangleMesh& mesh) {
  Bounds3 b;
  for (const Vec3& p : mesh.positions) b.Extend(p);
  return b;
}

std::string InstanceShape::ToString() const {
  return "Instance{mesh=\"" + mesh->name + "\", parts=" + std::to_string(mesh->parts.size()) + ", " +
         farm::ToString(placement.to_world) + "}";
}

std::string ToString(const ShapeGeometry& geometry) {
  struct Visitor {
    std::string operator()(const SphereShape& s) const { return s.ToString(); }
    std::string operator()(const QuadShape& q) const { return q.ToString(); }
    std::string operator()(const std::shared_ptr<const TriangleMesh>& m) const {
      return m ? m->ToString() : "TriangleMesh{null}";
    }
    std::string operator()(const InstanceShape& i) const { return i.ToString(); }
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
    Bounds3 operator()(const std::shared_ptr<const TriangleMesh>& m) const { return m ? BoundsOf(*m) : Bounds3(); }
    Bounds3 operator()(const InstanceShape& i) const { return Place(i.mesh->bounds, i.placement); }
  };
  return std::visit(Visitor{}, geometry);
}

BoundingSphere BoundingSphereOf(const ShapeGeometry& geometry) {
  if (const auto* s = std::get_if<SphereShape>(&geometry)) return {s->center, s->radius};
  return BoundingSphere::Of(BoundsOf(geometry));
}

}  // namespace farm
