#include "texture/footprint.h"

#include <gtest/gtest.h>

#include <cmath>

namespace farm {
namespace {

// The world-space vector a texture-space axis stands for on a surface with these derivatives.
Vec3 World(Vec2 a, const Vec3& dpdu, const Vec3& dpdv) { return dpdu * a.x + dpdv * a.y; }

// A floor (normal +y) whose texture spans 2 units along x (u) and 3 along z (v).
const Vec3 kN(0, 1, 0), kDpdu(2, 0, 0), kDpdv(0, 0, 3);

TEST(Footprint, HeadOnIsACircleOfTheConesWidth) {
  const FootprintAxes f = FootprintOf(Vec3(0, -1, 0), kN, kDpdu, kDpdv, 0.2f);
  const Vec3 a = World(f.axis1, kDpdu, kDpdv), b = World(f.axis2, kDpdu, kDpdv);
  EXPECT_NEAR(Length(a), 0.2f, 1e-6);
  EXPECT_NEAR(Length(b), 0.2f, 1e-6);
  EXPECT_NEAR(Dot(a, b), 0, 1e-7);
  EXPECT_NEAR(Dot(a, kN), 0, 1e-7);
}

TEST(Footprint, ASlantStretchesTheAxisInTheIncidencePlane) {
  // 60 degrees from the normal, travelling along +x: the section is 0.2 / cos 60 = 0.4
  // long along x, that is 0.2 in u, and 0.2 wide along z, 0.2 / 3 in v.
  const Vec3 d(std::sin(1.0471976f), -std::cos(1.0471976f), 0);
  const FootprintAxes f = FootprintOf(d, kN, kDpdu, kDpdv, 0.2f);
  EXPECT_NEAR(f.axis1.x, 0.2f, 1e-5);
  EXPECT_NEAR(f.axis1.y, 0, 1e-6);
  EXPECT_NEAR(f.axis2.x, 0, 1e-6);
  EXPECT_NEAR(std::abs(f.axis2.y), 0.2f / 3, 1e-6);
}

TEST(Footprint, SkewedDerivativesAreInverted) {
  const Vec3 dpdu(1, 0, 0), dpdv(1, 0, 1);  // v runs diagonally
  const FootprintAxes f = FootprintOf(Vec3(0, -1, 0), kN, dpdu, dpdv, 0.5f);
  const Vec3 a = World(f.axis1, dpdu, dpdv), b = World(f.axis2, dpdu, dpdv);
  EXPECT_NEAR(Length(a), 0.5f, 1e-5);
  EXPECT_NEAR(Length(b), 0.5f, 1e-5);
  EXPECT_NEAR(Dot(a, b), 0, 1e-6);
}

TEST(Footprint, DegenerateOrZeroFootprintsReadTheFinestLevel) {
  for (const FootprintAxes& f : {FootprintOf(Vec3(0, -1, 0), kN, kDpdu, kDpdu * 2, 0.2f),
                                 FootprintOf(Vec3(0, -1, 0), kN, kDpdu, kDpdv, 0),
                                 FootprintOf(Vec3(0, -1, 0), kN, Vec3(), kDpdv, 0.2f)}) {
    EXPECT_EQ(f.axis1, Vec2{});
    EXPECT_EQ(f.axis2, Vec2{});
  }
}

TEST(Footprint, GrazingFootprintsStayFinite) {
  const FootprintAxes f = FootprintOf(Vec3(1, 0, 0), kN, kDpdu, kDpdv, 0.01f);
  EXPECT_TRUE(std::isfinite(f.axis1.x) && std::isfinite(f.axis1.y));
  EXPECT_GT(f.axis1.x, 1.0f) << "many times the texture: the coarsest level";
}

}  // namespace
}  // namespace farm
