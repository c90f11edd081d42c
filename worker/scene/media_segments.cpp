#include "scene/media_segments.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "scene/scene_data.h"

namespace farm {
namespace {

// The interval of the ray's line inside a ball, or nothing if it misses.
std::optional<std::pair<float, float>> BallInterval(const BoundingSphere& ball, const Ray& ray) {
  const Vec3 to_center = ball.center - ray.origin;
  const float b = Dot(to_center, ray.direction);
  const float disc = b * b - (LengthSquared(to_center) - ball.radius * ball.radius);
  if (!(disc >= 0)) return std::nullopt;
  const float root = std::sqrt(disc);
  return std::pair{b - root, b + root};
}

}  // namespace

Rgb MediumSegment::TransmittanceTo(float t) const {
  if (!medium || !(t > t0)) return Rgb(1);
  return medium->Transmittance(std::min(t, t1) - t0);
}

MediumSegment SegmentIn(const SceneData& scene, const HomogeneousMedium* medium, const Ray& ray, float t_end) {
  if (!medium) return {};
  if (!scene.medium || medium != &*scene.medium) return {medium, 0, t_end};
  const std::optional<std::pair<float, float>> inside = BallInterval(scene.medium_ball, ray);
  if (!inside) return {};
  return {medium, std::max(0.0f, inside->first), std::min(t_end, inside->second)};
}

const HomogeneousMedium* MediumBeyond(const SceneData& scene, const SurfaceHit& hit, const Vec3& wo, const Vec3& wi,
                                      const HomogeneousMedium* current) {
  const std::optional<HomogeneousMedium>& interior = scene.shapes[hit.shape].interior_medium;
  if (!interior) return current;
  const bool from_front = Dot(wo, hit.n) > 0, to_front = Dot(wi, hit.n) > 0;
  if (from_front == to_front) return current;  // reflected: still on the same side
  if (from_front) return &*interior;
  return scene.medium ? &*scene.medium : nullptr;
}

Rgb TransmittanceBetween(const SceneData& scene, const HomogeneousMedium* medium, const Vec3& a, const Vec3& b) {
  if (!medium) return Rgb(1);
  const float d = Distance(a, b);
  if (!(d > 0)) return Rgb(1);
  return SegmentIn(scene, medium, Ray{a, (b - a) / d}, d).TransmittanceTo(d);
}

}  // namespace farm
