#include "scene/media_segments.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>
#include <utility>
#include <variant>

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

// [t0, t1] narrowed to the grid's box (in the grid's space, where t is the same): outside
// it the medium is vacuum, and distances drawn there would be wasted.
void ClipToGrid(const GridMedium& grid, MediumSegment& s) {
  const std::optional<std::pair<float, float>> inside = ClipToBox(grid.grid->box(), grid.ToGrid(s.ray), s.t0, s.t1);
  if (!inside) {
    s.t1 = s.t0;
    return;
  }
  std::tie(s.t0, s.t1) = *inside;
}

}  // namespace

Rgb MediumSegment::TransmittanceTo(float t) const {
  if (!medium || !(t > t0)) return Rgb(1);
  return Transmittance(*medium, ray, t0, std::min(t, t1));
}

Rgb MediumSegment::ScatteringAt(float t) const { return farm::ScatteringAt(*medium, ray.At(t)); }

std::optional<DistanceSample> MediumSegment::SampleDistance(float u_channel, float u) const {
  if (empty()) return std::nullopt;
  return farm::SampleDistance(*medium, ray, t0, t1, u_channel, u);
}

float MediumSegment::DistancePdf(float t) const {
  if (empty()) return 0;
  return farm::DistancePdf(*medium, ray, t0, t1, t);
}

FreeFlight MediumSegment::SampleFlight(float u_channel, float u) const {
  return farm::SampleFlight(*medium, ray, t0, t1, u_channel, u);
}

MediumSegment SegmentIn(const SceneData& scene, const Medium* medium, const Ray& ray, float t_end) {
  if (!medium) return {};
  MediumSegment s{medium, ray, 0, t_end};
  if (scene.medium && medium == &*scene.medium) {
    const std::optional<std::pair<float, float>> inside = BallInterval(scene.medium_ball, ray);
    if (!inside) return {};
    s.t0 = std::max(0.0f, inside->first);
    s.t1 = std::min(t_end, inside->second);
  }
  if (const auto* grid = std::get_if<GridMedium>(&medium->kind)) ClipToGrid(*grid, s);
  return s;
}

const Medium* MediumBeyond(const SceneData& scene, const SurfaceHit& hit, const Vec3& wo, const Vec3& wi,
                           const Medium* current) {
  const std::optional<Medium>& interior = scene.shapes[hit.shape].interior_medium;
  if (!interior) return current;
  const bool from_front = Dot(wo, hit.n) > 0, to_front = Dot(wi, hit.n) > 0;
  if (from_front == to_front) return current;  // reflected: still on the same side
  if (from_front) return &*interior;
  return scene.medium ? &*scene.medium : nullptr;
}

Rgb TransmittanceBetween(const SceneData& scene, const Medium* medium, const Vec3& a, const Vec3& b) {
  if (!medium) return Rgb(1);
  const float d = Distance(a, b);
  if (!(d > 0)) return Rgb(1);
  return SegmentIn(scene, medium, Ray{a, (b - a) / d}, d).TransmittanceTo(d);
}

}  // namespace farm
