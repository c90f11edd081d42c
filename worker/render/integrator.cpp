#include "render/integrator.h"

#include <cmath>

namespace farm {

SampleResult DirectLightingIntegrator::Li(const Ray& camera_ray, PixelSampler& sampler) const {
  SampleResult result;
  const std::optional<SurfaceHit> hit = scene_.Intersect(camera_ray);
  if (!hit) return result;  // black background, alpha 0
  result.alpha = 1;
  const Vec3 wo = -camera_ray.direction;
  const Material& material = scene_.material_of(*hit);
  result.radiance = Emitted(material, hit->n, wo);
  if (Reflects(material)) result.radiance += SampleDirect(*hit, wo, material, sampler);
  if (!result.radiance.IsFinite()) result.radiance = Rgb();  // never let NaN/Inf through
  return result;
}

Rgb DirectLightingIntegrator::SampleDirect(const SurfaceHit& hit, const Vec3& wo,
                                           const Material& material, PixelSampler& sampler) const {
  // Draw the numbers before any early exit so that the dimensions a sample uses do not
  // depend on what it hits (keeps later dimensions aligned across pixels).
  const float u_light = sampler.Get1D();
  const Vec2 u_point = sampler.Get2D();
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

}  // namespace farm
