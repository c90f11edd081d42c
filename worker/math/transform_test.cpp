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

}  // namespace
}  // namespace farm
