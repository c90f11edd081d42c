#include "scene/surface_geometry.h"

#include <gtest/gtest.h>

#include <cmath>

#include "math/math.h"
#include "scene/scene_data.h"

namespace farm {
namespace {

void ExpectNear(const Vec3& a, const Vec3& b, float tolerance) {
  EXPECT_LE(Length(a - b), tolerance) << a << " vs " << b;
}

// A sphere's texture coordinates are an equirectangular map's, and dp/du, dp/dv are the
// derivatives of the point they map to: checked by finite differences of that map.
TEST(DescribeSphereHit, TextureCoordinatesAndTheirDerivatives) {
  const SphereShape s{{1, 2, 3}, 2};
  const auto at = [&](float u, float v) {  // the point at (u, v)
    const float f = (u - 0.5f) * 2 * kPi, t = v * kPi;
    return s.center + Vec3(std::sin(t) * std::sin(f), std::cos(t), -std::sin(t) * std::cos(f)) * s.radius;
  };
  SurfaceHit hit;
  DescribeSphereHit(s, s.center + Vec3(0, 0, -5), hit);  // looking along -z from the centre
  EXPECT_TRUE(hit.has_uv);
  EXPECT_NEAR(hit.uv.x, 0.5f, 1e-6f);
  EXPECT_NEAR(hit.uv.y, 0.5f, 1e-6f);
  DescribeSphereHit(s, s.center + Vec3(1, 0, 0), hit);  // +x: a quarter turn on
  EXPECT_NEAR(hit.uv.x, 0.75f, 1e-6f);
  for (const Vec2 uv : {Vec2{0.3f, 0.2f}, Vec2{0.9f, 0.7f}}) {
    DescribeSphereHit(s, at(uv.x, uv.y), hit);
    EXPECT_NEAR(hit.uv.x, uv.x, 1e-5f);
    EXPECT_NEAR(hit.uv.y, uv.y, 1e-5f);
    const float h = 1e-3f;
    ExpectNear(hit.dpdu, (at(uv.x + h, uv.y) - at(uv.x - h, uv.y)) / (2 * h), 2e-2f);
    ExpectNear(hit.dpdv, (at(uv.x, uv.y + h) - at(uv.x, uv.y - h)) / (2 * h), 2e-2f);
    EXPECT_EQ(hit.ns, hit.n);
  }
  DescribeSphereHit(s, s.center + Vec3(0, 3, 0), hit);  // the pole: a frame about the normal
  EXPECT_NEAR(Length(hit.dpdu), 1, 1e-6f);
  EXPECT_NEAR(Dot(hit.dpdu, hit.n), 0, 1e-6f);
}

TEST(DescribeQuadHit, TextureCoordinatesRunAlongTheEdges) {
  const QuadShape q = QuadShape::Make({0, 0, 0}, {2, 0, 0}, {1, 0, -4});  // sheared
  SurfaceHit hit;
  DescribeQuadHit(q, q.origin + q.edge_u * 0.25f + q.edge_v * 0.5f + Vec3(0, 0.01f, 0), hit);
  EXPECT_NEAR(hit.uv.x, 0.25f, 1e-6f);
  EXPECT_NEAR(hit.uv.y, 0.5f, 1e-6f);
  EXPECT_EQ(hit.dpdu, q.edge_u);
  EXPECT_EQ(hit.dpdv, q.edge_v);
  EXPECT_EQ(hit.p.y, 0);
}

// One triangle with every attribute: corners p0, p1, p2 at texture coordinates (0, 1),
// (1, 1), (0, 0) (v down, so p2 is up the image).
TriangleMesh Triangle() {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {2, 0, 0}, {0, 3, 0}};
  m.indices = {0, 1, 2};
  m.texcoords = {{0, 1}, {1, 1}, {0, 0}};
  m.normals = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  return m;
}

TEST(DescribeTriangleHit, InterpolatesTextureCoordinatesAndNormals) {
  const TriangleMesh m = Triangle();
  SurfaceHit hit;
  const Vec2 b{0.25f, 0.5f};
  DescribeTriangleHit(m, nullptr, 0, b, {0.5f, 1.5f, 0.2f}, hit);
  EXPECT_EQ(hit.n, Vec3(0, 0, 1));
  EXPECT_EQ(hit.p, Vec3(0.5f, 1.5f, 0));
  EXPECT_NEAR(hit.uv.x, 0.25f, 1e-6f);
  EXPECT_NEAR(hit.uv.y, 0.5f, 1e-6f);
  ExpectNear(hit.ns, Normalize(Vec3(0.25f, 0.5f, 1)), 1e-6f);
  // Every edge is the derivatives times its change of texture coordinates.
  ExpectNear(hit.dpdu * 1 + hit.dpdv * 0, m.positions[1] - m.positions[0], 1e-6f);
  ExpectNear(hit.dpdv * -1, m.positions[2] - m.positions[0], 1e-6f);
}

TEST(DescribeTriangleHit, ShadingNormalsLieOnTheFrontAndZeroOnesFallBack) {
  TriangleMesh m = Triangle();
  m.normals = {{0, 0, -1}, {0, 0, -1}, {0, 0, -1}};  // pointing to the back
  SurfaceHit hit;
  DescribeTriangleHit(m, nullptr, 0, {0.2f, 0.2f}, {0.1f, 0.1f, 0}, hit);
  EXPECT_EQ(hit.ns, Vec3(0, 0, 1));
  m.normals = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  DescribeTriangleHit(m, nullptr, 0, {0.2f, 0.2f}, {0.1f, 0.1f, 0}, hit);
  EXPECT_EQ(hit.ns, hit.n);
}

TEST(DescribeTriangleHit, TangentsGiveTheFrameTheirDirectionsAndTheTextureTheirLengths) {
  TriangleMesh m = Triangle();
  m.normals.clear();
  m.tangents = {{{1, 0, 0.5f}, 1}, {{1, 0, 0.5f}, 1}, {{1, 0, 0.5f}, 1}};
  SurfaceHit hit;
  DescribeTriangleHit(m, nullptr, 0, {0.2f, 0.2f}, {0.4f, 0.6f, 0}, hit);
  ExpectNear(hit.dpdu, Vec3(2, 0, 0), 1e-6f);  // the tangent made perpendicular to ns, |dp/du| = 2
  // The bitangent cross(n, t) = +y is up the image, where v decreases: dp/dv = -3 y.
  ExpectNear(hit.dpdv, Vec3(0, -3, 0), 1e-6f);
  m.tangents.assign(3, {{1, 0, 0}, -1});
  DescribeTriangleHit(m, nullptr, 0, {0.2f, 0.2f}, {0.4f, 0.6f, 0}, hit);
  ExpectNear(hit.dpdv, Vec3(0, 3, 0), 1e-6f);
}

TEST(DescribeTriangleHit, WithoutTextureCoordinatesAFrameAboutTheShadingNormal) {
  TriangleMesh m = Triangle();
  m.texcoords.clear();
  SurfaceHit hit;
  DescribeTriangleHit(m, nullptr, 0, {0.2f, 0.3f}, {0.4f, 0.9f, 0}, hit);
  EXPECT_FALSE(hit.has_uv);
  EXPECT_NEAR(Length(hit.dpdu), 1, 1e-6f);
  EXPECT_NEAR(Length(hit.dpdv), 1, 1e-6f);
  EXPECT_NEAR(Dot(hit.dpdu, hit.ns), 0, 1e-6f);
  EXPECT_NEAR(Dot(hit.dpdv, hit.ns), 0, 1e-6f);
  EXPECT_NEAR(Dot(hit.dpdu, hit.dpdv), 0, 1e-6f);
}

// A placed triangle is described as the same triangle moved into the world would be: a
// mirror keeps the front its normals name, and the bitangent follows the texture.
TEST(DescribeTriangleHit, APlacementMovesEveryAttribute) {
  TriangleMesh m = Triangle();
  m.tangents = {{{1, 0, 0}, 1}, {{1, 0, 0}, 1}, {{1, 0, 0}, 1}};
  const double rows[12] = {-1, 0, 0, 5, 0, 2, 0, 0, 0, 0, 1, 1};  // mirror x, stretch y, move
  const Placement placement(Affine3d::FromRows(rows));
  SurfaceHit hit;
  DescribeTriangleHit(m, &placement, 0, {0.25f, 0.5f}, {4.5f, 3, 1}, hit);
  EXPECT_EQ(hit.n, Vec3(0, 0, 1));  // the front stays +z: the mirror turned the corners around
  EXPECT_EQ(hit.p, Vec3(4.5f, 3, 1));
  ExpectNear(hit.ns, Normalize(Vec3(-0.25f, 0.25f, 1)), 1e-6f);  // (x, y, z) / (-1, 2, 1)
  m.normals.clear();  // a flat triangle: the tangent needs no projection
  DescribeTriangleHit(m, &placement, 0, {0.25f, 0.5f}, {4.5f, 3, 1}, hit);
  ExpectNear(hit.dpdu, Vec3(-2, 0, 0), 1e-5f);  // the tangent placed; dp/du = p1 - p0 placed
  ExpectNear(hit.dpdv, Vec3(0, -6, 0), 1e-5f);  // p2 - p0 placed is -dp/dv
}

}  // namespace
}  // namespace farm
