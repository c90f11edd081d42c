#include "math/frame.h"

#include <gtest/gtest.h>

namespace farm {
namespace {

TEST(Frame, IsOrthonormalAndRightHandedForManyNormals) {
  const Vec3 normals[] = {{0, 0, 1},  {0, 0, -1},         {1, 0, 0},        {0, -1, 0},
                          {1, 1, 1},  {-0.3f, 0.2f, -0.9f}, {1e-4f, 0, -1},  {0, 1e-4f, 1}};
  for (Vec3 n : normals) {
    n = Normalize(n);
    const Frame f = Frame::FromZ(n);
    SCOPED_TRACE(ToString(f));
    EXPECT_NEAR(Length(f.x), 1, 1e-6);
    EXPECT_NEAR(Length(f.y), 1, 1e-6);
    EXPECT_NEAR(Dot(f.x, f.y), 0, 1e-6);
    EXPECT_NEAR(Dot(f.x, f.z), 0, 1e-6);
    EXPECT_NEAR(Dot(f.y, f.z), 0, 1e-6);
    EXPECT_NEAR(Length(Cross(f.x, f.y) - f.z), 0, 1e-6);
  }
}

TEST(Frame, ToLocalAndBackIsIdentity) {
  const Frame f = Frame::FromZ(Normalize(Vec3(0.2f, -0.7f, 0.4f)));
  const Vec3 v(0.3f, 1.5f, -2.0f);
  EXPECT_NEAR(Length(f.FromLocal(f.ToLocal(v)) - v), 0, 1e-5);
  EXPECT_NEAR(f.ToLocal(f.z).z, 1, 1e-6);
}

}  // namespace
}  // namespace farm
