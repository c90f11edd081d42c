#pragma once

// The photon-mapping integrator (Jensen's two-pass method with Christensen's precomputed
// irradiance): a camera ray follows specular bounces (mirror, metal, glass; bounded depth
// and Russian roulette) to the first non-specular surface, where the light leaving it is
// split into
//
//   emitted   its own emission, and that of emitters seen through specular bounces; the
//             environment where the camera ray leaves the scene (unless it is hidden from
//             the camera) or leaves it after specular bounces
//   direct    light_samples shadow rays, to lights picked in proportion to power (area
//             lights and a sun with a disc give soft shadows, point, spot and a sun
//             without one hard). The environment is sampled as a light too, and also
//             reached by the gather rays (the diffuse lobe) and the glossy bounce (the
//             rest) that leave the scene at once: each part of the BSDF weighs the two
//             strategies that sample it by the balance heuristic with their sample counts
//             (multiple importance sampling), and that light counts as direct.
//   caustic   radiance estimate on the caustic map (light -> specular+ -> here), over the
//             surface its disc covers (photon/surface_estimate.h: no light lost at edges)
//   indirect  FINAL_GATHER: gather_rays cosine-weighted rays (Malley over the concentric
//             disk, stratified); where a gather ray lands on a diffuse surface (after at
//             most kGatherSpecularDepth specular bounces) its radiance is albedo / pi times
//             (one shadow-ray sample of the direct irradiance there + the irradiance
//             precomputed at the nearest photon facing the same way and visible from it).
//             A glossy surface adds its glossy lobe by one sampled ray per camera sample;
//             the diffuse surface that ray reaches is shaded in full with
//             secondary_gather_rays gather rays.
//             PHOTON_MAP (or a snapshot without irradiance): the global map's radiance
//             estimate seen directly (over the surface its disc covers, as the caustic's).
//
// each weighted by the throughput of the specular path, so the four (and the volume layer
// below) add up to the beauty.
// Glass reflects and refracts: at a camera path's first three specular bounces (SPLIT, the
// default of Sampling.specular) the path splits and follows both, each branch weighted by
// its Fresnel share (the seed renderer's Whitted-style glass, so one sample per pixel shows
// a glass sphere without speckle); later bounces, and every bounce in CHOOSE mode, follow
// one of the two at random with the Fresnel probabilities. Branches share the sample's
// dimensions, each turned by a rotation hashed from its own key, so a sample's value still
// depends only on (seed, pixel, sample index).
// A smooth principled surface with a diffuse base (specular and reflecting at once) is
// shaded for its base like any diffuse surface, and the path goes on through its lobe;
// where a gather ray lands on one, its albedo reflects the irradiance as if diffuse.
//
// Every hit reads its material's textures (scene/surface_shading.h) over the footprint of
// the ray's cone (texture/footprint.h): camera rays start with the pixel's spread angle,
// which specular bounces and the glossy bounce pass on; gather rays start where the cone
// is at their origin, spread by sqrt(2 pi / gather_rays), the side of each one's share of
// the hemisphere, and read with the isotropic filter (TextureFilter). Only camera paths
// read emission textures: nothing else counts emission.
// The terms cover disjoint sets of paths: shadow rays are blocked by glass, whose light
// arrives through the caustic map; the global map (and so the precomputed irradiance)
// holds no direct light; gather rays ignore the emitters they hit (direct light covers
// them) and read no caustic at the shading point (the caustic map does).
//
// Participating media (docs/media.md, media_transport.h): each branch of a camera path
// travels in a medium (the scene's, a shape's interior one it refracted into, or none); a
// segment in one attenuates what it reaches and adds the light scattered along it towards
// the camera (the volume layer): once, from light samples and phase-function samples
// weighed by MIS, and more than once, read from the volume photon map or, in a medium of
// |g| at or above the contract's path_traced_media_min_abs_g, by a volumetric path from
// each phase sample (VolumePath); the shadow rays of the points it shades are attenuated.
// Photons travel through media too (photon_tracer.h), so the global and caustic maps hold
// light as media let it through. A gather ray in a medium is attenuated up to its first
// hit, and eight of a point's gather rays (chosen at random, weighted to stay unbiased)
// gather the light scattered along that first segment likewise; past a specular bounce it
// sees vacuum. A segment reads the volume photon map twice, whatever its light samples. A
// scene without media draws exactly the numbers it drew before media existed.
//
// Light leaking at walls and corners: the remedy is that no direct light is ever read from
// photons (it is sampled by a shadow ray at every gather hit, exact to the corner and
// blocked by any wall), and the precomputed irradiance is read only from a photon whose
// normal is within 60 degrees of the hit's and that a shadow ray shows visible from it, so
// neither the other side of a thin wall nor the perpendicular wall of a corner lends its
// light. This replaces Jensen's "short gather rays recurse" rule, which needs direct light
// in the photon estimate to matter.

#include <string>
#include <vector>

#include "math/ray.h"
#include "math/rgb.h"
#include "photon/photon_irradiance.h"
#include "photonmap/photon_map.h"
#include "photonmap/radiance_estimate.h"
#include "render/media_transport.h"
#include "sampling/pixel_sampler.h"
#include "scene/scene_data.h"
#include "texture/footprint.h"

namespace farm {

// Specular bounces a gather ray may follow to the diffuse surface it lights.
inline constexpr int kGatherSpecularDepth = 4;

// Everything one camera sample contributes to its pixel; the tile renderer averages these
// into the channels of RenderChannels().
struct SampleResult {
  Rgb radiance;  // beauty = emitted + direct + indirect + caustic + volume
  Rgb emitted, direct, indirect, caustic;
  // Light that media scattered towards the camera path's segments, once (from the lights)
  // or more (from the volume photon map): the volume layer, graded apart from surfaces.
  Rgb volume;
  // The bias layer (image/error_estimate.h): what radiance would gain if every photon
  // estimate on the path took its companion (Companion in radiance_estimate.h: twice the
  // neighbours, twice the area, the same photons) instead, everything else the same.
  Rgb bias;
  // 1 if the camera ray hit geometry or sees an environment visible to the camera, 0 if
  // it escaped into black.
  float alpha = 0;
  bool hit = false;  // whether the camera ray hit geometry
  // Of the first surface the camera ray hits (valid when hit).
  Rgb albedo;
  Vec3 normal;      // unit shading normal, on the side of the surface the camera sees
  float depth = 0;  // distance along the camera ray
  // The irradiance from the lights but the environment on the surfaces the path's first
  // branch shaded, times its throughput: direct (shadowed, over their geometric normals,
  // from the same light samples as direct) and focused by specular surfaces (the caustic
  // estimate's, its reflected radiance over the surface's diffuse albedo). Shadows and
  // caustics change it, textures and normal maps do not, nor the noise of sampling the
  // sky. Edge anti-aliasing reads it.
  Rgb light_irradiance;
  // An id of the surfaces (shape, mesh part, material) the path's first branch hit, the
  // first one and those it saw through specular bounces (the refracted branch where glass
  // splits), and of the emitters any branch met (a light reflected in glass); 0 if the
  // camera ray hit nothing. Edge anti-aliasing compares it between samples and pixels
  // (render/edge_detect.h).
  uint32_t surface = 0;
  // The camera ray's hit's own normal (interpolated, not normal-mapped), on the side the
  // camera sees: edge anti-aliasing's crease cue, which a normal map's detail must not move.
  Vec3 surface_normal;
  // Whether the path (a branch of it) reached a non-specular surface and shaded it: such a
  // sample is black only where no light reaches.
  bool shaded = false;
  // Whether a light term came out NaN or infinite (and was dropped, so radiance is finite).
  bool nonfinite = false;
};

// How much a camera sample shades (PhotonMappingIntegrator::Li).
struct SampleEffort {
  // The share, in (0, 1], of the scene's light samples and gather rays its shading points
  // take (at least one of each).
  float share = 1;
  // Sample `index` of `count` samples of a pixel that draw the light samples and gather rays
  // of their first branch's shading points as one stratified set keyed by `seed`, each its
  // own run of it (so that few rays a sample still stratify over the pixel); count 0: each
  // shading point draws a set of its own.
  uint32_t seed = 0, index = 0, count = 0;
};

// The job's photon maps (any may be null) with their estimate settings.
struct PhotonMaps {
  const PhotonMap* global = nullptr;
  const PhotonMap* caustic = nullptr;
  const PhotonMap* volume = nullptr;
  // The global map's photons that carry precomputed irradiance, as a map whose photon i is
  // the global map's photon i (PhotonSnapshot::irradiance_sites; in tests, often the global
  // map itself): what final gathering reads. Null: no final gathering.
  const PhotonMap* irradiance = nullptr;
  RadianceEstimateSettings global_estimate;
  RadianceEstimateSettings caustic_estimate;
  RadianceEstimateSettings volume_estimate;
};

class PhotonMappingIntegrator {
 public:
  // radius_scale shrinks every photon estimate's radius and k (progressive rounds:
  // RoundSettings::radius_scale, ForRound in radiance_estimate.h). bias_layer: whether each
  // photon estimate also takes its companion for SampleResult::bias (which stays 0
  // otherwise): a second k-nearest search and coverage of twice the area.
  PhotonMappingIntegrator(const SceneData& scene, const PhotonMaps& maps,
                          double radius_scale = 1.0, bool bias_layer = false);

  // Consumes sampler dimensions after the camera's: seven per specular bounce, drawn
  // before any early exit, so a bounce's dimensions do not depend on what earlier bounces
  // hit (the branches of a split path share them).
  // Gather rays and shadow rays take stratified (Owen-scrambled Sobol) points whose
  // scrambles come from those dimensions, so the result depends only on (seed, pixel,
  // sample index). scratch is reused between calls (one per thread). Never returns NaN or
  // infinity.
  // effort: the share of the scene's light samples and gather rays the sample's shading
  // points take (ShadingCount), 1 for a pixel's own samples, less for the extra samples
  // edge anti-aliasing or adaptive sampling adds to a pixel, which are there to resolve
  // what the pixel covers (its edges, the highlights it sees in glass and mirrors) rather
  // than the light at each point; those draw their rays as one stratified set over the
  // pixel (SampleEffort). A branch of a split path takes its Fresnel share of the sample's
  // share too, so the faint reflection in glass takes few rays. Each count stays at least
  // 1, so every estimate is unbiased whatever the effort.
  SampleResult Li(const Ray& camera_ray, PixelSampler& sampler, std::vector<PhotonNeighbour>& scratch,
                  const SampleEffort& effort = {}) const;

  // Only what edge anti-aliasing reads of a camera ray (SampleResult's surface, hit,
  // surface_normal, depth and emitted; render/edge_detect.h): the path walked as Li walks
  // it, every branch of it, drawing the same dimensions and so making the same specular
  // choices, with no light found along it but what the surfaces it meets emit and the
  // environment it escapes to (a light seen directly or in a mirror). A small part of a
  // sample's cost: a ray per specular bounce of each branch.
  SampleResult Cues(const Ray& camera_ray, PixelSampler& sampler) const;

  // Whether indirect light comes from final gathering (FINAL_GATHER and a global map with
  // precomputed irradiance) rather than the global map seen directly.
  bool final_gathering() const { return final_gather_; }

  std::string ToString() const;

 private:
  struct Shading;
  struct PathBranch;
  struct BounceDimensions;
  struct Branches;
  struct PointSet;
  // What a shading point samples: its light samples, and the BSDF-sampled rays it takes
  // besides: gather rays of the diffuse lobe (0 for none), whether a glossy bounce
  // follows, and the gather rays of the point that bounce lands on.
  struct Strategies {
    uint32_t gather_rays = 0;
    bool glossy_bounce = false;
    uint32_t light_samples = 0;
    uint32_t secondary_gather_rays = 0;
    // The pixel's shared set of light samples and gather rays the point draws its run of,
    // if any (SampleEffort's seed, index and count).
    SampleEffort strata;
  };
  // A camera path's branch's shading points' strategies (Li's effort's share times the
  // branch's split share; the pixel's shared set on the first branch).
  Strategies CameraStrategies(const PathBranch& branch) const;
  // Light found by a BSDF-sampled ray: direct (the environment it escaped to) and indirect,
  // and the bias layer's share of it (SampleResult::bias).
  struct LightSplit {
    Rgb direct, indirect, bias;
  };

  // One bounce of one branch of a camera path: adds what its hit emits and reflects to
  // result, and the branches that go on from it to next (two where glass splits it).
  // With light false, only the cues, the emitted light and the branches (Cues).
  void Bounce(const PathBranch& branch, int depth, const BounceDimensions& u, std::vector<PhotonNeighbour>& scratch,
              bool light, SampleResult& result, Branches& next) const;
  // Li, or with light false Cues.
  SampleResult Trace(const Ray& camera_ray, PixelSampler& sampler, std::vector<PhotonNeighbour>& scratch,
                     bool light, const SampleEffort& effort) const;
  // Direct + caustic + indirect leaving a non-specular hit along wo, and their bias layer
  // (SampleResult::bias); no gather rays means the global map's estimate instead of
  // gathering. seed scrambles the stratified points. irradiance, if not null, receives the
  // irradiance from the lights, direct (DirectLight's) and caustic (SampleResult::
  // light_irradiance).
  void Shade(const Shading& at, const Strategies& strategies, uint32_t seed,
             std::vector<PhotonNeighbour>& scratch, Rgb& direct, Rgb& caustic, Rgb& indirect, Rgb& bias,
             Rgb* irradiance = nullptr) const;
  // A photon estimate of map at a shading point over the surface its disc covers
  // (surface_estimate.h), reflected by its BSDF; adds its companion's difference from it
  // (Companion, the same coverage probes) to bias.
  Rgb EstimateWithCompanion(const PhotonMap& map, const Shading& at, const RadianceEstimateSettings& estimate,
                            const RadianceEstimateSettings& companion, uint32_t seed,
                            std::vector<PhotonNeighbour>& scratch, Rgb& bias) const;
  // Light samples a shading point takes at full effort.
  uint32_t LightSampleCount() const;
  // The average of strategies.light_samples light samples of the reflected direct radiance
  // along wo, the environment's weighted against `strategies`. irradiance, if not null, receives
  // the same samples' estimate of the irradiance over the geometric normal (no BSDF, no
  // weighting), shadows included, from every light but the environment.
  Rgb DirectLight(const Shading& at, const Strategies& strategies, uint32_t seed, Rgb* irradiance = nullptr) const;
  // The density with which light sampling (DirectLight) picks the environment along w.
  float EnvironmentLightPdf(const Vec3& w) const;
  // The density with which GlossyBounce samples wi; 0 where it has no glossy lobe.
  float GlossyBouncePdf(const Shading& at, const Vec3& wi) const;
  // Diffuse-lobe radiance along wo from strategies.gather_rays gather rays: indirect, plus
  // the environment's share of direct light where a ray escapes.
  LightSplit Gather(const Shading& at, const Strategies& strategies, uint32_t seed,
                    std::vector<PhotonNeighbour>& scratch) const;
  // Radiance a gather ray brings back (see the file comment); i indexes its stratified
  // points; cone is the ray's (footprint.h); seed its specular choices'. escaped: the ray
  // left the scene before any bounce.
  // medium: the one around the shading point, which the landing point's shadow ray crosses.
  // companion, if not null, receives what the ray's radiance would gain if the precomputed
  // irradiance it reads were its companion's (LandingIrradiance).
  Rgb GatherRay(Ray ray, RayCone cone, uint32_t i, const PointSet& points, uint32_t seed, const Medium* medium,
                std::vector<PhotonNeighbour>& scratch, bool& escaped, Rgb* companion = nullptr) const;
  // One sample of the irradiance from the lights at a shading point, on its side.
  Rgb DirectIrradiance(const Shading& at, float u_light, Vec2 u_point) const;
  // The irradiance at a diffuse surface where a gather ray (or a volumetric path) lands:
  // one light sample's, and that precomputed at the nearest photon facing the same way and
  // visible from it when final gathering. companion, if not null, receives the companion's
  // irradiance at that photon (PhotonIrradiance with the companion estimates, computed
  // here) less the precomputed value it read.
  Rgb LandingIrradiance(const Shading& at, float u_light, Vec2 u_point, std::vector<PhotonNeighbour>& scratch,
                        Rgb* companion = nullptr) const;
  // The glossy lobe of a glossy first hit by one ray, its diffuse landing point shaded in
  // full with strategies' secondary gathering and light samples (indirect), or the
  // environment it escapes to (direct).
  LightSplit GlossyBounce(const Shading& at, const Strategies& strategies, Vec2 u, uint32_t seed,
                          std::vector<PhotonNeighbour>& scratch) const;

  // A light sample's light where it reaches a shading point: attenuated by the medium
  // around the point on the way.
  Rgb Arriving(const Shading& at, const LightSample& ls) const;
  // The average of `count` samples of the light scattered towards the ray's origin along
  // the segment (media_transport.h): single scattering from the lights (direct: count
  // light samples and count phase samples, weighed by MIS) and multiple scattering
  // (indirect) from the volume map, or by a volumetric path from each phase sample where
  // the medium's is path traced (scene/multiple_scattering.h). With the bias layer and
  // along a camera path (camera_path), the first volume estimate's companion stands for
  // all of the segment's (the bias layer's share); a gather ray's segment, whose light is
  // one of many a shading point averages, takes none (docs/error-estimate.md).
  LightSplit InScattered(const MediumSegment& segment, const Ray& ray, uint32_t seed, uint32_t count,
                         bool camera_path, std::vector<PhotonNeighbour>& scratch) const;
  // The light arriving at ray.origin along -ray.direction that is not the lights' own
  // emission seen straight along the ray (single scattering took that): a volumetric path
  // tracer from a scattering point in `medium`, ray's first hit given. Each scattering on
  // the way takes single scattering by MIS (ScatterAt) and goes on by the phase function;
  // a specular surface is followed by one sampled direction and what the ray beyond it
  // meets emitting is counted; a diffuse surface ends the path with the light it reflects,
  // as where a gather ray lands (LandingIrradiance). Russian roulette on the throughput,
  // at most kMaxVolumePathVertices vertices; seed draws every number. Adds the bias
  // layer's share to bias.
  Rgb VolumePath(Ray ray, std::optional<SurfaceHit> hit, const Medium* medium, uint32_t seed,
                 std::vector<PhotonNeighbour>& scratch, Rgb& bias) const;
  // The light a sample reaches a point in `medium` with: blocked by any surface,
  // attenuated by the medium (the scene's clipped to its ball).
  ShadowTransmittance ShadowIn(const Medium* medium) const;

  const SceneData& scene_;
  PhotonMaps maps_;
  // The companions of maps_' estimates and of the round's precompute (the bias layer), if
  // it is rendered.
  bool bias_layer_ = false;
  RadianceEstimateSettings global_companion_, caustic_companion_, volume_companion_;
  PrecomputeEstimates precompute_companion_;
  bool final_gather_ = false;
  bool single_delta_light_ = false;
  // Whether some light is not a delta light: a ray can meet it, so single scattering takes
  // phase samples beside its light samples.
  bool hittable_lights_ = false;
  float lookup_radius_ = 0;
};

}  // namespace farm
