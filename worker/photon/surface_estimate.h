#pragma once

// A photon estimate over the surface its disc covers (scene/disc_coverage.h), not over the
// whole disc: no light lost where the disc hangs over an edge.

#include <cstdint>
#include <functional>
#include <numbers>
#include <vector>

#include "photonmap/filter_kernel.h"
#include "photonmap/radiance_estimate.h"
#include "scene/disc_coverage.h"
#include "scene/scene_data.h"

namespace farm {

// EstimateRadiance (radiance_estimate.h) divided by the share of its disc that is surface,
// each probe weighted by the estimate's filter (so a cone or Gaussian estimate is
// normalised over the covered part of its kernel). seed scrambles the probes.
inline Rgb EstimateOnSurface(const SceneData& scene, const PhotonMap& map, const Vec3& p, const Vec3& n,
                             const RadianceEstimateSettings& settings,
                             const std::function<Rgb(const Vec3& wi)>& bsdf,
                             std::vector<PhotonNeighbour>& scratch, uint32_t seed) {
  const DiscEstimate e = EstimateRadianceOverDisc(map, p, n, settings, bsdf, scratch);
  if (e.radiance.IsBlack()) return e.radiance;
  const float cone_k = std::max(settings.cone_k, 1.0f);
  const auto kernel = [&](float u) {
    return FilterKernel(settings.filter, u, cone_k) * std::numbers::pi_v<float>;
  };
  return e.radiance / DiscCoverage(scene, p, n, e.radius, seed,
                                   settings.filter == PhotonFilter::kBox ? std::function<float(float)>() : kernel);
}

}  // namespace farm
