#pragma once

// The environment: the radiance of rays that leave the scene, arriving from infinitely far
// away. Either a constant colour, or an equirectangular (latitude-longitude) linear RGB
// image times a colour.
//
// Map coordinates (Scene.environment.map in scene.proto): +Y is up (the image's top row),
// the middle column looks along -Z, and longitude grows towards +X, so u = 0.75 looks
// along +X; rotation_degrees turns the map about +Y (counter-clockwise seen from above, the
// right-hand rule). With theta the angle from +Y and phi = atan2(x, -z),
// u = 1/2 + phi / (2 pi), v = theta / pi. Lookups are bilinear, wrapping in u and clamped
// in v.
//
// Importance sampling: a constant environment is sampled uniformly over the sphere. A map
// is sampled by a piecewise-constant density over (u, v) whose cells weigh the mean of
// the bilinear lookup's luminance over the cell (the texel's with its neighbours', 3/4 and
// 1/8 along each axis, so that every direction the lookup lights can be drawn) times
// sin(theta) at the cell's centre (the solid angle a row of the map covers); maps wider
// than kMaxDistributionWidth texels are sampled on cells of k x k texels. The density over
// solid angle is the (u, v) density / (2 pi^2 sin(theta)).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "math/rgb.h"
#include "math/vec3.h"
#include "sampling/distribution_2d.h"

namespace farm {

// A linear RGB image, row 0 at the top.
struct EnvironmentImage {
  int width = 0, height = 0;
  std::vector<Rgb> texels;  // row-major, width * height

  const Rgb& at(int x, int y) const { return texels[std::size_t(y) * width + x]; }
};

class Environment {
 public:
  // The widest grid the sampling density is built on (memory: 12 bytes a cell).
  static constexpr int kMaxDistributionWidth = 2048;

  static Environment Constant(const Rgb& radiance);
  // image must not be empty; scale multiplies every texel.
  static Environment Map(EnvironmentImage image, const Rgb& scale, double rotation_degrees);

  // Radiance arriving along -w, i.e. seen looking along w (unit).
  Rgb Radiance(const Vec3& w) const;

  struct Sample {
    Vec3 w;  // unit, from the scene towards the environment
    Rgb radiance;
    float pdf = 0;  // per unit solid angle
  };
  // Nothing for a degenerate sample (a pole of the map).
  std::optional<Sample> SampleDirection(Vec2 u) const;
  // The density SampleDirection gives w.
  float Pdf(const Vec3& w) const;

  // The integral of the radiance over all directions (W / m^2 through a surface facing
  // every way at once): times the area of a disc, the power that crosses it.
  Rgb SphereIntegral() const;
  bool IsBlack() const { return SphereIntegral().IsBlack(); }

  std::string ToString() const;

 private:
  Rgb Lookup(Vec2 uv) const;  // bilinear, times scale_
  Vec3 ToMap(const Vec3& w) const;
  Vec3 FromMap(const Vec3& m) const;

  Rgb scale_;
  std::shared_ptr<const EnvironmentImage> image_;  // null: constant
  float cos_rotation_ = 1, sin_rotation_ = 0;
  Distribution2D distribution_;
  int cell_ = 1;  // texels per distribution cell along each axis
  Rgb integral_;
};

}  // namespace farm
