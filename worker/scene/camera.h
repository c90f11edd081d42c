#pragma once

// A pinhole camera. Film coordinates are in pixels: (0, 0) is the top-left corner of the
// image, (width, height) the bottom-right; pixel (x, y) covers [x, x+1) x [y, y+1). The
// image's right is cross(forward, up) (so the Cornell box camera at z = -800 looking +z with
// up +y sees x = 556 on the left), its up the component of `up` orthogonal to forward.

#include <string>

#include "math/ray.h"
#include "math/vec3.h"

namespace renderfarm::v1 {
class Camera;
}

namespace farm {

class Camera {
 public:
  Camera() = default;
  // The view must not be degenerate: look_at differs from position, up is not parallel to
  // the view direction and the field of view lies in (0, 180), as the scene's rules
  // (scene/scene_rules.h) make sure.
  Camera(const Vec3d& position, const Vec3d& look_at, const Vec3d& up, double vertical_fov_degrees,
         int width, int height);
  static Camera FromProto(const renderfarm::v1::Camera& camera, int width, int height);

  // The ray through film point `film` (pixels), with a unit direction.
  Ray GenerateRay(Vec2 film) const;

  // The angle one pixel subtends at the image's centre, radians: the spread of a camera
  // ray's cone (texture/footprint.h).
  float PixelSpreadAngle() const { return 2 * tan_half_fov_ / height_; }

  const Vec3& position() const { return position_; }
  const Vec3& forward() const { return forward_; }
  const Vec3& right() const { return right_; }
  const Vec3& up() const { return up_; }

  std::string ToString() const;

 private:
  Vec3 position_, forward_, right_, up_;
  float tan_half_fov_ = 0;  // vertical
  float aspect_ = 1;        // width / height
  float width_ = 1, height_ = 1;
};

}  // namespace farm
