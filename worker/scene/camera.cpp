#include "scene/camera.h"

#include <cmath>

#include "math/math.h"
#include "renderfarm/v1/scene.pb.h"
#include "scene/proto_values.h"

namespace farm {

Camera::Camera(const Vec3d& position, const Vec3d& look_at, const Vec3d& up,
               double vertical_fov_degrees, int width, int height) {
  const Vec3d forward = Normalize(look_at - position);
  const Vec3d r = Normalize(Cross(forward, up));
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
  return Camera(Vec3dOf(c.position()), Vec3dOf(c.look_at()), Vec3dOf(c.up()), c.vertical_fov_degrees(),
                width, height);
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
