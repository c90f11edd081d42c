#pragma once

// Light transport through media along camera paths (docs/media.md): where a ray travels
// in a medium, what it reaches is attenuated by the medium's transmittance (closed-form,
// or the exact optical depth through a grid), and light from every light scattered once towards the
// ray along the way (single scattering) is added:
//
//   L_ss = integral over t and wi of T(t0, t) sigma_s p(wo, wi) L_light(x(t), wi) T_shadow,
//
// by two strategies over (t, wi), each sample weighed against the other by the power
// heuristic (multiple importance sampling, Veach 1997):
//
//   light   pick a light in proportion to power and a point on it, then a distance along
//           the segment: equiangularly towards point and spot lights and towards the point
//           drawn on a quad or mesh light (media/equiangular.h: it cancels their 1 / d^2,
//           which makes halos clean), by the segment's truncated free-flight density for
//           spheres and distant lights (InScatter);
//   phase   a distance from the truncated free flight, a direction from the phase
//           function, and whatever light the ray along it meets: an area light it hits, or
//           the sun's disc and the environment if it escapes (PhaseInScatter).
//
// The truncated free flight is the medium's (MediumSegment::SampleDistance): closed-form
// in a homogeneous medium, by inverting the exact optical depth in a grid, where sigma_s
// varies along the ray; either way both strategies weigh a sample by the density that
// drew it and the density the other would have drawn it with (MediumSegment::
// DistancePdf), so the power heuristic compares what the samplers really do.
//
// Light sampling alone has infinite variance where a ray grazes an emitter (the estimate
// goes as 1 / h, h the distance from the ray to the point drawn on the light) and misses
// the lobe of a phase function of |g| near 1, which is (1 - |g|)^2 wide; phase sampling
// alone cannot reach point lights and is noisy for small lights. Delta lights are light
// sampled only (weight 1). Shadow rays from media and from surfaces are attenuated by the
// transmittance of the medium they cross.
//
// The phase strategy's ray is also where a volumetric path goes on (multiple scattering
// by path tracing in media of |g| at or above the contract's path_traced_media_min_abs_g,
// homogeneous or grid: scene/multiple_scattering.h); ScatterAt is single scattering at a
// fixed point of such a path, the same two strategies over directions alone.

#include <array>
#include <functional>
#include <vector>
#include <optional>

#include "math/bounds.h"
#include "math/ray.h"
#include "math/rgb.h"
#include "photonmap/photon_map.h"
#include "photonmap/radiance_estimate.h"
#include "scene/lights.h"
#include "scene/media_segments.h"
#include "scene/scene_data.h"

namespace farm {


// The light a light sample reaches x with, times the transmittance of the way; zero where
// something blocks it.
using ShadowTransmittance = std::function<Rgb(const Vec3& x, const LightSample& sample)>;

// How a strategy's samples of single scattering are weighed: against the other strategy
// by the power heuristic (the renderer always takes both), or alone (each is an unbiased
// estimate on its own, which tests compare).
enum class Weighting { kMis, kAlone };

// The power heuristic (exponent 2): the weight of a sample that one strategy drew with
// density `mine` where the other's density is `other`; 0 if mine is not positive.
float PowerHeuristic(float mine, float other);

// The random numbers of one single-scattering sample.
struct InScatterDimensions {
  Vec2 light;  // the point on the light (SampleLi)
  float channel = 0;  // which channel's free-flight density (spheres and distant lights)
  float distance = 0;
};

// One sample of the light strategy: the single-scattered radiance arriving at the ray's
// origin from `light` (picked with probability pick_pmf) along the segment; ray.direction
// unit.
Rgb InScatter(const MediumSegment& segment, const Ray& ray, const Light& light, float pick_pmf,
              const InScatterDimensions& u, const ShadowTransmittance& shadow, Weighting weighting = Weighting::kMis);

// A ray a scattering point sends on, drawn by its phase function, with what it found.
struct ScatteredRay {
  Ray ray;  // from the scattering point along the sampled direction
  std::optional<SurfaceHit> hit;  // the ray's first hit
  // What light arriving at the scattering point along -ray.direction is worth where the
  // caller is (PhaseInScatter: T sigma_s / pdf of the distance, the phase function and
  // its density cancelling; ScatterAt: 1, the caller's throughput holds sigma_s).
  Rgb weight;
  // Light from the lights' own emission scattered once towards the caller, weighed
  // against the light strategy (ScatterAt: and its light sample's share).
  Rgb single;
};

// One sample of the phase strategy along the segment: a distance from the truncated free
// flight (u_channel, u_distance), a direction from the phase function (u_direction), the
// ray along it traced, and the light it meets (LightsAlong), weighed against InScatter's
// density for the same distance and direction. Nothing where the medium does not scatter.
std::optional<ScatteredRay> PhaseInScatter(const SceneData& scene, const MediumSegment& segment, const Ray& ray,
                                           float u_channel, float u_distance, Vec2 u_direction,
                                           Weighting weighting = Weighting::kMis);

// Single scattering at the point x of a volumetric path in `medium` (not null; the scene's
// is told apart from a shape's by its address, as SegmentIn does) towards wo (unit): one
// light sample (u_pick, u_light) and one phase sample (u_direction), each weighed against
// the other over directions (the point is fixed); single is per unit of sigma_s. The phase
// sample's ray is where the path goes on.
ScatteredRay ScatterAt(const SceneData& scene, const Medium* medium, const Vec3& x, const Vec3& wo,
                       float u_pick, Vec2 u_light, Vec2 u_direction, const ShadowTransmittance& shadow);

// The lights a ray meets first (its hit, nothing, or all distant lights if it escapes):
// for each, fn(index in scene.lights, the LightSample that SampleLi would give for the
// ray's direction from its origin), radiance not yet attenuated.
void LightsAlong(const SceneData& scene, const Ray& ray, const std::optional<SurfaceHit>& hit,
                 const std::function<void(int light, const LightSample& sample)>& fn);

// One sample of the radiance scattered towards the ray's origin along the segment by light
// that bounced or scattered before (multiple scattering), from the volume photon map
// (Jensen and Christensen 1998): at a distance drawn from the truncated free-flight
// density, the in-scattered radiance times sigma_s is the photons' power weighed by the
// phase function over the volume of the sphere holding the k nearest,
//
//   sigma_s L_i(x, wo) = sum_p p(wo, wi_p) Phi_p / (4/3 pi r^3),
//
// the farthest of the k setting r and not summed (then the estimate of a uniform density
// is unbiased, as on surfaces: radiance_estimate.h); fewer than k within max_radius: all
// counted, r = max_radius. The sphere's volume is that part of it the point sees (probe
// rays), and its photons those the point sees (SeenBall), so no light is lost where it hangs
// over a wall nor borrowed from beyond one. In a grid, where sigma_s varies within the
// sphere, the photons' density is that of sigma_s L_i: the sum is divided by the integral
// of sigma_t over the seen part instead of its volume (an estimate of albedo x L_i) and
// multiplied by sigma_t at the point, so that scattering is not smeared past the smoke's
// edges (a halo where sigma_s is 0) nor averaged away in its wisps. The
// settings' filter does not apply. ray.direction unit; u_probe turns the probes.
Rgb VolumeInScatter(const SceneData& scene, const MediumSegment& segment, const Ray& ray, const PhotonMap& volume,
                    const RadianceEstimateSettings& estimate, float u_channel, float u_distance, Vec2 u_probe,
                    std::vector<PhotonNeighbour>& scratch);

// The part of the ball of radius r around x that x sees (no surface between), as
// kVolumeProbes probe rays find it: a spherical Fibonacci set of directions turned by u
// (its azimuth and its lattice's offset), each with the distance it sees, up to r.
// fraction is the mean of (depth / r)^3, the seen share of the ball's volume (an unbiased
// estimate of it over the turns; 1 in open space). Sees tells whether x sees a point at
// `offset` from it, so that the photons beyond a wall (in the bright room behind a ceiling)
// are not counted: in open space (fraction 1) every point, else by a ray to it. Judged
// by the probe nearest its direction instead, a point near a wall's plane was counted
// where that probe passed the wall's edge, behind it, and missed where the probe met the
// wall short of it, in front: as much volume either way, but the photons behind a lit
// room's wall are fewer, and the estimate came out 3% low over a ball a wall cuts
// (`SeenBallCountsWhatItsVolumeHolds`).
inline constexpr int kVolumeProbes = 24;
struct SeenBall {
  std::array<Vec3, kVolumeProbes> directions;
  std::array<float, kVolumeProbes> depths;
  float fraction = 1;

  static SeenBall Probe(const SceneData& scene, const Vec3& x, float r, Vec2 u);
  bool Sees(const SceneData& scene, const Vec3& x, const Vec3& offset) const;
  // The integral of f over the seen part of the ball around x: along each probe, two
  // Gauss-Legendre points over its depth (exact for f uniform: the s^2 of the volume
  // element is integrated exactly), each probe standing for 4 pi / kVolumeProbes of the
  // directions.
  double Integral(const Vec3& x, const std::function<float(const Vec3&)>& f) const;
};

}  // namespace farm
