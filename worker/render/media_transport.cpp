#include "render/media_transport.h"

#include <algorithm>
#include <cmath>
#include <variant>

#include "media/equiangular.h"
#include "media/henyey_greenstein.h"
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

// Where a light sample's distance along the ray is drawn from: the point of a point or a
// spot light, nothing for the others.
std::optional<Vec3> PointOf(const Light& light) {
  if (const auto* p = std::get_if<PointLight>(&light)) return p->position;
  if (const auto* s = std::get_if<SpotLight>(&light)) return s->position;
  return std::nullopt;
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

Rgb TransmittanceBetween(const SceneData& scene, const HomogeneousMedium* medium, const Vec3& a, const Vec3& b) {
  if (!medium) return Rgb(1);
  const float d = Distance(a, b);
  if (!(d > 0)) return Rgb(1);
  return SegmentIn(scene, medium, Ray{a, (b - a) / d}, d).TransmittanceTo(d);
}

Rgb InScatter(const MediumSegment& segment, const Ray& ray, const Light& light, float pick_pmf,
              const InScatterDimensions& u, const ShadowTransmittance& shadow) {
  if (segment.empty() || !(pick_pmf > 0)) return {};
  const HomogeneousMedium& m = *segment.medium;
  if (m.sigma_s.IsBlack()) return {};
  const float length = segment.t1 - segment.t0;
  std::optional<DistanceSample> d;
  if (const std::optional<Vec3> p = PointOf(light)) {
    d = SampleEquiangular(ray.origin, ray.direction, segment.t0, segment.t1, *p, u.distance);
  } else if (std::optional<DistanceSample> s = SampleTruncatedFlight(m, length, u.channel, u.distance)) {
    d = DistanceSample{segment.t0 + s->t, s->pdf};
  }
  if (!d) return {};
  const Vec3 x = ray.At(d->t);
  const std::optional<LightSample> ls = SampleLi(light, x, u.light);
  if (!ls || !(ls->pdf > 0)) return {};
  const Rgb arriving = shadow(x, *ls);
  if (arriving.IsBlack()) return {};
  const float phase = HenyeyGreenstein(-ray.direction, ls->wi, m.g);
  const float pdf = pick_pmf * d->pdf * ls->pdf;
  if (!(pdf > 0) || !std::isfinite(pdf)) return {};
  return segment.TransmittanceTo(d->t) * m.sigma_s * arriving * (phase / pdf);
}

}  // namespace farm
