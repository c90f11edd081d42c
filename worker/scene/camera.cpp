#include "scene/camera.h"

#include <cmath>

#include "math/math.h"
#include "renderfarm/v1/scene.pb.h"
#include "scene/scene.h"

namespace farm {

Camera::Camera(const Vec3d& position, const Vec3d& look_at, const Vec3d& up,
               double vertical_fov_degrees, int width, int height) {
  if (!(vertical_fov_degrees > 0 && vertical_fov_degrees < 180))
    throw SceneError("camera.vertical_fov_degrees: " + std::to_string(vertical_fov_degrees) +
                     " is outside (0, 180)");
  if (!IsFinite(position) || !IsFinite(look_at) || !IsFinite(up))
    throw SceneError("camera: position, look_at and up must be finite");
  const Vec3d view = look_at - position;
  if (!(LengthSquared(view) > 0)) throw SceneError("camera.look_at: equals camera.position");
  const Vec3d forward = Normalize(view);
  const Vec3d right = Cross(forward, up);
  // |right| = |up| sin(angle between them); refuse angles below ~1e-6 rad.
  if (!(LengthSquared(up) > 0) || Length(right) < 1e-6 * Length(up))
    throw SceneError("camera.up: zero or parallel to the view direction");
  const Vec3d r = Normalize(right);
  position_ = Vec3(position);
  forward_ = Vec3(forward);
  right_ = Vec3(r);
  up_ = Vec3(Cross(r, forward));
  tan_half_fov_ = static_cast<float>(std::tan(Radians(vertical_fov_degrees) / 2));
  width_ = static_cast<float>(width);
  height_ = static_cast<float>(height);
  aspect_ = width_ / height_;
}

Camera Camera::FromProto(const renderfarm::v1::Camera& c, int width, int height) {
  auto v = [](const renderfarm::v1::Vec3& p) { return Vec3d(p.x(), p.y(), p.z()); };
  return Camera(v(c.position()), v(c.look_at()), v(c.up()), c.vertical_fov_degrees(), width,
                height);
}

Ray Camera::GenerateRay(Vec2 film) const {
  // Screen coordinates in [-1, 1], y up.
  const float sx = 2 * film.x / width_ - 1;
  const float sy = 1 - 2 * film.y / height_;
  const Vec3 d = forward_ + right_ * (sx * tan_half_fov_ * aspect_) + up_ * (sy * tan_half_fov_);
  return Ray{position_, Normalize(d)};
}

std::string Camera::ToString() const {
  return "Camera{position=" + farm::ToString(position_) + ", forward=" + farm::ToString(forward_) +
         ", right=" + farm::ToString(right_) + ", up=" + farm::ToString(up_) +
         ", tan_half_fov=" + std::to_string(tan_half_fov_) + ", aspect=" + std::to_string(aspect_) +
         "}";
}

}  // namespace farm
