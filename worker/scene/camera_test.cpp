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

namespace farm {
namespace {

// p M for a row vector p = (x, y, z, 1), then divided by the fourth component.
Vec3d Project(const Matrix44& m, const Vec3& p) {
  double out[4];
  for (int j = 0; j < 4; ++j) out[j] = p.x * m[0 * 4 + j] + p.y * m[1 * 4 + j] + p.z * m[2 * 4 + j] + m[3 * 4 + j];
  return {out[0] / out[3], out[1] / out[3], out[2] / out[3]};
}

TEST(Camera, ThinLensRaysMeetAtTheFocusDistance) {
  const ThinLens lens{0.2, 0};  // focused on look_at, 5 away
  const Camera camera({0, 0, 0}, {3, 0, -4}, {0, 1, 0}, 50, 64, 48, lens);
  SCOPED_TRACE(camera.ToString());
  ASSERT_TRUE(camera.has_lens());
  EXPECT_FLOAT_EQ(camera.focus_distance(), 5);
  const Camera pinhole({0, 0, 0}, {3, 0, -4}, {0, 1, 0}, 50, 64, 48);
  for (const Vec2 film : {Vec2{32, 24}, Vec2{3.5f, 40}, Vec2{60, 1}}) {
    // Where the pinhole ray meets the plane in focus (5 along forward).
    const Ray p = pinhole.GenerateRay(film);
    const Vec3 focus = p.At(5 / Dot(p.direction, camera.forward()));
    for (const Vec2 u : {Vec2{0.1f, 0.2f}, Vec2{0.9f, 0.5f}, Vec2{0.5f, 0.99f}}) {
      const Ray r = camera.GenerateRay(film, u);
      EXPECT_NEAR(Length(r.direction), 1, 1e-5);
      EXPECT_LE(Distance(r.origin, Vec3(0, 0, 0)), 0.2f + 1e-6f);            // on the lens
      EXPECT_NEAR(Dot(r.origin, camera.forward()), 0, 1e-6);                    // in its plane
      EXPECT_NEAR(Distance(r.At(Dot(focus - r.origin, r.direction)), focus), 0, 1e-4);
    }
  }
  EXPECT_FALSE(pinhole.has_lens());
  EXPECT_FLOAT_EQ(Camera({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 50, 8, 8, {0.1, 2.5}).focus_distance(), 2.5f);
}

TEST(Camera, ExrMatricesProjectEachPixelsRayOntoItsPixel) {
  const Camera camera({1, 2, 3}, {4, -2, 10}, {0, 1, 0}, 40, 64, 32);
  const Matrix44 to_camera = camera.WorldToCamera();
  const Matrix44 to_ndc = camera.WorldToNdc();
  // The camera's position is the origin of camera space; forward is +z (left-handed, x
  // right, y up).
  EXPECT_NEAR(Length(Vec3(Project(to_camera, camera.position()))), 0, 1e-5);
  const Vec3d ahead = Project(to_camera, camera.position() + camera.forward() * 2.0f);
  EXPECT_NEAR(ahead.z, 2, 1e-5);
  const Vec3d right = Project(to_camera, camera.position() + camera.right());
  EXPECT_NEAR(right.x, 1, 1e-5);
  for (const Vec2 film : {Vec2{0, 0}, Vec2{64, 32}, Vec2{10.5f, 20.25f}, Vec2{32, 16}}) {
    const Ray r = camera.GenerateRay(film);
    for (const float t : {0.5f, 7.0f}) {
      const Vec3d ndc = Project(to_ndc, r.At(t));
      EXPECT_NEAR(ndc.x, film.x / 64, 1e-5);
      EXPECT_NEAR(ndc.y, film.y / 32, 1e-5);
      EXPECT_NEAR(ndc.z, 1 / (t * Dot(r.direction, camera.forward())), 1e-4);
    }
  }
}

}  // namespace
}  // namespace farm
