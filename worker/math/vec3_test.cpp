#include "math/vec3.h"

#include <gtest/gtest.h>

#include "math/ray.h"
#include "math/rgb.h"

namespace farm {
namespace {

TEST(Vec3, CrossFollowsTheRightHandRule) {
  EXPECT_EQ(Cross(Vec3(1, 0, 0), Vec3(0, 1, 0)), Vec3(0, 0, 1));
  EXPECT_EQ(Cross(Vec3(0, 1, 0), Vec3(0, 0, 1)), Vec3(1, 0, 0));
  // The Cornell box camera: forward +z, up +y, so the image's right is -x.
  EXPECT_EQ(Cross(Vec3(0, 0, 1), Vec3(0, 1, 0)), Vec3(-1, 0, 0));
}

TEST(Vec3, LengthDotNormalize) {
  EXPECT_FLOAT_EQ(Length(Vec3(3, 4, 12)), 13.0f);
  EXPECT_FLOAT_EQ(Dot(Vec3(1, 2, 3), Vec3(4, -5, 6)), 12.0f);
  EXPECT_NEAR(Length(Normalize(Vec3(1e-3f, 2e-3f, -5e-3f))), 1.0f, 1e-6f);
  EXPECT_EQ(MaxComponent(Vec3(-7, 2, 1)), 2.0f);
  EXPECT_EQ(FaceForward(Vec3(0, 0, 1), Vec3(0, 0, -1)), Vec3(0, 0, -1));
}

TEST(Vec3, ToStringShowsComponents) {
  EXPECT_EQ(ToString(Vec3(1, -2.5f, 0)), "[ 1, -2.5, 0 ]");
  EXPECT_EQ(ToString(Rgb(0.5f, 0, 1)), "rgb(0.5, 0, 1)");
}

TEST(Ray, OffsetMovesToTheSideOfTheOutgoingDirection) {
  const Vec3 p(500, 0, 0), n(0, 1, 0);
  const Vec3 above = OffsetRayOrigin(p, n, Vec3(0, 1, 0), 0);
  const Vec3 below = OffsetRayOrigin(p, n, Vec3(0, -1, 0), 0);
  EXPECT_GT(above.y, 0);
  EXPECT_LT(below.y, 0);
  // Scale-aware: the offset is relative to the point's magnitude, so it is larger than one
  // float ulp at 500 (6e-5) and tiny compared with the scene.
  EXPECT_GT(above.y, 1e-3f);
  EXPECT_LT(above.y, 0.1f);
  // Near the origin the scene-size floor applies.
  EXPECT_FLOAT_EQ(OffsetRayOrigin(Vec3(0, 0, 0), n, n, 1e-3f).y, 1e-3f);
}

}  // namespace
}  // namespace farm
