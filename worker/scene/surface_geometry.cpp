#include "scene/surface_geometry.h"

#include <algorithm>
#include <cmath>

#include "math/frame.h"
#include "math/math.h"
#include "scene/scene_data.h"

namespace farm {
namespace {

// An orthonormal pair about the shading normal: the derivatives of a surface that has no
// texture coordinates.
void FrameAboutShadingNormal(SurfaceHit& hit) {
  const Frame f = Frame::FromZ(hit.ns);
  hit.dpdu = f.x;
  hit.dpdv = f.y;
}

Vec2 Mix(const Vec2& a, const Vec2& b, const Vec2& c, float b0, Vec2 bc) {
  return {a.x * b0 + b.x * bc.x + c.x * bc.y, a.y * b0 + b.y * bc.x + c.y * bc.y};
}

Vec3 Mix(const Vec3& a, const Vec3& b, const Vec3& c, float b0, Vec2 bc) { return a * b0 + b * bc.x + c * bc.y; }

// dp/du and dp/dv of a triangle from its corners and their texture coordinates; false if
// the texture coordinates do not span an area (or the result is not finite).
bool TriangleDerivatives(const Vec3 (&p)[3], const Vec2 (&uv)[3], Vec3& dpdu, Vec3& dpdv) {
  const Vec2 d02{uv[0].x - uv[2].x, uv[0].y - uv[2].y}, d12{uv[1].x - uv[2].x, uv[1].y - uv[2].y};
  const Vec3 dp02 = p[0] - p[2], dp12 = p[1] - p[2];
  const float det = d02.x * d12.y - d02.y * d12.x;
  if (!(std::abs(det) > 0)) return false;
  const float inv = 1 / det;
  dpdu = (dp02 * d12.y - dp12 * d02.y) * inv;
  dpdv = (dp12 * d02.x - dp02 * d12.x) * inv;
  return IsFinite(dpdu) && IsFinite(dpdv) && LengthSquared(Cross(dpdu, dpdv)) > 0;
}

// The corners of triangle `triangle` in the world, and its front's unnormalised normal (a
// mirror's corners run clockwise, and their front is the other side). Recomputed from our
// own copy of the geometry, independent of Embree's Ng conventions.
struct PlacedTriangle {
  Vec3 p[3];
  Vec3 scaled_normal;
};
PlacedTriangle Place(const TriangleMesh& m, const Placement* placement, uint32_t triangle) {
  const std::size_t first = std::size_t(triangle) * 3;
  PlacedTriangle t{};
  for (int i = 0; i < 3; ++i) t.p[i] = m.positions[m.indices[first + std::size_t(i)]];
  if (placement)
    for (Vec3& corner : t.p) corner = placement->Point(corner);
  t.scaled_normal = Cross(t.p[1] - t.p[0], t.p[2] - t.p[0]);
  if (placement && placement->mirrors) t.scaled_normal = -t.scaled_normal;
  return t;
}

// The unit vector along v, +z where v is zero (a degenerate sliver's normal, a point at a
// sphere's centre: any unit normal does).
Vec3 UnitOr(const Vec3& v) {
  const float len = Length(v);
  return len > 0 ? v / len : Vec3(0, 0, 1);
}

}  // namespace

Vec3 SphereNormal(const SphereShape& s, const Vec3& point) { return UnitOr(point - s.center); }

Vec3 TriangleNormal(const TriangleMesh& m, const Placement* placement, uint32_t triangle) {
  return UnitOr(Place(m, placement, triangle).scaled_normal);
}

void DescribeSphereHit(const SphereShape& s, const Vec3& point, SurfaceHit& hit) {
  hit.n = SphereNormal(s, point);
  hit.p = s.center + hit.n * s.radius;
  hit.ns = hit.n;
  // The direction n is (sin t sin f, cos t, -sin t cos f) at latitude t from +y and
  // longitude f from -z towards +x: u = 0.5 + f / 2pi, v = t / pi.
  const Vec3& n = hit.n;
  const float sin_t = std::sqrt(n.x * n.x + n.z * n.z);
  hit.uv = {0.5f + std::atan2(n.x, -n.z) * (0.5f * kInvPi), std::acos(std::clamp(n.y, -1.0f, 1.0f)) * kInvPi};
  hit.has_uv = true;
  if (!(sin_t > 0)) {  // a pole: the longitude has no direction
    FrameAboutShadingNormal(hit);
    return;
  }
  hit.dpdu = Vec3(-n.z, 0, n.x) * (2 * kPi * s.radius);
  hit.dpdv = Vec3(n.y * n.x / sin_t, -sin_t, n.y * n.z / sin_t) * (kPi * s.radius);
}

void DescribeQuadHit(const QuadShape& q, const Vec3& point, SurfaceHit& hit) {
  hit.n = q.normal;
  hit.p = point - q.normal * Dot(point - q.origin, q.normal);
  hit.ns = hit.n;
  // p - origin = u edge_u + v edge_v, solved by the normal equations (the edges need not be
  // perpendicular).
  const Vec3 d = hit.p - q.origin;
  const float uu = Dot(q.edge_u, q.edge_u), uv = Dot(q.edge_u, q.edge_v), vv = Dot(q.edge_v, q.edge_v);
  const float du = Dot(d, q.edge_u), dv = Dot(d, q.edge_v), det = uu * vv - uv * uv;
  hit.uv = det > 0 ? Vec2{(du * vv - dv * uv) / det, (dv * uu - du * uv) / det} : Vec2{};
  hit.has_uv = true;
  hit.dpdu = q.edge_u;
  hit.dpdv = q.edge_v;
}

bool TriangleTexcoords(const TriangleMesh& m, uint32_t triangle, Vec2 b, Vec2& uv) {
  if (m.texcoords.empty()) return false;
  const std::size_t first = std::size_t(triangle) * 3;
  uv = Mix(m.texcoords[m.indices[first]], m.texcoords[m.indices[first + 1]], m.texcoords[m.indices[first + 2]],
           1 - b.x - b.y, b);
  return true;
}

void DescribeTriangleHit(const TriangleMesh& m, const Placement* placement, uint32_t triangle, Vec2 b,
                         const Vec3& point, SurfaceHit& hit) {
  const std::size_t first = std::size_t(triangle) * 3;
  const uint32_t v[3] = {m.indices[first], m.indices[first + 1], m.indices[first + 2]};
  const PlacedTriangle placed = Place(m, placement, triangle);
  const Vec3(&p)[3] = placed.p;
  hit.n = UnitOr(placed.scaled_normal);
  // o + t d carries the rounding error of the whole ray length, the projection only that of
  // the primitive's coordinates; a degenerate sliver keeps Embree's point.
  hit.p = LengthSquared(placed.scaled_normal) > 0 ? point - hit.n * Dot(point - p[0], hit.n) : point;

  const float b0 = 1 - b.x - b.y;
  hit.ns = hit.n;
  if (!m.normals.empty()) {
    Vec3 ns = Mix(m.normals[v[0]], m.normals[v[1]], m.normals[v[2]], b0, b);
    if (placement) ns = placement->Normal(ns);
    const float ns_len = Length(ns);
    if (ns_len > 0 && std::isfinite(ns_len)) hit.ns = FaceForward(ns / ns_len, hit.n);
  }

  hit.has_uv = TriangleTexcoords(m, triangle, b, hit.uv);
  bool derivatives = false;
  if (hit.has_uv) {
    const Vec2 uv[3] = {m.texcoords[v[0]], m.texcoords[v[1]], m.texcoords[v[2]]};
    derivatives = TriangleDerivatives(p, uv, hit.dpdu, hit.dpdv);
  }
  if (!m.tangents.empty()) {
    Vec3 t = Mix(m.tangents[v[0]].xyz, m.tangents[v[1]].xyz, m.tangents[v[2]].xyz, b0, b);
    float w = m.tangents[v[0]].w;
    if (placement) {
      t = placement->Vector(t);
      if (placement->mirrors) w = -w;
    }
    t -= hit.ns * Dot(hit.ns, t);
    const float t_len = Length(t);
    if (t_len > 0 && std::isfinite(t_len)) {
      t = t / t_len;
      const Vec3 bitangent = Cross(hit.ns, t) * w;
      const float u_scale = derivatives ? Length(hit.dpdu) : 1, v_scale = derivatives ? Length(hit.dpdv) : 1;
      hit.dpdu = t * u_scale;
      hit.dpdv = -bitangent * v_scale;
      return;
    }
  }
  if (!derivatives) FrameAboutShadingNormal(hit);
}

}  // namespace farm
