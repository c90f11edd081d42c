#include "photon/photon_tracer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <string>

#include "contract/failure.h"
#include "contract/rules.h"

#include "math/math.h"
#include "photon/photon_emission.h"
#include "photon/trace_photons.h"
#include "media/henyey_greenstein.h"
#include "scene/media_segments.h"
#include "scene/multiple_scattering.h"
#include "scene/scene_data.h"
#include "scene/surface_shading.h"
#include "spectral/spectral_light.h"

namespace farm {
namespace {

// Bounces after which a path is cut even if Russian roulette keeps it (light trapped by
// total internal reflection would otherwise circle for long).
constexpr int kMaxBounces = 32;
// Scatterings in media after which a path is cut: an albedo-1 medium keeps every photon,
// and in a dense one a path random-walks long before it reaches a wall.
constexpr int kMaxScatterings = 256;

// Paths per parallel work item: big enough to amortise scheduling, small enough to balance
// two cores and to notice a stop request quickly.
constexpr uint64_t kChunkPaths = 2048;

// The least share of the photons a reflecting surface keeps. Glossy surfaces keep their
// diffuse share, but a rough metal, which has none, must keep some too: a gather ray that
// lands on it reads the irradiance there (integrator.h), and without photons its light
// from the rest of the scene would be missing (the floor under a metal ball darkened).
constexpr float kMinPhotonKeep = 0.5f;

void CheckRequest(const PhotonShardRequest& r) {
  if (!IsPhotonMapKind(static_cast<uint32_t>(r.map)))
    throw std::invalid_argument("TracePhotonShard: map kind " +
                                std::to_string(static_cast<uint32_t>(r.map)) + " is unknown");
  if (r.total_photons == 0)
    throw std::invalid_argument("TracePhotonShard: total_photons must be positive");
  if (r.first_photon > r.total_photons || r.photon_count > r.total_photons - r.first_photon)
    throw std::invalid_argument("TracePhotonShard: paths [" + std::to_string(r.first_photon) +
                                ", +" + std::to_string(r.photon_count) + ") exceed total_photons " +
                                std::to_string(r.total_photons));
  if (r.round_offset > UINT64_MAX - r.total_photons)
    throw std::invalid_argument("TracePhotonShard: round_offset " + std::to_string(r.round_offset) +
                                " overflows the path index");
}

}  // namespace

void TracePhotonPath(const SceneData& scene, PhotonMapKind kind, uint64_t index,
                     float power_scale, const PhotonTraceOptions& options,
                     std::vector<ShardPhoton>& out) {
  PhotonRandom random(scene.seed, kind, index);
  const std::optional<PhotonRay> emitted = EmitPhoton(scene, kind, random);
  if (!emitted) return;
  ContinuePhotonPath(scene, kind, *emitted, random, power_scale, options, out);
}

void ContinuePhotonPath(const SceneData& scene, PhotonMapKind kind, const PhotonRay& emitted,
                        PhotonRandom& random, float power_scale, const PhotonTraceOptions& options,
                        std::vector<ShardPhoton>& out) {
  Ray ray = emitted.ray;
  Rgb power = emitted.power * power_scale;
  int specular_bounces = 0, diffuse_bounces = 0;
  // Set in spectral mode from emission on, and at the first dispersive surface: the light
  // the photon carries at a few wavelengths (power is its RGB, spectral->ToRgb()).
  std::optional<SpectralLight> spectral;
  if (scene.spectral_always) {
    spectral = SpectralLight::Hero(power, random.Get1D());
    power = spectral->ToRgb();
  }

  // The medium the path travels in: lights sit in the scene's (docs/media.md).
  const Medium* medium = scene.medium ? &*scene.medium : nullptr;
  // Russian roulette: survive with the ratio of the new to the old power (its largest
  // channel), and divide by it, so that surviving photons keep roughly constant power.
  // False if the path ends.
  const auto survive_with = [&](const Rgb& weight, float u_survive) {
    std::optional<SpectralLight> next_spectral;
    Rgb next = power * weight;
    if (spectral) {
      next_spectral = spectral->Times(weight);
      next = next_spectral->ToRgb();
    }
    const float survive = std::min(1.0f, MaxComponent(Vec3(next.r, next.g, next.b)) /
                                             MaxComponent(Vec3(power.r, power.g, power.b)));
    if (!(survive > 0) || u_survive >= survive) return false;
    power = next / survive;
    if (spectral) spectral = next_spectral->Over(survive);
    return power.IsFinite();
  };

  int scatterings = 0;
  for (int bounce = 0; bounce < kMaxBounces && scatterings < kMaxScatterings;) {
    // Four draws per bounce whatever happens, so that bounce k's numbers never shift; four
    // more in a scene with media.
    const float u_store = random.Get1D();
    const float u_lobe = random.Get1D();
    const Vec2 u_direction = random.Get2D();
    const float u_survive = random.Get1D();
    float u_channel = 0, u_distance = 0;
    Vec2 u_phase;
    if (scene.has_media) {
      u_channel = random.Get1D();
      u_distance = random.Get1D();
      u_phase = random.Get2D();
    }

    const std::optional<SurfaceHit> hit = scene.Intersect(ray);
    if (const MediumSegment segment =
            SegmentIn(scene, medium, ray, hit ? hit->t : std::numeric_limits<float>::infinity());
        !segment.empty()) {
      const FreeFlight flight = segment.SampleFlight(u_channel, u_distance);
      if (flight.t) {
        // Taken by the medium: a caustic path ends (what it scatters is the volume and
        // global maps' light); a volume path stores a photon unless the light came straight
        // from a light (single scattering is sampled from the lights: media_transport.h)
        // or the medium's multiple scattering is path traced (multiple_scattering.h).
        if (kind == PhotonMapKind::kCaustic) return;
        // The photon carries what it scatters there (sigma_s T / pdf of the light it
        // brings: the albedo, one channel): the density of scatterings, not of collisions.
        const Vec3 x = ray.At(*flight.t);
        const Rgb scattered = flight.weight;
        if (kind == PhotonMapKind::kVolume && (bounce > 0 || scatterings > 0) &&
            !PathTracesMultipleScattering(*segment.medium))
          out.push_back({x, spectral ? spectral->Times(scattered).ToRgb() : power * scattered, -ray.direction,
                         Vec3(0, 0, 1)});
        if (!survive_with(scattered, u_survive)) return;
        // Scattered light is indirect: the global map stores it where it lands.
        ++diffuse_bounces;
        ++scatterings;
        ray = Ray{x, SampleHenyeyGreenstein(-ray.direction, segment.medium->g(), u_phase).wi};
        continue;
      }
      // Through: the transmittance over the probability of getting through.
      const Rgb through = flight.weight;
      power = power * through;
      if (spectral) {
        spectral = spectral->Times(through);
        power = spectral->ToRgb();
      }
    }
    if (!hit) return;
    // A photon aimed at a target is that target's to carry only (photon_emission.h).
    if (bounce == 0 && emitted.target >= 0 &&
        !(scene.specular_target_surfaces[emitted.target] == SceneData::TargetSurface{hit->shape, hit->part}))
      return;
    // A photon is one sample among very many: a point lookup of the textures (emission
    // aside: it scatters light, whatever the surface emits).
    Material material = MaterialAt(scene, *hit, ray.direction, TextureRead{.emission = false});
    const Vec3 wi = -ray.direction;  // towards where the photon came from
    if (IsDispersive(material)) {
      // u_store is free here: a dielectric stores no photon.
      if (!spectral || spectral->count() > 1) {
        const MonochromePath at =
            options.wavelength_nm > 0 ? MonochromePath{options.wavelength_nm} : MonochromePath::Sample(u_store);
        spectral = spectral ? spectral->HeroOnly() : SpectralLight::One(power, at);
        power = spectral->ToRgb();
      }
      material = AtWavelength(material, spectral->hero_nm());
    }

    const MaterialCapabilities& can = scene.capabilities_of(*hit);
    if (!can.specular && !can.reflects) return;  // emitters absorb
    if (can.reflects) {
      // Global: indirect light only (after a diffuse or glossy bounce). Caustic: L S+ D,
      // stored at the first non-specular surface, where the path ends.
      // Volume: nothing on surfaces.
      const bool wanted = kind == PhotonMapKind::kCaustic  ? specular_bounces > 0
                          : kind == PhotonMapKind::kGlobal ? diffuse_bounces > 0 || options.store_direct
                                                           : false;
      if (wanted) {
        // Glossy surfaces keep a photon only with the probability of their diffuse share,
        // at least kMinPhotonKeep; the kept ones carry proportionally more power, so the
        // estimate stays unbiased.
        const float keep = std::max(can.diffuse_fraction, kMinPhotonKeep);
        if (u_store < keep)
          out.push_back({hit->p, power / keep, wi, FaceForward(hit->n, wi)});
      }
      if (kind == PhotonMapKind::kCaustic && !can.specular) return;
    }

    const std::optional<BsdfSample> s =
        SampleBsdf(material, hit->ns, wi, u_lobe, u_direction, TransportMode::kImportance);
    if (!s) return;
    // A caustic path goes on only through specular bounces (a smooth principled surface's
    // diffuse base ends it: the photon was stored above).
    if (kind == PhotonMapKind::kCaustic && !s->specular) return;
    Rgb weight = s->weight;
    // A shading normal (a mesh's smooth normals, a normal map) makes the BSDF non-symmetric
    // for what photons carry (Veach's adjoint): |wi.ns| |wo.n| / (|wi.n| |wo.ns|), for wi
    // towards where the photon came from and wo where it goes. Exactly 1 without one.
    if (const Vec3 ns = ShadingNormalOf(material, hit->ns); ns != hit->n) {
      const float scale = AbsDot(wi, ns) * AbsDot(s->wi, hit->n) / (AbsDot(wi, hit->n) * AbsDot(s->wi, ns));
      if (!std::isfinite(scale)) return;
      weight = weight * scale;
    }
    // At one wavelength, the surface's RGB weight acts as its uplifted spectrum there.
    if (!survive_with(weight, u_survive)) return;
    if (s->specular) {
      ++specular_bounces;
    } else {
      ++diffuse_bounces;
    }
    medium = MediumBeyond(scene, *hit, wi, s->wi, medium);
    ray = Ray{OffsetRayOrigin(hit->p, hit->n, s->wi, scene.ray_epsilon), s->wi};
    ++bounce;
  }
}

std::vector<ShardPhoton> TracePhotons(const Scene& scene, const PhotonShardRequest& request,
                                      const PhotonTraceOptions& options, std::stop_token stop,
                                      Progress progress) {
  CheckRequest(request);
  const SceneData& data = scene.data();
  const float power_scale = static_cast<float>(1.0 / static_cast<double>(request.total_photons));
  const uint64_t chunks = (request.photon_count + kChunkPaths - 1) / kChunkPaths;
  const uint64_t max_photons =
      options.max_photons != 0 ? options.max_photons : contract::SceneLimits().max_shard_photons();
  std::vector<std::vector<ShardPhoton>> per_chunk(chunks);
  std::atomic<uint64_t> stored{0};
  // Each chunk fills its own vector; concatenating them in chunk order gives path-index
  // order, whatever the number of threads or the order chunks finish in.
  tbb::parallel_for(tbb::blocked_range<uint64_t>(0, chunks, 1),
                    [&](const tbb::blocked_range<uint64_t>& range) {
                      for (uint64_t c = range.begin(); c < range.end(); ++c) {
                        if (stop.stop_requested() || stored.load() > max_photons) return;
                        const uint64_t begin = request.first_photon + c * kChunkPaths;
                        const uint64_t end = std::min(request.first_photon + request.photon_count,
                                                      begin + kChunkPaths);
                        for (uint64_t i = begin; i < end; ++i)
                          TracePhotonPath(data, request.map, request.round_offset + i,
                                          power_scale, options, per_chunk[c]);
                        stored += per_chunk[c].size();
                        progress.Advance(end - begin);  // Once a chunk, beside the stop check.
                      }
                    });
  if (stored.load() > max_photons) {
    const char* map = PhotonMapName(request.map);
    throw BadInputError(std::string("photons.photons_per_shard: the ") + map + " map's paths " +
                        std::to_string(request.first_photon) + "+" + std::to_string(request.photon_count) +
                        " store more than the " + std::to_string(max_photons) +
                        " photons a shard may hold (scene_limits.max_shard_photons); lower photons.photons_per_shard");
  }
  std::size_t total = 0;
  for (const auto& c : per_chunk) total += c.size();
  std::vector<ShardPhoton> photons;
  photons.reserve(total);
  for (const auto& c : per_chunk) photons.insert(photons.end(), c.begin(), c.end());
  return photons;
}

std::string TracePhotonShard(const Scene& scene, const PhotonShardRequest& request,
                             std::stop_token stop, Progress progress) {
  const std::vector<ShardPhoton> photons = TracePhotons(scene, request, {}, stop, progress);
  return EncodeShard(request.map, request.first_photon, request.photon_count, photons);
}

}  // namespace farm
