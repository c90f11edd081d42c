#include "render/integrator.h"

#include <algorithm>
#include <cmath>

namespace farm {
namespace {

// Specular bounces a camera path may take before it is cut (a ray trapped between two
// mirrors); Russian roulette starts after kRouletteDepth of them.
constexpr int kMaxSpecularDepth = 16;
constexpr int kRouletteDepth = 4;

Rgb Finite(const Rgb& c) { return c.IsFinite() ? c : Rgb(); }

// What the radiance estimate weighs photons with: captured by a single reference so that
// std::function stores it without allocating.
struct BsdfAt {
  const Material& material;
  Vec3 n, wo;
};

}  // namespace

RadianceEstimateSettings ToRadianceEstimate(const EstimateSettings& s) {
  RadianceEstimateSettings r;
  r.neighbours = s.neighbours;
  r.max_radius = s.max_radius;
  r.cone_k = s.cone_k;
  switch (s.filter) {
    case EstimateFilter::kBox: r.filter = PhotonFilter::kBox; break;
    case EstimateFilter::kCone: r.filter = PhotonFilter::kCone; break;
    case EstimateFilter::kGaussian: r.filter = PhotonFilter::kGaussian; break;
  }
  return r;
}

SampleResult PhotonMappingIntegrator::Li(const Ray& camera_ray, PixelSampler& sampler,
                                         std::vector<PhotonNeighbour>& scratch) const {
  SampleResult result;
  Ray ray = camera_ray;
  Rgb throughput(1);
  for (int depth = 0; depth < kMaxSpecularDepth; ++depth) {
    // The same draws at every bounce, before any early exit, so that the dimensions a
    // bounce uses do not depend on what earlier bounces hit.
    const float u_light = sampler.Get1D();
    const Vec2 u_point = sampler.Get2D();
    const float u_lobe = sampler.Get1D();
    const Vec2 u_direction = sampler.Get2D();
    const float u_survive = sampler.Get1D();

    const std::optional<SurfaceHit> hit = scene_.Intersect(ray);
    if (!hit) break;  // black background
    const Vec3 wo = -ray.direction;
    const Material& material = scene_.material_of(*hit);
    if (depth == 0) {
      result.alpha = 1;
      result.albedo = Albedo(material);
      result.normal = FaceForward(hit->n, wo);
      result.depth = hit->t;
    }
    result.emitted += throughput * Emitted(material, hit->n, wo);

    if (!IsSpecular(material)) {
      if (Reflects(material)) {
        result.direct = throughput * SampleDirect(*hit, wo, material, u_light, u_point);
        const Vec3 n = FaceForward(hit->n, wo);
        const BsdfAt at{material, hit->n, wo};
        const auto bsdf = [&at](const Vec3& wi) { return EvaluateBsdf(at.material, at.n, at.wo, wi); };
        if (maps_.caustic)
          result.caustic = throughput * EstimateRadiance(*maps_.caustic, hit->p, n,
                                                         maps_.caustic_estimate, bsdf, scratch);
        if (maps_.global)
          result.indirect = throughput * EstimateRadiance(*maps_.global, hit->p, n,
                                                          maps_.global_estimate, bsdf, scratch);
      }
      break;
    }

    const std::optional<BsdfSample> s =
        SampleBsdf(material, hit->n, wo, u_lobe, u_direction, TransportMode::kRadiance);
    if (!s) break;
    throughput = throughput * s->weight;
    if (depth >= kRouletteDepth) {
      const float survive = std::min(1.0f, std::max({throughput.r, throughput.g, throughput.b}));
      if (!(survive > 0) || u_survive >= survive) break;
      throughput = throughput / survive;
    }
    if (!throughput.IsFinite() || throughput.IsBlack()) break;
    ray = Ray{OffsetRayOrigin(hit->p, hit->n, s->wi, scene_.ray_epsilon), s->wi};
  }
  // Never let NaN or infinity through: a bad term is dropped, not the whole sample.
  result.emitted = Finite(result.emitted);
  result.direct = Finite(result.direct);
  result.caustic = Finite(result.caustic);
  result.indirect = Finite(result.indirect);
  result.albedo = Finite(result.albedo);
  if (!std::isfinite(result.depth)) result.depth = 0;
  result.radiance = result.emitted + result.direct + result.indirect + result.caustic;
  return result;
}

Rgb PhotonMappingIntegrator::SampleDirect(const SurfaceHit& hit, const Vec3& wo,
                                          const Material& material, float u_light,
                                          Vec2 u_point) const {
  if (scene_.light_power.empty()) return {};
  const auto pick = scene_.light_power.Sample(u_light);
  if (!(pick.pmf > 0)) return {};
  const std::optional<LightSample> ls = SampleLi(scene_.lights[pick.index], hit.p, u_point);
  if (!ls) return {};
  const Rgb f = EvaluateBsdf(material, hit.n, wo, ls->wi);
  if (f.IsBlack()) return {};
  const float cos_theta = AbsDot(hit.n, ls->wi);
  const float pdf = pick.pmf * ls->pdf;
  if (!(pdf > 0) || !std::isfinite(pdf)) return {};
  if (!scene_.Visible(hit.p, hit.n, ls->p, ls->n)) return {};
  return f * ls->radiance * (cos_theta / pdf);
}

std::string PhotonMappingIntegrator::ToString() const {
  return std::string("PhotonMappingIntegrator{global=") + (maps_.global ? "yes" : "no") +
         ", caustic=" + (maps_.caustic ? "yes" : "no") + "}";
}

}  // namespace farm
