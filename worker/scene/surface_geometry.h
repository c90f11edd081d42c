#pragma once

// How a hit on each kind of shape is described (SurfaceHit, scene_data.h): the point moved
// back onto the surface, the geometric and shading normals, texture coordinates and the
// surface's derivatives by them. Each function fills those fields of `hit` from `point`,
// where the ray met the surface.

#include <cstdint>

#include "math/transform.h"
#include "math/vec3.h"
#include "scene/shapes.h"

namespace farm {

struct SurfaceHit;

// The geometric normal (SurfaceHit::n) each Describe function gives, alone: what a probe
// that only asks which way a surface faces needs (SceneData::IntersectFacing). A sphere's
// points outward from its centre; a triangle's is its front's, the corners' cross product
// turned for a mirroring placement, +z for a degenerate sliver.
Vec3 SphereNormal(const SphereShape& sphere, const Vec3& point);
Vec3 TriangleNormal(const TriangleMesh& mesh, const Placement* placement, uint32_t triangle);

void DescribeSphereHit(const SphereShape& sphere, const Vec3& point, SurfaceHit& hit);
void DescribeQuadHit(const QuadShape& quad, const Vec3& point, SurfaceHit& hit);
// Triangle `triangle` of `mesh` at Embree's barycentric coordinates, placed in the world by
// `placement` (an instance's) or already there (nullptr).
void DescribeTriangleHit(const TriangleMesh& mesh, const Placement* placement, uint32_t triangle, Vec2 barycentric,
                         const Vec3& point, SurfaceHit& hit);
// The texture coordinates of `mesh` at the barycentric point of triangle `triangle`, as
// DescribeTriangleHit gives them; false (uv untouched) if the mesh has none.
bool TriangleTexcoords(const TriangleMesh& mesh, uint32_t triangle, Vec2 barycentric, Vec2& uv);

}  // namespace farm
