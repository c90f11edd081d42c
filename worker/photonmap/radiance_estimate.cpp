#include "photonmap/radiance_estimate.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "photonmap/filter_kernel.h"

namespace farm {

// Photons whose normal is more than 60 degrees from n are ignored: those on the back of a
// thin wall face the opposite way, those on a perpendicular wall at a corner 90 degrees
// away, while the 7+7-bit normal quantisation (< 2 degrees) and gentle curvature within
// the search radius stay well inside (docs/photon-snapshot.md, "Readers").
inline constexpr float kMinNormalCosine = 0.5f;

RadianceEstimateSettings ForRound(RadianceEstimateSettings s, double radius_scale) {
  s.max_radius = static_cast<float>(s.max_radius * radius_scale);
  const double k = std::round(s.neighbours * radius_scale * radius_scale);
  s.neighbours = std::min(s.neighbours, std::max(kMinRoundNeighbours, static_cast<int>(k)));
  return s;
}

RadianceEstimateSettings Companion(RadianceEstimateSettings s) {
  s.max_radius = static_cast<float>(s.max_radius * std::numbers::sqrt2);
  s.neighbours *= 2;
  return s;
}

Rgb EstimateRadiance(const PhotonMap& map, const Vec3& p, const Vec3& n,
                     const RadianceEstimateSettings& settings,
                     const std::function<Rgb(const Vec3& wi)>& bsdf,
                     std::vector<PhotonNeighbour>& scratch) {
  return EstimateRadianceOverDisc(map, p, n, settings, bsdf, scratch).radiance;
}

DiscEstimate EstimateRadianceOverDisc(const PhotonMap& map, const Vec3& p, const Vec3& n,
                                      const RadianceEstimateSettings& settings,
                                      const std::function<Rgb(const Vec3& wi)>& bsdf,
                                      std::vector<PhotonNeighbour>& scratch) {
  const std::size_t k = static_cast<std::size_t>(std::max(settings.neighbours, 1));
  map.NearestK(p, static_cast<int>(k), settings.max_radius, scratch);
  if (scratch.empty()) return {};
  // Jensen's radius: that of the farthest photon found, when k were found (a tie is broken
  // by index, so the photon left out does not depend on the search's order). Fewer than k
  // means the whole max_radius disc was searched, so that disc is the area: dividing by
  // the farthest photon's distance instead would blow up one lonely photon near p.
  std::size_t farthest = scratch.size();
  float r2 = settings.max_radius * settings.max_radius;
  if (scratch.size() >= k) {
    farthest = 0;
    for (std::size_t i = 1; i < scratch.size(); ++i) {
      const PhotonNeighbour& a = scratch[i];
      const PhotonNeighbour& b = scratch[farthest];
      if (a.distance_squared > b.distance_squared ||
          (a.distance_squared == b.distance_squared && a.index > b.index))
        farthest = i;
    }
    r2 = scratch[farthest].distance_squared;
  }
  if (!(r2 > 0)) return {};
  const float r = std::sqrt(r2);
  const float cone_k = std::max(settings.cone_k, 1.0f);
  Rgb sum;
  for (std::size_t i = 0; i < scratch.size(); ++i) {
    if (i == farthest) continue;
    const PhotonNeighbour& nb = scratch[i];
    DecodedPhoton photon = map.photon(nb.index);
    if (Dot(photon.normal, n) < kMinNormalCosine) continue;
    float w = FilterKernel(settings.filter, std::sqrt(nb.distance_squared) / r, cone_k);
    sum += bsdf(photon.wi) * photon.power * w;
  }
  return {sum / r2, r};
}

}  // namespace farm
