#include "render/integrator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "math/frame.h"
#include "math/math.h"
#include "photon/surface_estimate.h"
#include "photonmap/irradiance_lookup.h"
#include "render/media_transport.h"
#include "sampling/hash.h"
#include "sampling/sobol.h"
#include "sampling/warps.h"
#include "scene/multiple_scattering.h"
#include "scene/surface_shading.h"
#include "spectral/spectral_light.h"
#include "texture/footprint.h"

namespace farm {

// A non-specular surface point being shaded: n, the geometric normal, faces the side wo
// comes from, and ns, the shading normal, is on n's side: the material's own where it has
// one (a principled material's, normal-mapped: MaterialAt), else the hit's. The BSDF and
// its cosines are taken about ns; offsets, and which side of the surface a direction is
// on, about n (a direction ns sees above the surface but n below it is not lit: it would
// leak). material is as it is at the hit (MaterialAt); cone_width is the width the ray's
// cone has reached there, where the rays leaving it start their own.
struct PhotonMappingIntegrator::Shading {
  const SurfaceHit& hit;
  Vec3 wo;
  const Material& material;
  Vec3 n;
  Vec3 ns;
  float cone_width = 0;
  // The medium around the point (null: vacuum), which attenuates its shadow rays.
  const Medium* medium = nullptr;

  Shading(const SurfaceHit& h, const Vec3& w, const Material& m, float cone, const Medium* around = nullptr)
      : hit(h), wo(w), material(m), n(FaceForward(h.n, w)), ns(ShadingNormalOf(m, h.ns)), cone_width(cone),
        medium(around) {
    if (Dot(h.n, n) < 0) ns = -ns;
  }

  // The BSDF for light arriving along wi, and nothing from below the geometric surface.
  Rgb Reflected(const Vec3& wi) const { return Dot(wi, n) > 0 ? EvaluateBsdf(material, ns, wo, wi) : Rgb(); }
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
  kCoverageSeed,
  kMediumSeed,
  kMediumLightPick,
  kMediumLightPoint,
  kMediumChannel,
  kMediumDistance,
  kGatherMedium,
  kVolumeChannel,
  kVolumeDistance,
  kVolumeProbe,
  kGatherScatterPick,
  // Single scattering's phase strategy along a segment, and the volumetric paths that go
  // on from its rays (one seed a path, one a vertex: kPath*).
  kMediumPhaseChannel,
  kMediumPhaseDistance,
  kMediumPhaseDirection,
  kVolumePath,
  kPathChannel,
  kPathDistance,
  kPathLightPick,
  kPathLightPoint,
  kPathDirection,
  kPathLobe,
  kPathSurvive,
  // Which shading point's gather ray recomputes its photon's irradiance for the bias layer.
  kGatherCompanion,
};

// Volume photon estimates per camera-path segment: the estimate is smooth (k photons, the
// probes of the ball's seen part), so the segment's light samples would mostly repeat it.
constexpr uint32_t kVolumeEstimatesPerSegment = 2;
// Vertices (scatterings and specular bounces) after which a volumetric path is cut (an
// albedo-1 medium keeps all its light, as photon paths' kMaxScatterings); Russian roulette
// on the path's throughput starts after kVolumeRouletteVertices of them.
constexpr int kMaxVolumePathVertices = 256;
constexpr int kVolumeRouletteVertices = 4;
// Of a shading point's gather rays in a medium, about this many gather the light scattered
// along their first segment (every stride-th, from a random offset, weighted by the
// stride: each ray is chosen with probability 1 / stride, so the sum stays unbiased); the
// rest only see the medium's transmittance. Each such estimate costs a kNN search and
// the seen-volume probes.
constexpr uint32_t kGatherScatterSamples = 8;
// With the bias layer, one shading point in this many (chosen at random) recomputes, at
// one of its gather rays (likewise), the irradiance of the photon that ray reads with the
// precompute's companion estimates; weighted by this times the gather rays, so the bias
// layer's share stays unbiased. Each costs a k-nearest search of twice the neighbours of
// each map and the coverage probes of its disc (docs/error-estimate.md).
constexpr uint32_t kGatherCompanionStride = 4;

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

// count at a share in (0, 1] (PhotonMappingIntegrator::Li), rounded, at least 1 (0 stays
// 0): the light samples or gather rays a shading point takes. Any count gives an unbiased
// estimate; fewer give a noisier one.
uint32_t ShadingCount(uint32_t count, float share) {
  if (count == 0 || !(share < 1)) return count;
  return std::max(1u, uint32_t(std::lround(double(count) * double(share))));
}

// The spread of a gather ray's cone: the side of the solid angle each of `count` rays
// stands for (2 pi / count of the hemisphere).
float GatherSpread(uint32_t count) { return std::sqrt(2 * kPi / float(std::max(count, 1u))); }

// A uniform float from 24 bits of a hash (for the rare choices of specular bounces).
float HashFloat(uint64_t h) { return float(h >> 40) * 0x1p-24f; }

// Specular bounces at which a camera path that meets glass follows both the reflected and
// the refracted ray (Sampling.specular SPLIT): at most 2^kSplitDepth branches a sample.
constexpr int kSplitDepth = 3;
constexpr int kMaxBranches = 1 << kSplitDepth;

// u turned by a rotation (Cranley-Patterson) hashed from a branch's key and the
// dimension: uniform again, and unchanged for key 0, so that a path that never splits
// draws exactly what it drew before splitting existed.
float ForBranch(float u, uint64_t key, uint32_t dimension) {
  if (key == 0) return u;
  const float v = u + HashFloat(Hash(key, dimension));
  return v < 1 ? v : v - 1;
}

float MaxComponent(const Rgb& c) { return std::max({c.r, c.g, c.b}); }

// Follows at most kGatherSpecularDepth specular bounces to the first non-specular surface
// that reflects; nothing if the ray escapes, ends on an emitter or is absorbed. key seeds
// the Fresnel choices; the ray's cone (footprint.h) reads the textures on the way. escaped
// tells whether the ray left the scene before any bounce (it then sees the environment;
// after a specular bounce that light is a caustic's).
struct DiffuseHit {
  SurfaceHit hit;
  Rgb throughput;
  Vec3 wo;
  Material material;  // at the hit
  float cone_width = 0;
};
std::optional<DiffuseHit> TraceToDiffuse(const SceneData& scene, Ray ray, RayCone cone, uint64_t key,
                                         bool& escaped) {
  Rgb throughput(1);
  escaped = false;
  for (int depth = 0; depth <= kGatherSpecularDepth; ++depth) {
    const std::optional<SurfaceHit> hit = scene.Intersect(ray);
    if (!hit) {
      escaped = depth == 0;
      return std::nullopt;
    }
    cone.width = cone.WidthAt(hit->t);
    // Nothing on this chain counts emission: gather rays ignore the emitters they hit.
    const Material material = MaterialAt(scene, *hit, ray.direction, TextureRead{cone.width, cone.filter, false});
    const MaterialCapabilities& can = scene.capabilities_of(*hit);
    const Vec3 wo = -ray.direction;
    // A smooth principled surface (specular and diffuse) ends the chain too: where a gather
    // ray lands, its albedo, specular lobe included, reflects the irradiance as if diffuse.
    if (can.reflects) return DiffuseHit{*hit, throughput, wo, material, cone.width};
    if (!can.specular) return std::nullopt;
    const uint64_t h = Hash(key, uint64_t(depth));
    const uint64_t h2 = MixBits(h);
    const std::optional<BsdfSample> s = SampleBsdf(material, hit->ns, wo, HashFloat(h),
                                                   {HashFloat(h2), HashFloat(h2 << 24)},
                                                   TransportMode::kRadiance);
    if (!s) return std::nullopt;
    throughput = throughput * s->weight;
    if (!throughput.IsFinite() || throughput.IsBlack()) return std::nullopt;
    ray = Ray{OffsetRayOrigin(hit->p, hit->n, s->wi, scene.ray_epsilon), s->wi};
  }
  return std::nullopt;
}

// The irradiance that a diffuse surface of this albedo reflects as `radiance` (pi L /
// albedo per channel, 0 where the albedo is): a caustic estimate's, without the texture.
Rgb IrradianceReflectedAs(const Rgb& radiance, const Rgb& albedo) {
  const auto channel = [](float l, float a) { return a > 1e-3f ? kPi * l / a : 0.0f; };
  return {channel(radiance.r, albedo.r), channel(radiance.g, albedo.g), channel(radiance.b, albedo.b)};
}

// a - b per channel, at least 0 (rounding may leave a diffuse material's f a hair below
// its diffuse part).
Rgb Excess(const Rgb& a, const Rgb& b) {
  return {std::max(0.0f, a.r - b.r), std::max(0.0f, a.g - b.g), std::max(0.0f, a.b - b.b)};
}

// The balance heuristic with sample counts: the weight of a sample of strategy a (a = its
// count times its density) against strategy b, for the same direction.
float BalanceWeight(float a, float b) { return a + b > 0 ? a / (a + b) : 0.0f; }

}  // namespace

// One branch of a camera path: its ray and cone, the throughput it carries, the product of
// the split shares it took (1 on a path that never split), the key that turns the
// sample's dimensions into its own (0 for the path's first branch), and the sample's
// effort (Li).
struct PhotonMappingIntegrator::PathBranch {
  Ray ray;
  RayCone cone;
  Rgb throughput;
  float share = 1;
  uint64_t key = 0;
  const Medium* medium = nullptr;  // the one the ray travels in; null: vacuum
  SampleEffort effort;
  // Set in spectral mode from the start, and once the branch crossed a dispersive surface:
  // the light it carries at a few wavelengths (throughput is its RGB, spectral->ToRgb()),
  // which sees an RGB quantity as its uplift at each.
  std::optional<SpectralLight> spectral;

  // What light x (RGB) reaching the branch adds to the film.
  Rgb Carried(const Rgb& x) const { return spectral ? spectral->Times(x).ToRgb() : throughput * x; }
  // What the film gains when light x reaching the branch becomes x + dx (dx may be
  // negative, x + dx not): an RGB's uplift to a spectrum is not linear, so in spectral mode
  // the difference of the two carried lights.
  Rgb CarriedChange(const Rgb& x, const Rgb& dx) const {
    return spectral ? Carried(x + dx) - Carried(x) : throughput * dx;
  }

  // The branch with its throughput times weight (RGB: a surface's or a medium's), over
  // survive.
  PathBranch Continued(const Rgb& weight, float survive = 1) const {
    PathBranch on = *this;
    if (spectral) {
      on.spectral = spectral->Times(weight, survive);
      on.throughput = on.spectral->ToRgb();
    } else {
      on.throughput = throughput * weight / survive;
    }
    return on;
  }

  // The branch at one wavelength from here on: the hero of its wavelengths, or (traced in
  // RGB so far) one drawn from u, carrying the uplift of its throughput there.
  PathBranch AtOneWavelength(float u) const {
    PathBranch on = *this;
    on.spectral = spectral ? spectral->HeroOnly() : SpectralLight::One(throughput, MonochromePath::Sample(u));
    on.throughput = on.spectral->ToRgb();
    return on;
  }
};

// The stratified points of one use of a shading point's (its light samples, its gather
// rays): point i is point offset + i of the (0,2)-net of `total` points keyed by seed.
struct PhotonMappingIntegrator::PointSet {
  uint32_t seed = 0, offset = 0, total = 0;

  // A point's `count` points keyed by own_seed, or, under shared strata, its run of the
  // set its pixel's samples draw together, keyed by `key` (a stream of the shared seed).
  static PointSet For(const SampleEffort& strata, uint32_t own_seed, uint32_t key, uint32_t count) {
    if (strata.count == 0) return {own_seed, 0, count};
    return {SubSeed(strata.seed, key), strata.index * count, strata.count * count};
  }
  float Get1(uint32_t i, uint32_t stream) const { return Point1(offset + i, total, seed, stream); }
  Vec2 Get2(uint32_t i, uint32_t stream) const { return Point2(offset + i, total, seed, stream); }
};

// The sampler's dimensions of one bounce.
struct PhotonMappingIntegrator::BounceDimensions {
  float seed = 0, lobe = 0;
  Vec2 direction;
  float survive = 0;
  Vec2 glossy;
};

// The branches of one bounce (kMaxBranches bounds them: only the first kSplitDepth
// bounces split).
struct PhotonMappingIntegrator::Branches {
  std::array<PathBranch, kMaxBranches> at;
  int count = 0;

  void Push(const PathBranch& branch) { at[count++] = branch; }
};

PhotonMappingIntegrator::PhotonMappingIntegrator(const SceneData& scene, const PhotonMaps& maps,
                                                 double radius_scale, bool bias_layer)
    : scene_(scene), maps_(maps), bias_layer_(bias_layer) {
  const float scale = std::isfinite(radius_scale) && radius_scale > 0 ? float(radius_scale) : 1.0f;
  maps_.global_estimate = ForRound(maps_.global_estimate, scale);
  maps_.caustic_estimate = ForRound(maps_.caustic_estimate, scale);
  maps_.volume_estimate = ForRound(maps_.volume_estimate, scale);
  global_companion_ = Companion(maps_.global_estimate);
  caustic_companion_ = Companion(maps_.caustic_estimate);
  volume_companion_ = Companion(maps_.volume_estimate);
  precompute_companion_ = Companion(PrecomputeEstimatesOf(scene, scale));
  lookup_radius_ = maps_.global_estimate.max_radius;
  // Without precomputed irradiance (a job planned before the precompute phase existed, or
  // a map too small to need one) the global map is seen directly rather than not at all.
  final_gather_ = scene.indirect.mode == IndirectMode::kFinalGather && maps_.global && maps_.irradiance &&
                  maps_.irradiance->has_irradiance();
  // A lone point or sun light gives every shadow ray the same answer: one is enough.
  single_delta_light_ = scene.lights.size() == 1 && IsDeltaLight(scene.lights.front());
  hittable_lights_ = std::any_of(scene.lights.begin(), scene.lights.end(),
                                 [](const Light& light) { return !IsDeltaLight(light); });
}

SampleResult PhotonMappingIntegrator::Li(const Ray& camera_ray, PixelSampler& sampler,
                                         std::vector<PhotonNeighbour>& scratch, const SampleEffort& effort) const {
  SampleEffort e = effort;
  if (!(std::isfinite(e.share) && e.share > 0)) e.share = 1;
  return Trace(camera_ray, sampler, scratch, /*light=*/true, e);
}

SampleResult PhotonMappingIntegrator::Cues(const Ray& camera_ray, PixelSampler& sampler) const {
  std::vector<PhotonNeighbour> unused;  // no photon is looked up
  return Trace(camera_ray, sampler, unused, /*light=*/false, {});
}

SampleResult PhotonMappingIntegrator::Trace(const Ray& camera_ray, PixelSampler& sampler,
                                            std::vector<PhotonNeighbour>& scratch, bool light,
                                            const SampleEffort& effort) const {
  SampleResult result;
  // The camera ray, with the pixel's cone, which specular bounces pass on (footprint.h).
  Branches branches;
  // In spectral mode the path's wavelengths come from a dimension of their own, drawn first.
  std::optional<SpectralLight> spectral;
  if (scene_.spectral_always) spectral = SpectralLight::Hero(Rgb(1), sampler.Get1D());
  // The camera is in the scene's medium (docs/media.md: not inside a shape's).
  branches.Push({camera_ray, RayCone{0, scene_.camera.PixelSpreadAngle()}, spectral ? spectral->ToRgb() : Rgb(1), 1,
                 0, scene_.medium ? &*scene_.medium : nullptr, effort, spectral});
  for (int depth = 0; depth < kMaxSpecularDepth && branches.count > 0; ++depth) {
    // The same draws at every bounce, before any early exit, so that the dimensions a
    // bounce uses do not depend on what earlier bounces hit; the branches share them.
    BounceDimensions u;
    u.seed = sampler.Get1D();
    u.lobe = sampler.Get1D();
    u.direction = sampler.Get2D();
    u.survive = sampler.Get1D();
    u.glossy = sampler.Get2D();
    Branches next;
    for (int b = 0; b < branches.count; ++b) Bounce(branches.at[b], depth, u, scratch, light, result, next);
    branches = next;
  }
  // Never let NaN or infinity through: a bad term is dropped, not the whole sample, and
  // the sample counted (the tile renderer's non-finite count: a bug to find, not hide).
  result.nonfinite = !(result.emitted.IsFinite() && result.direct.IsFinite() && result.caustic.IsFinite() &&
                       result.indirect.IsFinite() && result.volume.IsFinite());
  result.emitted = Finite(result.emitted);
  result.direct = Finite(result.direct);
  result.caustic = Finite(result.caustic);
  result.indirect = Finite(result.indirect);
  result.volume = Finite(result.volume);
  result.bias = Finite(result.bias);
  result.albedo = Finite(result.albedo);
  result.light_irradiance = Finite(result.light_irradiance);
  if (!std::isfinite(result.depth)) result.depth = 0;
  result.radiance = result.emitted + result.direct + result.indirect + result.caustic + result.volume;
  return result;
}

void PhotonMappingIntegrator::Bounce(const PathBranch& branch, int depth, const BounceDimensions& u,
                                     std::vector<PhotonNeighbour>& scratch, bool light, SampleResult& result,
                                     Branches& next) const {
  const Ray& ray = branch.ray;
  PathBranch path = branch;  // its throughput as the medium leaves it
  const std::optional<SurfaceHit> hit = scene_.Intersect(ray);
  // 2^32 levels from the sample's dimension, hashed so that nearby values give unrelated
  // scrambles.
  const float u_seed = ForBranch(u.seed, branch.key, 0);
  const uint32_t seed = uint32_t(Hash(uint64_t(double(u_seed) * 4294967296.0)));
  const Strategies strategies = CameraStrategies(branch);
  if (branch.medium) {
    // Light scattered towards the ray on its way (the volume layer: single and multiple
    // scattering), then what it reaches seen through the medium (media_transport.h).
    const float t_end = hit ? hit->t : std::numeric_limits<float>::infinity();
    const MediumSegment segment = SegmentIn(scene_, branch.medium, ray, t_end);
    if (light) {
      const LightSplit scattered =
          InScattered(segment, ray, SubSeed(seed, kMediumSeed), strategies.light_samples, /*camera_path=*/true,
                      scratch);
      result.volume += path.Carried(scattered.direct + scattered.indirect);
      result.bias += path.CarriedChange(scattered.direct + scattered.indirect, scattered.bias);
    }
    // Cues too: Russian roulette below reads the throughput, and the cues follow the
    // choices Li makes.
    path = path.Continued(segment.TransmittanceTo(t_end));
  }
  if (!hit) {
    // The environment, seen directly (unless hidden) or through specular bounces, which
    // only this path can reach (a delta BSDF): no other strategy shares it. Cues too (edge
    // anti-aliasing weighs an edge by the emitted light on its bright side).
    if (scene_.environment && (depth > 0 || scene_.environment_visible)) {
      result.emitted += path.Carried(scene_.environment->Radiance(ray.direction));
      if (depth == 0) result.alpha = 1;  // the background is part of the picture
    }
    return;
  }
  const Vec3 wo = -ray.direction;
  const RayCone cone{branch.cone.WidthAt(hit->t), branch.cone.spread};
  Material material = MaterialAt(scene_, *hit, ray.direction, TextureRead{cone.width, cone.filter});
  if (IsDispersive(material)) {
    // The wavelength from the direction's dimension, which a dielectric does not use.
    if (!path.spectral || path.spectral->count() > 1)
      path = path.AtOneWavelength(ForBranch(u.direction.x, branch.key, 3));
    material = AtWavelength(material, path.spectral->hero_nm());
  }
  const Shading at(*hit, wo, material, cone.width, branch.medium);
  const MaterialCapabilities& can = scene_.capabilities_of(*hit);
  // The first branch's surfaces, and an emitter any branch meets: a light reflected in
  // glass is a small bright feature that the refracted first branch does not see.
  if (branch.key == 0 || can.emits) {
    // Never 0, which stands for no hit.
    const uint64_t id = Hash(uint64_t(hit->shape), uint64_t(hit->part), uint64_t(hit->material));
    result.surface = uint32_t(Hash(uint64_t(result.surface), id)) | 1u;
  }
  if (depth == 0) {
    result.alpha = 1;
    result.hit = true;
    result.albedo = Albedo(material);
    result.normal = at.ns;
    result.surface_normal = Dot(hit->n, at.n) < 0 ? -hit->ns : hit->ns;
    result.depth = hit->t;
  }
  result.emitted += path.Carried(Emitted(material, hit->n, wo));  // Cues too, as above
  if (light && can.reflects) {
    result.shaded = true;
    Rgb direct, caustic, indirect, bias;
    Rgb irradiance;
    Shade(at, strategies, seed, scratch, direct, caustic, indirect, bias, branch.key == 0 ? &irradiance : nullptr);
    result.light_irradiance += path.Carried(irradiance);
    if (final_gather_) {
      const Vec2 u_glossy{ForBranch(u.glossy.x, branch.key, 1), ForBranch(u.glossy.y, branch.key, 2)};
      const LightSplit glossy = GlossyBounce(at, strategies, u_glossy, SubSeed(seed, kSecondarySeed), scratch);
      direct += glossy.direct;
      indirect += glossy.indirect;
      bias += glossy.bias;
    }
    // Added, not set: a smooth principled surface is shaded for its diffuse base here and
    // followed through its specular lobe below, and what lies beyond adds its own.
    result.direct += path.Carried(direct);
    result.caustic += path.Carried(caustic);
    result.indirect += path.Carried(indirect);
    result.bias += path.CarriedChange(direct + caustic + indirect, bias);
  }
  if (!can.specular) return;

  // The branch on along wi, its throughput times weight, then divided by survive.
  const auto go_on = [&](const Vec3& wi, const Rgb& weight, float share, uint64_t key, float survive = 1) {
    PathBranch on = path.Continued(weight, survive);
    if (!on.throughput.IsFinite() || on.throughput.IsBlack()) return;
    on.ray = Ray{OffsetRayOrigin(hit->p, hit->n, wi, scene_.ray_epsilon), wi};
    on.cone = cone;
    on.share = share;
    on.key = key;
    on.medium = MediumBeyond(scene_, *hit, wo, wi, branch.medium);
    next.Push(on);
  };
  if (scene_.split_specular && depth < kSplitDepth) {
    if (const std::optional<SpecularSplit> split = SplitSpecular(material, hit->ns, wo, TransportMode::kRadiance)) {
      // The refracted branch keeps the path's key, the reflected one takes a new one, so
      // that the branches' shading points draw unrelated numbers.
      const auto share = [&](const BsdfSample& s) { return branch.share * MaxComponent(s.weight); };
      if (split->transmitted)
        go_on(split->transmitted->wi, split->transmitted->weight, share(*split->transmitted), branch.key);
      go_on(split->reflected.wi, split->reflected.weight, share(split->reflected), Hash(branch.key, uint64_t(depth) + 1));
      return;
    }
  }
  const Vec2 u_direction{ForBranch(u.direction.x, branch.key, 3), ForBranch(u.direction.y, branch.key, 4)};
  const std::optional<BsdfSample> s = SampleSpecular(material, hit->ns, wo, ForBranch(u.lobe, branch.key, 5),
                                                     u_direction, TransportMode::kRadiance);
  if (!s) return;
  float survive = 1;
  if (depth >= kRouletteDepth) {
    // On what the path has lost besides its split shares: a branch is not cut for being
    // one of several.
    survive = std::min(1.0f, MaxComponent(path.Continued(s->weight).throughput) / branch.share);
    if (!(survive > 0) || ForBranch(u.survive, branch.key, 6) >= survive) return;
  }
  go_on(s->wi, s->weight, branch.share, branch.key, survive);
}

void PhotonMappingIntegrator::Shade(const Shading& at, const Strategies& strategies, uint32_t seed,
                                    std::vector<PhotonNeighbour>& scratch, Rgb& direct,
                                    Rgb& caustic, Rgb& indirect, Rgb& bias, Rgb* irradiance) const {
  direct = DirectLight(at, strategies, SubSeed(seed, kDirectSeed), irradiance);
  bias = {};
  // Both photon estimates are over the surface their disc covers (surface_estimate.h).
  const uint32_t coverage_seed = SubSeed(seed, kCoverageSeed);
  caustic = maps_.caustic ? EstimateWithCompanion(*maps_.caustic, at, maps_.caustic_estimate, caustic_companion_,
                                                  coverage_seed, scratch, bias)
                          : Rgb();
  if (irradiance) *irradiance += IrradianceReflectedAs(caustic, Albedo(at.material));
  if (strategies.gather_rays > 0) {
    const LightSplit gathered = Gather(at, strategies, SubSeed(seed, kGatherSeed), scratch);
    direct += gathered.direct;
    indirect = gathered.indirect;
    bias += gathered.bias;
  } else if (maps_.global) {
    indirect = EstimateWithCompanion(*maps_.global, at, maps_.global_estimate, global_companion_, coverage_seed,
                                     scratch, bias);
  } else {
    indirect = {};
  }
}

Rgb PhotonMappingIntegrator::EstimateWithCompanion(const PhotonMap& map, const Shading& at,
                                                   const RadianceEstimateSettings& estimate,
                                                   const RadianceEstimateSettings& companion, uint32_t seed,
                                                   std::vector<PhotonNeighbour>& scratch, Rgb& bias) const {
  const auto bsdf = [&at](const Vec3& wi) { return at.Reflected(wi); };
  const Rgb e = EstimateOnSurface(scene_, map, at.hit.p, at.n, estimate, bsdf, scratch, seed);
  if (bias_layer_) bias += EstimateOnSurface(scene_, map, at.hit.p, at.n, companion, bsdf, scratch, seed) - e;
  return e;
}

uint32_t PhotonMappingIntegrator::LightSampleCount() const {
  return single_delta_light_ ? 1 : scene_.indirect.light_samples;
}

PhotonMappingIntegrator::Strategies PhotonMappingIntegrator::CameraStrategies(const PathBranch& branch) const {
  const float share = branch.effort.share * branch.share;
  Strategies s;
  s.gather_rays = final_gather_ ? ShadingCount(scene_.indirect.gather_rays, share) : 0;
  s.glossy_bounce = final_gather_;
  s.light_samples = ShadingCount(LightSampleCount(), share);
  s.secondary_gather_rays = ShadingCount(scene_.indirect.secondary_gather_rays, share);
  if (branch.key == 0) s.strata = branch.effort;
  return s;
}

float PhotonMappingIntegrator::EnvironmentLightPdf(const Vec3& w) const {
  if (scene_.environment_light < 0) return 0;
  return scene_.light_power.Pmf(scene_.environment_light) * scene_.environment->Pdf(w);
}

float PhotonMappingIntegrator::GlossyBouncePdf(const Shading& at, const Vec3& wi) const {
  if (!(Dot(wi, at.n) > 0)) return 0;  // GlossyBounce drops what is below the surface
  return GlossyLobePdf(at.material, at.ns, at.wo, wi);
}

Rgb PhotonMappingIntegrator::DirectLight(const Shading& at, const Strategies& strategies, uint32_t seed,
                                         Rgb* irradiance) const {
  const uint32_t count = strategies.light_samples;
  if (scene_.light_power.empty() || count == 0) return {};
  const PointSet points = PointSet::For(strategies.strata, seed, kDirectSeed, count);
  Rgb sum, incident;
  for (uint32_t j = 0; j < count; ++j) {
    const auto pick = scene_.light_power.Sample(points.Get1(j, kLightPick));
    if (!(pick.pmf > 0)) continue;
    const std::optional<LightSample> ls = SampleLi(scene_.lights[pick.index], at.hit.p, points.Get2(j, kLightPoint));
    if (!ls) continue;
    Rgb f = at.Reflected(ls->wi);
    const float pdf = pick.pmf * ls->pdf;
    if (!(pdf > 0) || !std::isfinite(pdf)) continue;
    // Over the geometric normal, so that neither a black texel nor a normal map hides it;
    // not the environment's, whose shadows are soft and whose samples are noisy.
    const float cos_geometric =
        irradiance && pick.index != scene_.environment_light ? Dot(at.n, ls->wi) : 0.0f;
    if (f.IsBlack() && !(cos_geometric > 0)) continue;
    if (!scene_.Visible(at.hit.p, at.hit.n, ls->p, ls->n)) continue;
    if (cos_geometric > 0) incident += ls->radiance * (cos_geometric / pdf);
    if (f.IsBlack()) continue;
    if (pick.index == scene_.environment_light) {
      // Gather rays (the diffuse lobe) and the glossy bounce (the rest) that escape see the
      // environment too: each part of f takes its balance-heuristic share.
      const float light = float(count) * pdf;
      const Rgb f_diffuse = DiffuseReflectance(at.material, at.ns, at.wo, ls->wi) * kInvPi;
      const float cos = Dot(at.ns, ls->wi);
      const float gather = float(strategies.gather_rays) * (cos > 0 ? CosineHemispherePdf(cos) : 0.0f);
      const float glossy = strategies.glossy_bounce ? GlossyBouncePdf(at, ls->wi) : 0.0f;
      f = f_diffuse * BalanceWeight(light, gather) + Excess(f, f_diffuse) * BalanceWeight(light, glossy);
    }
    sum += f * Arriving(at, *ls) * (AbsDot(at.ns, ls->wi) / pdf);
  }
  if (irradiance) *irradiance = incident / float(count);
  return sum / float(count);
}

PhotonMappingIntegrator::LightSplit PhotonMappingIntegrator::Gather(const Shading& at, const Strategies& strategies,
                                                                    uint32_t seed,
                                                                    std::vector<PhotonNeighbour>& scratch) const {
  const uint32_t count = strategies.gather_rays;
  if (count == 0) return {};
  const PointSet points = PointSet::For(strategies.strata, seed, kGatherSeed, count);
  const Frame frame = Frame::FromZ(at.ns);
  const float light_samples = float(strategies.light_samples);
  const uint32_t scatter_stride = std::max(1u, count / kGatherScatterSamples);
  const uint32_t scatter_offset =
      std::min(scatter_stride - 1, uint32_t(Point1(0, 1, seed, kGatherScatterPick) * float(scatter_stride)));
  // The bias layer's share of the precomputed irradiance (kGatherCompanionStride).
  const uint64_t pick = Hash(seed, uint32_t(kGatherCompanion));
  const bool companion = bias_layer_ && final_gather_ && pick % kGatherCompanionStride == 0;
  const uint32_t companion_ray = uint32_t((pick >> 32) % count);
  Rgb indirect, escaped, bias;
  for (uint32_t i = 0; i < count; ++i) {
    const Vec3 local = SampleCosineHemisphere(points.Get2(i, kGatherDirection));
    const Vec3 w = frame.FromLocal(local);
    if (Dot(w, at.n) < 0) continue;  // below the surface (only a shading normal tilts the frame so)
    // Cosine-weighted directions: f cos / pdf is the diffuse lobe's f times pi (kd, for
    // Lambert and glossy, whatever the direction).
    const Rgb kd = DiffuseReflectance(at.material, at.ns, at.wo, w);
    if (kd.IsBlack()) continue;
    const Ray ray{OffsetRayOrigin(at.hit.p, at.hit.n, w, scene_.ray_epsilon), w};
    // In a medium: what the ray's first segment scatters towards the point (one sample,
    // all of it indirect light here), and what lies beyond seen through it.
    Rgb through(1);
    if (at.medium) {
      const std::optional<SurfaceHit> first = scene_.Intersect(ray);
      const float t_end = first ? first->t : std::numeric_limits<float>::infinity();
      const MediumSegment segment = SegmentIn(scene_, at.medium, ray, t_end);
      if (i % scatter_stride == scatter_offset) {
        const LightSplit scattered =
            InScattered(segment, ray, uint32_t(Hash(seed, uint32_t(kGatherMedium), i)), 1, /*camera_path=*/false, scratch);
        indirect += kd * (scattered.direct + scattered.indirect) * float(scatter_stride);
        bias += kd * scattered.bias * float(scatter_stride);
      }
      through = segment.TransmittanceTo(t_end);
    }
    bool escaped_directly = false;
    Rgb change;
    indirect += kd * through *
                GatherRay(ray, RayCone{at.cone_width, GatherSpread(count), TextureFilter::kIsotropic}, i, points, seed,
                          at.medium, scratch, escaped_directly, companion && i == companion_ray ? &change : nullptr);
    bias += kd * through * change * float(count * kGatherCompanionStride);
    if (escaped_directly && scene_.environment_light >= 0) {
      // The environment seen by a gather ray is direct light, shared with light sampling.
      const float gather = float(count) * CosineHemispherePdf(local.z);
      escaped += kd * through * scene_.environment->Radiance(w) *
                 BalanceWeight(gather, light_samples * EnvironmentLightPdf(w));
    }
  }
  return {escaped / float(count), indirect / float(count), bias / float(count)};
}

Rgb PhotonMappingIntegrator::GatherRay(Ray ray, RayCone cone, uint32_t i, const PointSet& points, uint32_t seed,
                                       const Medium* medium, std::vector<PhotonNeighbour>& scratch,
                                       bool& escaped, Rgb* companion) const {
  const std::optional<DiffuseHit> d =
      TraceToDiffuse(scene_, ray, cone, Hash(seed, uint32_t(kGatherSpecular), i), escaped);
  if (!d) return {};
  const Shading at(d->hit, d->wo, d->material, d->cone_width, medium);
  const Rgb reflect = d->throughput * Albedo(at.material) * kInvPi;
  const Rgb e =
      LandingIrradiance(at, points.Get1(i, kGatherLightPick), points.Get2(i, kGatherLightPoint), scratch, companion);
  if (companion) *companion = reflect * *companion;
  return reflect * e;
}

Rgb PhotonMappingIntegrator::LandingIrradiance(const Shading& at, float u_light, Vec2 u_point,
                                               std::vector<PhotonNeighbour>& scratch, Rgb* companion) const {
  Rgb e = DirectIrradiance(at, u_light, u_point);
  if (!final_gather_) return e;
  const auto visible = [&](const DecodedPhoton& photon) {
    return scene_.FrontsSeeEachOther(at.hit.p, at.n, photon.position, photon.normal);
  };
  const std::optional<std::uint32_t> photon =
      NearestIrradiancePhoton(*maps_.irradiance, at.hit.p, at.n, lookup_radius_, visible, scratch);
  if (!photon) return e;
  const Rgb precomputed = maps_.irradiance->irradiance(*photon);
  e += precomputed;
  // Against the stored value: its rounding (RGB9E5, to nearest) adds noise to the
  // difference, not bias.
  if (companion)
    *companion = PhotonIrradiance(scene_, *maps_.global, maps_.caustic, *photon, precompute_companion_, scratch) -
                 precomputed;
  return e;
}

Rgb PhotonMappingIntegrator::DirectIrradiance(const Shading& at, float u_light, Vec2 u_point) const {
  if (scene_.light_power.empty()) return {};
  const auto pick = scene_.light_power.Sample(u_light);
  if (!(pick.pmf > 0)) return {};
  const std::optional<LightSample> ls = SampleLi(scene_.lights[pick.index], at.hit.p, u_point);
  if (!ls) return {};
  const float cos_theta = Dot(at.ns, ls->wi);
  const float pdf = pick.pmf * ls->pdf;
  if (!(cos_theta > 0) || !(Dot(at.n, ls->wi) > 0) || !(pdf > 0) || !std::isfinite(pdf)) return {};
  if (!scene_.Visible(at.hit.p, at.hit.n, ls->p, ls->n)) return {};
  return Arriving(at, *ls) * (cos_theta / pdf);
}

PhotonMappingIntegrator::LightSplit PhotonMappingIntegrator::GlossyBounce(const Shading& at,
                                                                          const Strategies& strategies, Vec2 u,
                                                                          uint32_t seed,
                                                                          std::vector<PhotonNeighbour>& scratch) const {
  const std::optional<BsdfSample> lobe = SampleGlossyLobe(at.material, at.ns, at.wo, u);
  if (!lobe || lobe->weight.IsBlack()) return {};
  const Rgb weight = lobe->weight;
  const Vec3 wi = lobe->wi;
  if (!(Dot(wi, at.n) > 0)) return {};  // below the surface
  const Ray ray{OffsetRayOrigin(at.hit.p, at.hit.n, wi, scene_.ray_epsilon), wi};
  // A glossy lobe is taken as sharp for the footprint: the pixel's cone goes on.
  bool escaped = false;
  const std::optional<DiffuseHit> d =
      TraceToDiffuse(scene_, ray, RayCone{at.cone_width, scene_.camera.PixelSpreadAngle()},
                     Hash(seed, uint32_t(kGatherSpecular)), escaped);
  if (escaped && scene_.environment_light >= 0) {
    // Direct light from the environment, shared with light sampling (DirectLight).
    const float share = BalanceWeight(lobe->pdf, float(strategies.light_samples) * EnvironmentLightPdf(wi));
    return {weight * scene_.environment->Radiance(wi) * share, Rgb(), Rgb()};
  }
  if (!d) return {};
  // Seen through a (possibly sharp) glossy reflection, a nearest-photon read would show:
  // the landing point is shaded in full, with the cheaper secondary gather.
  const Shading next(d->hit, d->wo, d->material, d->cone_width, at.medium);
  Rgb direct, caustic, indirect, bias;
  const Strategies secondary{strategies.secondary_gather_rays, false, strategies.light_samples, 0, {}};
  Shade(next, secondary, seed, scratch, direct, caustic, indirect, bias);
  return {Rgb(), weight * d->throughput * (direct + caustic + indirect), weight * d->throughput * bias};
}

Rgb PhotonMappingIntegrator::Arriving(const Shading& at, const LightSample& ls) const {
  if (!at.medium) return ls.radiance;
  return ls.radiance * TransmittanceBetween(scene_, at.medium, at.hit.p, ls.p);
}

ShadowTransmittance PhotonMappingIntegrator::ShadowIn(const Medium* medium) const {
  return [this, medium](const Vec3& x, const LightSample& ls) {
    if (!scene_.Visible(x, Vec3(), ls.p, ls.n)) return Rgb();
    return ls.radiance * TransmittanceBetween(scene_, medium, x, ls.p);
  };
}

PhotonMappingIntegrator::LightSplit PhotonMappingIntegrator::InScattered(const MediumSegment& segment, const Ray& ray,
                                                                         uint32_t seed, uint32_t count, bool camera_path,
                                                                         std::vector<PhotonNeighbour>& scratch) const {
  if (segment.empty() || scene_.light_power.empty() || count == 0) return {};
  const ShadowTransmittance shadow = ShadowIn(segment.medium);
  Rgb single, multiple, bias;
  for (uint32_t j = 0; j < count; ++j) {
    const auto pick = scene_.light_power.Sample(Point1(j, count, seed, kMediumLightPick));
    const InScatterDimensions u{Point2(j, count, seed, kMediumLightPoint), Point1(j, count, seed, kMediumChannel),
                                Point1(j, count, seed, kMediumDistance)};
    single += InScatter(segment, ray, scene_.lights[pick.index], pick.pmf, u, shadow);
  }
  // The phase strategy: it finds the lights that rays can hit (InScatter weighs its samples
  // of those against it), and its rays are where volumetric paths go on.
  const bool path_traced = PathTracesMultipleScattering(*segment.medium);
  if (hittable_lights_ || path_traced) {
    for (uint32_t j = 0; j < count; ++j) {
      const std::optional<ScatteredRay> s =
          PhaseInScatter(scene_, segment, ray, Point1(j, count, seed, kMediumPhaseChannel),
                         Point1(j, count, seed, kMediumPhaseDistance), Point2(j, count, seed, kMediumPhaseDirection));
      if (!s) continue;
      single += s->single;
      if (path_traced) {
        const uint32_t path_seed = uint32_t(Hash(seed, uint32_t(kVolumePath), j));
        Rgb path_bias;
        multiple += s->weight * VolumePath(s->ray, s->hit, segment.medium, path_seed, scratch, path_bias);
        bias += s->weight * path_bias;
      }
    }
  }
  if (path_traced) return {single / float(count), multiple / float(count), bias / float(count)};
  const uint32_t estimates = maps_.volume ? std::min(count, kVolumeEstimatesPerSegment) : 0;
  for (uint32_t j = 0; j < estimates; ++j) {
    // The companion at the same distance, with the same probes of the seen part.
    const auto estimate = [&](const RadianceEstimateSettings& settings) {
      return VolumeInScatter(scene_, segment, ray, *maps_.volume, settings, Point1(j, estimates, seed, kVolumeChannel),
                             Point1(j, estimates, seed, kVolumeDistance), Point2(j, estimates, seed, kVolumeProbe),
                             scratch);
    };
    const Rgb e = estimate(maps_.volume_estimate);
    multiple += e;
    // One companion, the first estimate's, for the segment: the estimates differ only in
    // where they fall along it, and a second companion search would cost as much again.
    if (bias_layer_ && camera_path && j == 0) bias = estimate(volume_companion_) - e;
  }
  if (!estimates) return {single / float(count), Rgb(), Rgb()};
  return {single / float(count), multiple / float(estimates), bias};
}

Rgb PhotonMappingIntegrator::VolumePath(Ray ray, std::optional<SurfaceHit> hit, const Medium* medium,
                                        uint32_t seed, std::vector<PhotonNeighbour>& scratch, Rgb& bias) const {
  Rgb light, throughput(1);
  bool after_specular = false;  // the ray left a specular surface, not a scattering point
  for (int vertex = 0; vertex < kMaxVolumePathVertices; ++vertex) {
    const uint32_t v = uint32_t(Hash(seed, uint32_t(vertex)));
    if (vertex >= kVolumeRouletteVertices) {
      const float survive = std::min(1.0f, MaxComponent(throughput));
      if (!(survive > 0) || Point1(0, 1, v, kPathSurvive) >= survive) break;
      throughput = throughput / survive;
    }
    const float t_end = hit ? hit->t : std::numeric_limits<float>::infinity();
    const MediumSegment segment = SegmentIn(scene_, medium, ray, t_end);
    std::optional<Material> material;  // of the hit, read once
    if (after_specular) {
      // What the ray meets that emits: only this path finds light past a specular bounce
      // (shadow rays stop at glass), so all of it, seen through the medium on the way.
      Rgb emitted;
      if (hit) {
        material = MaterialAt(scene_, *hit, ray.direction, TextureRead{0, TextureFilter::kIsotropic});
        emitted = Emitted(*material, hit->n, -ray.direction);
      } else {
        LightsAlong(scene_, ray, hit, [&](int, const LightSample& ls) { emitted += ls.radiance; });
      }
      light += throughput * segment.TransmittanceTo(t_end) * emitted;
    }
    // The ray's free flight: it scatters at x, where single scattering is taken and the
    // path goes on by the phase function, or gets through to what it meets.
    if (!segment.empty()) {
      // Closed-form in a homogeneous medium, delta-tracked in a grid: the weight is
      // sigma_s T / pdf where it scatters, T / the probability of getting through where
      // it does not (media/medium.h).
      const FreeFlight flight = segment.SampleFlight(Point1(0, 1, v, kPathChannel), Point1(0, 1, v, kPathDistance));
      throughput = throughput * flight.weight;
      if (flight.t) {
        const ScatteredRay s = ScatterAt(scene_, segment.medium, ray.At(*flight.t), -ray.direction,
                                         Point1(0, 1, v, kPathLightPick), Point2(0, 1, v, kPathLightPoint),
                                         Point2(0, 1, v, kPathDirection), ShadowIn(segment.medium));
        light += throughput * s.single;
        ray = s.ray;
        hit = s.hit;
        after_specular = false;
        continue;
      }
    }
    // Through to the surface (an escaped ray's lights were the last vertex's to find).
    if (!hit) break;
    const Vec3 wo = -ray.direction;
    if (!material) material = MaterialAt(scene_, *hit, ray.direction, TextureRead{0, TextureFilter::kIsotropic, false});
    const MaterialCapabilities& can = scene_.capabilities_of(*hit);
    if (can.reflects) {
      // Where a gather ray would land: its reflected light, not its emission (which the
      // lights gave single scattering) nor its caustics.
      const Shading at(*hit, wo, *material, 0, medium);
      light += throughput * Albedo(*material) * kInvPi *
               LandingIrradiance(at, Point1(0, 1, v, kPathLightPick), Point2(0, 1, v, kPathLightPoint), scratch);
      if (!final_gather_ && maps_.global) {
        Rgb companion;
        light += throughput * EstimateWithCompanion(*maps_.global, at, maps_.global_estimate, global_companion_,
                                                    SubSeed(v, kCoverageSeed), scratch, companion);
        bias += throughput * companion;
      }
      break;
    }
    if (!can.specular) break;
    const std::optional<BsdfSample> b = SampleBsdf(*material, hit->ns, wo, Point1(0, 1, v, kPathLobe),
                                                   Point2(0, 1, v, kPathDirection), TransportMode::kRadiance);
    if (!b) break;
    throughput = throughput * b->weight;
    if (!throughput.IsFinite() || throughput.IsBlack()) break;
    medium = MediumBeyond(scene_, *hit, wo, b->wi, medium);
    ray = Ray{OffsetRayOrigin(hit->p, hit->n, b->wi, scene_.ray_epsilon), b->wi};
    hit = scene_.Intersect(ray);
    after_specular = true;
  }
  return light;
}

std::string PhotonMappingIntegrator::ToString() const {
  return std::string("PhotonMappingIntegrator{global=") + (maps_.global ? "yes" : "no") +
         ", caustic=" + (maps_.caustic ? "yes" : "no") + ", volume=" + (maps_.volume ? "yes" : "no") +
         ", indirect=" + (final_gather_ ? "final gathering" : "global map seen directly") + ", " +
         scene_.indirect.ToString() + "}";
}

}  // namespace farm
