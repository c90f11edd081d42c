#include "render/media_transport.h"

#include <algorithm>
#include <cmath>
#include <variant>

#include "math/math.h"
#include "media/equiangular.h"
#include "media/henyey_greenstein.h"
#include "scene/scene_data.h"
#include "util/overloaded.h"

namespace farm {
namespace {

// The point a light sample's distance along the ray is drawn towards (equiangularly): a
// point or spot light's position, or the point of a quad or mesh light that SampleLi
// picks with the same numbers (by area, whatever the shading point: lights.h). Drawing
// the distance towards it cancels the 1 / d^2 of the light's geometry term, which under
// free-flight sampling makes the points of a ray that passes close to an emitter blow up
// (no receiver cosine tames it in a medium). Nothing for spheres, sampled by the cone they
// subtend (bounded), and distant lights: their distance follows the free flight.
std::optional<Vec3> PointOf(const Light& light, Vec2 u) {
  if (const auto* p = std::get_if<PointLight>(&light)) return p->position;
  if (const auto* s = std::get_if<SpotLight>(&light)) return s->position;
  if (std::holds_alternative<QuadLight>(light) || std::holds_alternative<TriangleMeshLight>(light)) {
    const std::optional<LightOrigin> origin = SampleLightOrigin(light, u);
    if (origin) return origin->p;
  }
  return std::nullopt;
}

// The density with which InScatter draws the distance t for `light` whose sample lies at
// `at` (PointOf's choice: equiangular towards a quad's or mesh's point, else the segment's
// truncated free flight, a grid's by its exact optical depth).
float LightDistancePdf(const MediumSegment& segment, const Ray& ray, const Light& light, const Vec3& at, float t) {
  if (std::holds_alternative<QuadLight>(light) || std::holds_alternative<TriangleMeshLight>(light))
    return EquiangularPdf(ray.origin, ray.direction, segment.t0, segment.t1, at, t);
  return segment.DistancePdf(t);
}

// The weight of one strategy's sample: the power heuristic, or 1 alone.
float WeightOf(Weighting weighting, float mine, float other) {
  return weighting == Weighting::kAlone ? 1.0f : PowerHeuristic(mine, other);
}

}  // namespace

float PowerHeuristic(float mine, float other) {
  if (!(mine > 0)) return 0;
  // As a ratio, in double: densities of narrow lobes and tiny lights square past float.
  const double r = double(other) / double(mine);
  const double w = 1 / (1 + r * r);
  return std::isfinite(w) ? float(w) : 0.0f;
}

Rgb InScatter(const MediumSegment& segment, const Ray& ray, const Light& light, float pick_pmf,
              const InScatterDimensions& u, const ShadowTransmittance& shadow, Weighting weighting) {
  if (segment.empty() || !(pick_pmf > 0)) return {};
  if (!segment.medium->Scatters()) return {};
  std::optional<DistanceSample> d;
  if (const std::optional<Vec3> p = PointOf(light, u.light)) {
    d = SampleEquiangular(ray.origin, ray.direction, segment.t0, segment.t1, *p, u.distance);
  } else {
    d = segment.SampleDistance(u.channel, u.distance);
  }
  if (!d) return {};
  // Nothing scatters where a grid is empty (an equiangular distance may land there): no
  // shadow ray.
  const Rgb sigma_s = segment.ScatteringAt(d->t);
  if (sigma_s.IsBlack()) return {};
  const Vec3 x = ray.At(d->t);
  const std::optional<LightSample> ls = SampleLi(light, x, u.light);
  if (!ls || !(ls->pdf > 0)) return {};
  const Rgb arriving = shadow(x, *ls);
  if (arriving.IsBlack()) return {};
  const float phase = HenyeyGreenstein(-ray.direction, ls->wi, segment.medium->g());
  const float pdf = pick_pmf * d->pdf * ls->pdf;
  if (!(pdf > 0) || !std::isfinite(pdf)) return {};
  // The phase strategy cannot draw a delta light's one direction.
  const float weight = ls->delta ? 1.0f : WeightOf(weighting, pdf, segment.DistancePdf(d->t) * phase);
  return segment.TransmittanceTo(d->t) * sigma_s * arriving * (phase * weight / pdf);
}

void LightsAlong(const SceneData& scene, const Ray& ray, const std::optional<SurfaceHit>& hit,
                 const std::function<void(int light, const LightSample& sample)>& fn) {
  if (hit) {
    const int light = scene.AreaLightOf(*hit);
    if (light < 0) return;
    if (const std::optional<LightSample> ls = LightSampleAlong(scene.lights[light], ray.origin, ray.direction,
                                                               hit->p, hit->n))
      fn(light, *ls);
    return;
  }
  // Escaped: every light from infinitely far away (the sun's disc, the environment), which
  // come after the area lights.
  for (std::size_t i = scene.area_light_surfaces.size(); i < scene.lights.size(); ++i) {
    const std::optional<LightSample> ls = LightSampleAlong(scene.lights[i], ray.origin, ray.direction, Vec3(), Vec3());
    if (ls) fn(int(i), *ls);
  }
}

std::optional<ScatteredRay> PhaseInScatter(const SceneData& scene, const MediumSegment& segment, const Ray& ray,
                                           float u_channel, float u_distance, Vec2 u_direction, Weighting weighting) {
  if (segment.empty() || !segment.medium->Scatters()) return std::nullopt;
  const std::optional<DistanceSample> d = segment.SampleDistance(u_channel, u_distance);
  if (!d || !(d->pdf > 0)) return std::nullopt;
  const float t = d->t;
  const Vec3 x = ray.At(t);
  const PhaseSample phase = SampleHenyeyGreenstein(-ray.direction, segment.medium->g(), u_direction);
  ScatteredRay out;
  out.ray = Ray{x, phase.wi};
  out.hit = scene.Intersect(out.ray);
  out.weight = segment.TransmittanceTo(t) * segment.ScatteringAt(t) / d->pdf;
  // The phase function over its density is 1; the light strategy's density for the same
  // (t, wi) is the light's pick times its distance's density times SampleLi's.
  LightsAlong(scene, out.ray, out.hit, [&](int light, const LightSample& ls) {
    const float light_pdf = scene.light_power.Pmf(light) *
                            LightDistancePdf(segment, ray, scene.lights[light], ls.p, t) * ls.pdf;
    const float weight = WeightOf(weighting, d->pdf * phase.pdf, light_pdf);
    out.single += ls.radiance * TransmittanceBetween(scene, segment.medium, x, ls.p) * weight;
  });
  out.single = out.weight * out.single;
  return out;
}

ScatteredRay ScatterAt(const SceneData& scene, const Medium* medium, const Vec3& x, const Vec3& wo,
                       float u_pick, Vec2 u_light, Vec2 u_direction, const ShadowTransmittance& shadow) {
  ScatteredRay out;
  out.weight = Rgb(1);
  if (!scene.light_power.empty()) {
    const auto pick = scene.light_power.Sample(u_pick);
    const std::optional<LightSample> ls = pick.pmf > 0 ? SampleLi(scene.lights[pick.index], x, u_light) : std::nullopt;
    if (ls && ls->pdf > 0) {
      const float light_pdf = pick.pmf * ls->pdf;
      const float phase = HenyeyGreenstein(wo, ls->wi, medium->g());
      const float weight = ls->delta ? 1.0f : PowerHeuristic(light_pdf, phase);
      if (weight > 0 && std::isfinite(light_pdf)) {
        const Rgb arriving = shadow(x, *ls);
        if (!arriving.IsBlack()) out.single += arriving * (phase * weight / light_pdf);
      }
    }
  }
  const PhaseSample phase = SampleHenyeyGreenstein(wo, medium->g(), u_direction);
  out.ray = Ray{x, phase.wi};
  out.hit = scene.Intersect(out.ray);
  LightsAlong(scene, out.ray, out.hit, [&](int light, const LightSample& ls) {
    const float weight = PowerHeuristic(phase.pdf, scene.light_power.Pmf(light) * ls.pdf);
    out.single += ls.radiance * TransmittanceBetween(scene, medium, x, ls.p) * weight;
  });
  return out;
}

SeenBall SeenBall::Probe(const SceneData& scene, const Vec3& x, float r, Vec2 u) {
  SeenBall ball;
  double sum = 0;
  const float golden = kPi * (3 - std::sqrt(5.0f));
  for (int i = 0; i < kVolumeProbes; ++i) {
    const float z = 1 - 2 * (float(i) + u.y) / float(kVolumeProbes);
    const float s = std::sqrt(std::max(0.0f, 1 - z * z));
    const float phi = golden * float(i) + 2 * kPi * u.x;
    ball.directions[i] = Vec3(s * std::cos(phi), s * std::sin(phi), z);
    const std::optional<SurfaceHit> hit = scene.Intersect(Ray{x, ball.directions[i]});
    ball.depths[i] = hit ? std::min(hit->t, r) : r;
    const double seen = ball.depths[i] / r;
    sum += seen * seen * seen;
  }
  ball.fraction = float(sum / kVolumeProbes);
  return ball;
}

bool SeenBall::Sees(const SceneData& scene, const Vec3& x, const Vec3& offset) const {
  return fraction >= 1 || scene.SegmentClear(x, x + offset);
}

double SeenBall::Integral(const Vec3& x, const std::function<float(const Vec3&)>& f) const {
  // Gauss-Legendre on [0, d]: nodes d (1 -+ 1/sqrt(3)) / 2, weights d / 2.
  constexpr float kNode = 0.21132487f;  // (1 - 1/sqrt(3)) / 2
  double sum = 0;
  for (int i = 0; i < kVolumeProbes; ++i) {
    const float d = depths[i];
    for (const float s : {d * kNode, d * (1 - kNode)}) sum += double(f(x + directions[i] * s)) * s * s * d / 2;
  }
  return sum * 4 * kPi / kVolumeProbes;
}

Rgb VolumeInScatter(const SceneData& scene, const MediumSegment& segment, const Ray& ray, const PhotonMap& volume,
                    const RadianceEstimateSettings& estimate, float u_channel, float u_distance, Vec2 u_probe,
                    std::vector<PhotonNeighbour>& scratch) {
  if (segment.empty() || volume.size() == 0) return {};
  if (!segment.medium->Scatters()) return {};
  const std::optional<DistanceSample> d = segment.SampleDistance(u_channel, u_distance);
  if (!d || !(d->pdf > 0)) return {};
  const float t = d->t;
  const Vec3 x = ray.At(t);
  volume.NearestK(x, estimate.neighbours, estimate.max_radius, scratch);
  if (scratch.empty()) return {};
  float r2 = estimate.max_radius * estimate.max_radius;
  std::size_t farthest = scratch.size();  // none left out
  if (scratch.size() >= std::size_t(std::max(estimate.neighbours, 2))) {
    farthest = 0;
    for (std::size_t i = 1; i < scratch.size(); ++i)
      if (scratch[i].distance_squared > scratch[farthest].distance_squared) farthest = i;
    r2 = scratch[farthest].distance_squared;
  }
  if (!(r2 > 0)) return {};
  const float r = std::sqrt(r2);
  const SeenBall seen = SeenBall::Probe(scene, x, r, u_probe);
  Rgb sum;
  for (std::size_t i = 0; i < scratch.size(); ++i) {
    if (i == farthest) continue;
    const DecodedPhoton p = volume.photon(scratch[i].index);
    if (!seen.Sees(scene, x, p.position - x)) continue;
    sum += p.power * HenyeyGreenstein(-ray.direction, p.wi, segment.medium->g());
  }
  return std::visit(Overloaded{[&](const HomogeneousMedium&) -> Rgb {
                                 const float volume_of_sphere = 4.0f / 3.0f * kPi * r2 * r * seen.fraction;
                                 if (!(volume_of_sphere > 0)) return {};
                                 return segment.TransmittanceTo(t) * sum / (volume_of_sphere * d->pdf);
                               },
                               [&](const GridMedium& grid) -> Rgb {
                                 const double extinction = seen.Integral(x, [&](const Vec3& p) { return grid.SigmaT(p); });
                                 if (!(extinction > 0)) return {};
                                 return segment.TransmittanceTo(t) * sum *
                                        float(grid.SigmaT(x) / (extinction * d->pdf));
                               }},
                    segment.medium->kind);
}

}  // namespace farm
