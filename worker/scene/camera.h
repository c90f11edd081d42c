#pragma once

// A perspective camera, a pinhole or a thin lens. Film coordinates are in pixels: (0, 0) is
// the top-left corner of the image, (width, height) the bottom-right; pixel (x, y) covers
// [x, x+1) x [y, y+1). The image's right is cross(forward, up) (so the Cornell box camera
// at z = -800 looking +z with up +y sees x = 556 on the left), its up the component of
// `up` orthogonal to forward.
//
// A thin lens of radius A focused at distance F (along forward): the ray through film
// point f starts at a point of the lens disc (radius A about the position, in the
// right-up plane) and passes through where the pinhole ray through f meets the plane at
// distance F. A point at depth z is then imaged as a disc of radius A |1/z - 1/F| on the
// image plane at unit distance (that many times height / (2 tan(fov / 2)) pixels), the
// circle of confusion of the thin-lens formula; at z = F it is sharp.

#include <array>
#include <string>

#include "math/ray.h"
#include "math/vec3.h"

namespace renderfarm::v1 {
class Camera;
}

namespace farm {

struct ThinLens {
  double aperture_radius = 0;  // 0: a pinhole
  double focus_distance = 0;   // 0: the distance to look_at
};

// A 4x4 matrix in OpenEXR's convention: row-major, applied to row vectors (p' = p M).
using Matrix44 = std::array<double, 16>;

class Camera {
 public:
  Camera() = default;
  // The view must not be degenerate: look_at differs from position, up is not parallel to
  // the view direction and the field of view lies in (0, 180), as the scene's rules
  // (scene/scene_rules.h) make sure.
  Camera(const Vec3d& position, const Vec3d& look_at, const Vec3d& up, double vertical_fov_degrees,
         int width, int height, const ThinLens& lens = {});
  static Camera FromProto(const renderfarm::v1::Camera& camera, int width, int height);

  // The ray through film point `film` (pixels), with a unit direction; `lens` in [0, 1)^2
  // picks the point of the lens it starts from (ignored by a pinhole).
  Ray GenerateRay(Vec2 film, Vec2 lens = {}) const;
  // Whether GenerateRay reads `lens`.
  bool has_lens() const { return aperture_radius_ > 0; }

  // The angle one pixel subtends at the image's centre, radians: the spread of a camera
  // ray's cone (texture/footprint.h).
  float PixelSpreadAngle() const { return 2 * tan_half_fov_ / height_; }

  const Vec3& position() const { return position_; }
  const Vec3& forward() const { return forward_; }
  const Vec3& right() const { return right_; }
  const Vec3& up() const { return up_; }
  float focus_distance() const { return focus_distance_; }

  // OpenEXR's worldToCamera: to the left-handed camera space x right, y up, z forward
  // (the viewing direction), the origin at the camera's position.
  Matrix44 WorldToCamera() const;
  // OpenEXR's worldToNDC: p M, divided by its fourth component, has x and y in [0, 1] over
  // the image, (0, 0) its top-left corner and (1, 1) its bottom-right; z comes out as
  // 1 / depth.
  Matrix44 WorldToNdc() const;

  std::string ToString() const;

 private:
  Vec3 position_, forward_, right_, up_;
  float tan_half_fov_ = 0;  // vertical
  float aspect_ = 1;        // width / height
  float width_ = 1, height_ = 1;
  float aperture_radius_ = 0, focus_distance_ = 1;
};

}  // namespace farm
