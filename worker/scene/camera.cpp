#include "scene/camera.h"

#include <cmath>

#include "math/math.h"
#include "renderfarm/v1/scene.pb.h"
#include "sampling/warps.h"
#include "scene/proto_values.h"

namespace farm {
namespace {

// a b, both row-major 4x4.
Matrix44 Multiply(const Matrix44& a, const Matrix44& b) {
  Matrix44 m{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) m[i * 4 + j] += a[i * 4 + k] * b[k * 4 + j];
  return m;
}

}  // namespace

Camera::Camera(const Vec3d& position, const Vec3d& look_at, const Vec3d& up,
               double vertical_fov_degrees, int width, int height, const ThinLens& lens) {
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
  aperture_radius_ = static_cast<float>(lens.aperture_radius);
  focus_distance_ = static_cast<float>(lens.focus_distance > 0 ? lens.focus_distance : Length(look_at - position));
}

Camera Camera::FromProto(const renderfarm::v1::Camera& c, int width, int height) {
  return Camera(Vec3dOf(c.position()), Vec3dOf(c.look_at()), Vec3dOf(c.up()), c.vertical_fov_degrees(),
                width, height, ThinLens{c.aperture_radius(), c.focus_distance()});
}

Ray Camera::GenerateRay(Vec2 film, Vec2 lens) const {
  // Screen coordinates in [-1, 1], y up; d reaches the plane at unit distance.
  const float sx = 2 * film.x / width_ - 1;
  const float sy = 1 - 2 * film.y / height_;
  const Vec3 d = forward_ + right_ * (sx * tan_half_fov_ * aspect_) + up_ * (sy * tan_half_fov_);
  if (!has_lens()) return Ray{position_, Normalize(d)};
  const Vec2 disc = SampleUniformDiskConcentric(lens);
  const Vec3 origin = position_ + (right_ * disc.x + up_ * disc.y) * aperture_radius_;
  const Vec3 focus = position_ + d * focus_distance_;
  return Ray{origin, Normalize(focus - origin)};
}

Matrix44 Camera::WorldToCamera() const {
  const Vec3 axes[3] = {right_, up_, forward_};
  Matrix44 m{};
  for (int j = 0; j < 3; ++j) {
    m[0 * 4 + j] = axes[j].x;
    m[1 * 4 + j] = axes[j].y;
    m[2 * 4 + j] = axes[j].z;
    m[3 * 4 + j] = -double(Dot(position_, axes[j]));
  }
  m[15] = 1;
  return m;
}

Matrix44 Camera::WorldToNdc() const {
  // From camera space: x / z = sx tan aspect with sx = 2 ndc_x - 1, y / z = sy tan with
  // sy = 1 - 2 ndc_y; w = z, and z' = 1 so that the matrix is invertible.
  const double a = 1 / (2.0 * tan_half_fov_ * aspect_), b = 1 / (2.0 * tan_half_fov_);
  const Matrix44 projection = {a, 0, 0, 0,  //
                               0, -b, 0, 0,  //
                               0.5, 0.5, 0, 1,  //
                               0, 0, 1, 0};
  return Multiply(WorldToCamera(), projection);
}

std::string Camera::ToString() const {
  return "Camera{position=" + farm::ToString(position_) + ", forward=" + farm::ToString(forward_) +
         ", right=" + farm::ToString(right_) + ", up=" + farm::ToString(up_) +
         ", tan_half_fov=" + std::to_string(tan_half_fov_) + ", aspect=" + std::to_string(aspect_) +
         ", aperture_radius=" + std::to_string(aperture_radius_) +
         ", focus_distance=" + std::to_string(focus_distance_) + "}";
}

}  // namespace farm
