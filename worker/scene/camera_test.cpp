#include "scene/camera.h"

#include <gtest/gtest.h>

#include <cmath>


namespace farm {
namespace {

TEST(Camera, CentrePixelLooksAtLookAt) {
  const Vec3d position(1, 2, 3), look_at(4, -2, 10);
  const Camera camera(position, look_at, {0, 1, 0}, 40, 5, 3);  // odd sizes: a centre pixel
  const Ray ray = camera.GenerateRay({2.5f, 1.5f});
  SCOPED_TRACE(camera.ToString());
  EXPECT_NEAR(Length(ray.origin - Vec3(position)), 0, 1e-6);
  EXPECT_NEAR(Length(ray.direction - Vec3(Normalize(look_at - position))), 0, 1e-6);
  EXPECT_NEAR(Length(ray.direction), 1, 1e-6);
}

TEST(Camera, CornellBoxConventionPutsLargeXOnTheLeft) {
  // Camera of the Cornell box: at (278, 273, -800) looking +z, up +y. Its right is
  // cross(+z, +y) = -x, so the wall at x = 556 appears on the left of the image.
  const Camera camera({278, 273, -800}, {278, 273, 0}, {0, 1, 0}, 39.3, 64, 64);
  EXPECT_EQ(camera.right(), Vec3(-1, 0, 0));
  const Ray left = camera.GenerateRay({0.5f, 32});
  const Ray right = camera.GenerateRay({63.5f, 32});
  const Ray top = camera.GenerateRay({32, 0.5f});
  // Where they cross the plane z = 0 (the back wall is at z = 559, same sign).
  auto at_z0 = [](const Ray& r) { return r.At(-r.origin.z / r.direction.z); };
  EXPECT_GT(at_z0(left).x, 278 + 200);
  EXPECT_LT(at_z0(right).x, 278 - 200);
  EXPECT_GT(at_z0(top).y, 273 + 200);
}

TEST(Camera, EdgeOfTheFilmIsHalfTheFieldOfViewAway) {
  const double fov = 60;
  const Camera camera({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, fov, 200, 100);
  const Ray top = camera.GenerateRay({100, 0});
  EXPECT_NEAR(std::acos(Dot(top.direction, Vec3(0, 0, -1))), fov / 2 * std::numbers::pi / 180,
              1e-5);
  EXPECT_GT(top.direction.y, 0);
  // Square pixels: the horizontal half-extent is aspect times the vertical one.
  const Ray side = camera.GenerateRay({200, 50});
  EXPECT_NEAR(side.direction.x / -side.direction.z, 2 * std::tan(fov / 2 * std::numbers::pi / 180),
              1e-5);
}

}  // namespace
}  // namespace farm
