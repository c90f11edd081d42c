#include "render/integrator.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "math/frame.h"
#include "math/math.h"
#include "photonmap/irradiance_lookup.h"
#include "sampling/hash.h"
#include "sampling/sobol.h"
#include "sampling/warps.h"
#include "scene/surface_shading.h"
#include "texture/footprint.h"

namespace farm {

// A non-specular surface point being shaded: n faces the side wo comes from.
// material is as it is at the hit (MaterialAt); cone_width is the width the ray's cone has
// reached there, where the rays leaving it start their own.
struct PhotonMappingIntegrator::Shading {
  const SurfaceHit& hit;
  Vec3 wo;
  Material material;
  Vec3 n;
  float cone_width = 0;
};

namespace {

// Specular bounces a camera path may take before it is cut (a ray trapped between two
// mirrors); Russian roulette starts after kRouletteDepth of them.
constexpr int kMaxSpecularDepth = 16;
constexpr int kRouletteDepth = 4;

// Streams of stratified points hashed from one per-shading-point seed: each gets its own
// scramble and index shuffle, so streams are decorrelated while each stays a (0,2)-net.
enum Stream : uint32_t {
  kLightPick = 1,
  kLightPoint,
  kGatherDirection,
  kGatherLightPick,
  kGatherLightPoint,
  kGatherSpecular,
  kDirectSeed,
  kGatherSeed,
  kSecondarySeed,
};

Rgb Finite(const Rgb& c) { return c.IsFinite() ? c : Rgb(); }

uint32_t SubSeed(uint32_t seed, uint32_t stream) { return uint32_t(Hash(seed, stream)); }

// Point i of n of a stream: shuffled index, Owen-scrambled Sobol.
float Point1(uint32_t i, uint32_t n, uint32_t seed, uint32_t stream) {
  const uint64_t h = Hash(seed, stream);
  return SobolSample(PermutationElement(i, n, uint32_t(h >> 32)), 0, uint32_t(h));
}

Vec2 Point2(uint32_t i, uint32_t n, uint32_t seed, uint32_t stream) {
  const uint64_t h = Hash(seed, stream);
  const uint64_t s = MixBits(h);
  const uint32_t index = PermutationElement(i, n, uint32_t(h >> 32));
  return {SobolSample(index, 0, uint32_t(s)), SobolSample(index, 1, uint32_t(s >> 32))};
}

// The spread of a gather ray's cone: the side of the solid angle each of `count` rays
// stands for (2 pi / count of the hemisphere).
float GatherSpread(uint32_t count) { return std::sqrt(2 * kPi / float(std::max(count, 1u))); }

// A uniform float from 24 bits of a hash (for the rare choices of specular bounces).
float HashFloat(uint64_t h) { return float(h >> 40) * 0x1p-24f; }

// Follows at most kGatherSpecularDepth specular bounces to the first non-specular surface
// that reflects; nothing if the ray escapes, ends on an emitter or is absorbed. key seeds
// the Fresnel choices; the ray's cone (footprint.h) reads the textures on the way.
struct DiffuseHit {
  SurfaceHit hit;
  Rgb throughput;
  Vec3 wo;
  Material material;  // at the hit
  float cone_width = 0;
};
std::optional<DiffuseHit> TraceToDiffuse(const SceneData& scene, Ray ray, RayCone cone, uint64_t key) {
  Rgb throughput(1);
  for (int depth = 0; depth <= kGatherSpecularDepth; ++depth) {
    const std::optional<SurfaceHit> hit = scene.Intersect(ray);
    if (!hit) return std::nullopt;
    cone.width = cone.WidthAt(hit->t);
    const Material material = MaterialAt(scene, *hit, ray.direction, cone.width);
    const MaterialCapabilities& can = scene.capabilities_of(*hit);
    const Vec3 wo = -ray.direction;
    // A smooth principled surface (specular and diffuse) ends the chain too: where a gather
    // ray lands, its albedo, specular lobe included, reflects the irradiance as if diffuse.
    if (can.reflects) return DiffuseHit{*hit, throughput, wo, material, cone.width};
    if (!can.specular) return std::nullopt;
    const uint64_t h = Hash(key, uint64_t(depth));
    const uint64_t h2 = MixBits(h);
    const std::optional<BsdfSample> s = SampleBsdf(material, hit->n, wo, HashFloat(h),
                                                   {HashFloat(h2), HashFloat(h2 << 24)},
                                                   TransportMode::kRadiance);
    if (!s) return std::nullopt;
    throughput = throughput * s->weight;
    if (!throughput.IsFinite() || throughput.IsBlack()) return std::nullopt;
    ray = Ray{OffsetRayOrigin(hit->p, hit->n, s->wi, scene.ray_epsilon), s->wi};
  }
  return std::nullopt;
}

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

PhotonMappingIntegrator::PhotonMappingIntegrator(const SceneData& scene, const PhotonMaps& maps,
                                                 double radius_scale)
    : scene_(scene), maps_(maps) {
  const float scale = std::isfinite(radius_scale) && radius_scale > 0 ? float(radius_scale) : 1.0f;
  maps_.global_estimate.max_radius *= scale;
  maps_.caustic_estimate.max_radius *= scale;
  lookup_radius_ = maps_.global_estimate.max_radius;
  // Without precomputed irradiance (a job planned before the precompute phase existed, or
  // a map too small to need one) the global map is seen directly rather than not at all.
  final_gather_ = scene.indirect.mode == IndirectMode::kFinalGather && maps_.global &&
                  maps_.global->has_irradiance();
  // A lone point or sun light gives every shadow ray the same answer: one is enough.
  single_delta_light_ = scene.lights.size() == 1 && IsDeltaLight(scene.lights.front());
}

SampleResult PhotonMappingIntegrator::Li(const Ray& camera_ray, PixelSampler& sampler,
                                         std::vector<PhotonNeighbour>& scratch) const {
  SampleResult result;
  Ray ray = camera_ray;
  Rgb throughput(1);
  // The pixel's cone, passed on unchanged by specular bounces (footprint.h).
  RayCone cone{0, scene_.camera.PixelSpreadAngle()};
  for (int depth = 0; depth < kMaxSpecularDepth; ++depth) {
    // The same draws at every bounce, before any early exit, so that the dimensions a
    // bounce uses do not depend on what earlier bounces hit.
    const float u_seed = sampler.Get1D();
    const float u_lobe = sampler.Get1D();
    const Vec2 u_direction = sampler.Get2D();
    const float u_survive = sampler.Get1D();
    const Vec2 u_glossy = sampler.Get2D();

    const std::optional<SurfaceHit> hit = scene_.Intersect(ray);
    if (!hit) break;  // black background
    const Vec3 wo = -ray.direction;
    cone.width = cone.WidthAt(hit->t);
    const Material material = MaterialAt(scene_, *hit, ray.direction, cone.width);
    if (depth == 0) {
      result.alpha = 1;
      result.albedo = Albedo(material);
      result.normal = FaceForward(hit->n, wo);
      result.depth = hit->t;
    }
    result.emitted += throughput * Emitted(material, hit->n, wo);

    const MaterialCapabilities& can = scene_.capabilities_of(*hit);
    if (can.reflects) {
      // 2^32 levels from the sample's dimension, hashed so that nearby values give
      // unrelated scrambles.
      const uint32_t seed = uint32_t(Hash(uint64_t(double(u_seed) * 4294967296.0)));
      const Shading at{*hit, wo, material, FaceForward(hit->n, wo), cone.width};
      Rgb direct, caustic, indirect;
      Shade(at, final_gather_ ? scene_.indirect.gather_rays : 0, seed, scratch, direct, caustic,
            indirect);
      if (final_gather_) indirect += GlossyBounce(at, u_glossy, SubSeed(seed, kSecondarySeed), scratch);
      // Added, not set: a smooth principled surface is shaded for its diffuse base here and
      // followed through its specular lobe below, and what lies beyond adds its own.
      result.direct += throughput * direct;
      result.caustic += throughput * caustic;
      result.indirect += throughput * indirect;
    }
    if (!can.specular) break;

    const std::optional<BsdfSample> s =
        SampleSpecular(material, hit->n, wo, u_lobe, u_direction, TransportMode::kRadiance);
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

void PhotonMappingIntegrator::Shade(const Shading& at, uint32_t gather_rays, uint32_t seed,
                                    std::vector<PhotonNeighbour>& scratch, Rgb& direct,
                                    Rgb& caustic, Rgb& indirect) const {
  direct = DirectLight(at, scene_.indirect.light_samples, SubSeed(seed, kDirectSeed));
  const auto bsdf = [&at](const Vec3& wi) { return EvaluateBsdf(at.material, at.hit.n, at.wo, wi); };
  caustic = maps_.caustic ? EstimateRadiance(*maps_.caustic, at.hit.p, at.n, maps_.caustic_estimate,
                                             bsdf, scratch)
                          : Rgb();
  if (gather_rays > 0)
    indirect = Gather(at, gather_rays, SubSeed(seed, kGatherSeed), scratch);
  else if (maps_.global)
    indirect = EstimateRadiance(*maps_.global, at.hit.p, at.n, maps_.global_estimate, bsdf, scratch);
  else
    indirect = {};
}

Rgb PhotonMappingIntegrator::DirectLight(const Shading& at, uint32_t count, uint32_t seed) const {
  if (scene_.light_power.empty() || count == 0) return {};
  if (single_delta_light_) count = 1;
  Rgb sum;
  for (uint32_t j = 0; j < count; ++j) {
    const auto pick = scene_.light_power.Sample(Point1(j, count, seed, kLightPick));
    if (!(pick.pmf > 0)) continue;
    const std::optional<LightSample> ls =
        SampleLi(scene_.lights[pick.index], at.hit.p, Point2(j, count, seed, kLightPoint));
    if (!ls) continue;
    const Rgb f = EvaluateBsdf(at.material, at.hit.n, at.wo, ls->wi);
    if (f.IsBlack()) continue;
    const float pdf = pick.pmf * ls->pdf;
    if (!(pdf > 0) || !std::isfinite(pdf)) continue;
    if (!scene_.Visible(at.hit.p, at.hit.n, ls->p, ls->n)) continue;
    sum += f * ls->radiance * (AbsDot(at.hit.n, ls->wi) / pdf);
  }
  return sum / float(count);
}

Rgb PhotonMappingIntegrator::Gather(const Shading& at, uint32_t count, uint32_t seed,
                                    std::vector<PhotonNeighbour>& scratch) const {
  if (count == 0) return {};
  const Frame frame = Frame::FromZ(at.n);
  Rgb sum;
  for (uint32_t i = 0; i < count; ++i) {
    const Vec3 w = frame.FromLocal(SampleCosineHemisphere(Point2(i, count, seed, kGatherDirection)));
    // Cosine-weighted directions: f cos / pdf is the diffuse lobe's f times pi (kd, for
    // Lambert and glossy, whatever the direction).
    const Rgb kd = DiffuseReflectance(at.material, at.hit.n, at.wo, w);
    if (kd.IsBlack()) continue;
    const Ray ray{OffsetRayOrigin(at.hit.p, at.hit.n, w, scene_.ray_epsilon), w};
    sum += kd * GatherRay(ray, RayCone{at.cone_width, GatherSpread(count)}, i, seed, scratch);
  }
  return sum / float(count);
}

Rgb PhotonMappingIntegrator::GatherRay(Ray ray, RayCone cone, uint32_t i, uint32_t seed,
                                       std::vector<PhotonNeighbour>& scratch) const {
  const std::optional<DiffuseHit> d =
      TraceToDiffuse(scene_, ray, cone, Hash(seed, uint32_t(kGatherSpecular), i));
  if (!d) return {};
  const Vec3 n = FaceForward(d->hit.n, d->wo);
  const uint32_t count = scene_.indirect.gather_rays;
  Rgb e = DirectIrradiance(d->hit.p, d->hit.n, n, Point1(i, count, seed, kGatherLightPick),
                           Point2(i, count, seed, kGatherLightPoint));
  const auto visible = [&](const DecodedPhoton& photon) {
    return scene_.FrontsSeeEachOther(d->hit.p, n, photon.position, photon.normal);
  };
  if (const std::optional<Rgb> irradiance =
          NearestIrradiance(*maps_.global, d->hit.p, n, lookup_radius_, visible, scratch))
    e += *irradiance;
  return d->throughput * Albedo(d->material) * kInvPi * e;
}

Rgb PhotonMappingIntegrator::DirectIrradiance(const Vec3& p, const Vec3& geometric_n,
                                              const Vec3& n, float u_light, Vec2 u_point) const {
  if (scene_.light_power.empty()) return {};
  const auto pick = scene_.light_power.Sample(u_light);
  if (!(pick.pmf > 0)) return {};
  const std::optional<LightSample> ls = SampleLi(scene_.lights[pick.index], p, u_point);
  if (!ls) return {};
  const float cos_theta = Dot(n, ls->wi);
  const float pdf = pick.pmf * ls->pdf;
  if (!(cos_theta > 0) || !(pdf > 0) || !std::isfinite(pdf)) return {};
  if (!scene_.Visible(p, geometric_n, ls->p, ls->n)) return {};
  return ls->radiance * (cos_theta / pdf);
}

Rgb PhotonMappingIntegrator::GlossyBounce(const Shading& at, Vec2 u, uint32_t seed,
                                          std::vector<PhotonNeighbour>& scratch) const {
  const std::optional<BsdfSample> lobe = SampleGlossyLobe(at.material, at.hit.n, at.wo, u);
  if (!lobe || lobe->weight.IsBlack()) return {};
  const Rgb weight = lobe->weight;
  const Vec3 wi = lobe->wi;
  const Ray ray{OffsetRayOrigin(at.hit.p, at.hit.n, wi, scene_.ray_epsilon), wi};
  // A glossy lobe is taken as sharp for the footprint: the pixel's cone goes on.
  const std::optional<DiffuseHit> d = TraceToDiffuse(
      scene_, ray, RayCone{at.cone_width, scene_.camera.PixelSpreadAngle()}, Hash(seed, uint32_t(kGatherSpecular)));
  if (!d) return {};
  // Seen through a (possibly sharp) glossy reflection, a nearest-photon read would show:
  // the landing point is shaded in full, with the cheaper secondary gather.
  const Shading next{d->hit, d->wo, d->material, FaceForward(d->hit.n, d->wo), d->cone_width};
  Rgb direct, caustic, indirect;
  Shade(next, scene_.indirect.secondary_gather_rays, seed, scratch, direct, caustic, indirect);
  return weight * d->throughput * (direct + caustic + indirect);
}

std::string PhotonMappingIntegrator::ToString() const {
  return std::string("PhotonMappingIntegrator{global=") + (maps_.global ? "yes" : "no") +
         ", caustic=" + (maps_.caustic ? "yes" : "no") +
         ", indirect=" + (final_gather_ ? "final gathering" : "global map seen directly") + ", " +
         scene_.indirect.ToString() + "}";
}

}  // namespace farm
