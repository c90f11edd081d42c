#pragma once

// The photon-mapping integrator (Jensen's two-pass method, with the global map seen
// directly until final gathering arrives): a camera ray follows specular bounces (mirror,
// glass by a Fresnel choice, metal; bounded depth and Russian roulette) to the first
// non-specular surface, where the light leaving it is split into
//
//   emitted   its own emission, and that of emitters seen through specular bounces
//   direct    one light sample per camera sample, by a light picked in proportion to
//             power, with a shadow ray (area lights give soft shadows, point and sun hard)
//   caustic   radiance estimate on the caustic map (light -> specular+ -> here)
//   indirect  radiance estimate on the global map (light -> ... diffuse ... -> here)
//
// each weighted by the throughput of the specular path, so the four add up to the beauty.
// The three light-transport terms cover disjoint sets of paths: shadow rays are blocked by
// glass, whose light arrives through the caustic map, and the global map holds no direct
// light and no pure caustics.

#include <string>
#include <vector>

#include "math/ray.h"
#include "math/rgb.h"
#include "photonmap/photon_map.h"
#include "photonmap/radiance_estimate.h"
#include "sampling/pixel_sampler.h"
#include "scene/scene_data.h"

namespace farm {

// Everything one camera sample contributes to its pixel; the tile renderer averages these
// into the channels of RenderChannels().
struct SampleResult {
  Rgb radiance;  // beauty = emitted + direct + indirect + caustic
  Rgb emitted, direct, indirect, caustic;
  float alpha = 0;  // 1 if the camera ray hit geometry, 0 if it escaped
  // Of the first surface the camera ray hits (valid when alpha is 1).
  Rgb albedo;
  Vec3 normal;      // unit, facing the camera
  float depth = 0;  // distance along the camera ray
};

// The job's photon maps (either may be null) with their estimate settings.
struct PhotonMaps {
  const PhotonMap* global = nullptr;
  const PhotonMap* caustic = nullptr;
  RadianceEstimateSettings global_estimate;
  RadianceEstimateSettings caustic_estimate;
};

RadianceEstimateSettings ToRadianceEstimate(const EstimateSettings& settings);

class PhotonMappingIntegrator {
 public:
  PhotonMappingIntegrator(const SceneData& scene, const PhotonMaps& maps)
      : scene_(scene), maps_(maps) {}

  // Consumes sampler dimensions after the camera's; scratch is reused between calls (one per
  // thread). Never returns NaN or infinity.
  SampleResult Li(const Ray& camera_ray, PixelSampler& sampler,
                  std::vector<PhotonNeighbour>& scratch) const;

  std::string ToString() const;

 private:
  // Reflected radiance along wo at hit from one light sample.
  Rgb SampleDirect(const SurfaceHit& hit, const Vec3& wo, const Material& material, float u_light,
                   Vec2 u_point) const;

  const SceneData& scene_;
  PhotonMaps maps_;
};

}  // namespace farm
