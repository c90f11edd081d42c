#include "math/transform.h"

#include <gtest/gtest.h>

namespace farm {
namespace {

void ExpectNear(const Vec3d& a, const Vec3d& b) {
  EXPECT_NEAR(Length(a - b), 0, 1e-12) << ToString(a) << " vs " << ToString(b);
}

TEST(Affine3d, RotatesByTheRightHandRule) {
  const Affine3d a = Affine3d::ScaleRotateTranslate({1, 1, 1}, {0, 0, 1}, 90, {});
  ExpectNear(a.Apply({1, 0, 0}), {0, 1, 0});
  ExpectNear(a.Apply({0, 1, 0}), {-1, 0, 0});
}

TEST(Affine3d, ScalesThenRotatesThenTranslates) {
  // x scaled by 2 first, then (2,0,0) rotated 90 degrees about y to (0,0,-2), then moved.
  const Affine3d a = Affine3d::ScaleRotateTranslate({2, 3, 4}, {0, 5, 0}, 90, {10, 20, 30});
  SCOPED_TRACE(ToString(a));
  ExpectNear(a.Apply({1, 0, 0}), {10, 20, 28});
  ExpectNear(a.Apply({0, 1, 0}), {10, 23, 30});
  ExpectNear(a.Apply({0, 0, 1}), {14, 20, 30});
  EXPECT_NEAR(a.Determinant(), 24, 1e-12);
}

TEST(Affine3d, ZeroAngleIgnoresAxis) {
  const Affine3d a = Affine3d::ScaleRotateTranslate({1, 1, 1}, {0, 0, 0}, 0, {1, 2, 3});
  ExpectNear(a.Apply({0, 0, 0}), {1, 2, 3});
}

TEST(Affine3d, FromRowsReadsThreeRowsOfFour) {
  const double rows[12] = {0, -1, 0, 5, 1, 0, 0, 6, 0, 0, 2, 7};
  const Affine3d a = Affine3d::FromRows(rows);
  ExpectNear(a.Apply({1, 0, 0}), {5, 7, 7});
  ExpectNear(a.Apply({0, 0, 1}), {5, 6, 9});
  EXPECT_EQ(a.Determinant(), 2);
}

// A normal stays perpendicular to every tangent of the surface, under shears and mirrors.
TEST(Placement, NormalsStayPerpendicularToMovedTangents) {
  const double shear[12] = {1, 2, 0, 0, 0, 1, 0, 0, 0, 0, 3, 0};
  const double mirror_shear[12] = {-1, 0.5, 0, 1, 0, 1, 0, 0, 0.25, 0, 1, 2};
  for (const auto* rows : {&shear, &mirror_shear}) {
    const Placement p(Affine3d::FromRows(*rows));
    const Vec3 n(0.3f, -0.5f, 0.8f), t1 = Cross(n, Vec3(1, 0, 0)), t2 = Cross(n, t1);
    const Vec3 moved = p.Normal(n);
    EXPECT_NEAR(Dot(moved, p.Vector(t1)), 0, 1e-5);
    EXPECT_NEAR(Dot(moved, p.Vector(t2)), 0, 1e-5);
  }
}

// The front of a triangle is where its normal points; a mirror turns its corners' order
// around, and the moved normal is the front of the corners in their new order.
TEST(Placement, AMirrorKeepsTheFrontTheNormalNames) {
  const double mirror[12] = {-2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  const Placement p(Affine3d::FromRows(mirror));
  EXPECT_TRUE(p.mirrors);
  const Vec3 a(0, 0, 0), b(0, 1, 0), c(0, 0, 1);  // counter-clockwise about +x
  const Vec3 n = Cross(b - a, c - a);
  const Vec3 pa = p.Point(a), pb = p.Point(b), pc = p.Point(c);
  const Vec3 front_of_swapped = Cross(pc - pa, pb - pa);  // what a mirrored mesh file's winding gives
  EXPECT_GT(Dot(p.Normal(n), front_of_swapped), 0);
  EXPECT_FALSE(Placement(Affine3d::ScaleRotateTranslate({1, 2, 3}, {1, 1, 0}, 40, {})).mirrors);
}

// The inverse undoes the map (points, and directions by the linear part), for a rotation
// with uneven scales and translation and for a general matrix with a negative determinant.
TEST(Affine3d, TheInverseUndoesTheMap) {
  const double rows[12] = {0.5, 2, -1, 3, 0, 1, 4, -2, 1, 0, -3, 0.25};
  for (const Affine3d& a : {Affine3d::ScaleRotateTranslate({3, 0.5, 2}, {1, 2, -1}, 70, {5, -1, 2}), Affine3d::FromRows(rows)}) {
    const Affine3d inv = a.Inverse();
    for (const Vec3d p : {Vec3d(0, 0, 0), Vec3d(1, -2, 3), Vec3d(-7, 0.5, 11)}) {
      const Vec3d back = inv.Apply(a.Apply(p)), dir = inv.ApplyLinear(a.ApplyLinear(p));
      EXPECT_NEAR(back.x, p.x, 1e-12);
      EXPECT_NEAR(back.y, p.y, 1e-12);
      EXPECT_NEAR(back.z, p.z, 1e-12);
      EXPECT_NEAR(dir.x, p.x, 1e-12);
      EXPECT_NEAR(dir.z, p.z, 1e-12);
    }
  }
}

}  // namespace
}  // namespace farm
