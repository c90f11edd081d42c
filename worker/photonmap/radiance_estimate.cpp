#include "photonmap/radiance_estimate.h"

#include <algorithm>

#include "photonmap/filter_kernel.h"

namespace farm {

// Photons whose normal is more than 60 degrees from n are ignored: those on the back of a
// thin wall face the opposite way, those on a perpendicular wall at a corner 90 degrees
// away, while the 7+7-bit normal quantisation (< 2 degrees) and gentle curvature within
// the search radius stay well inside (docs/photon-snapshot.md, "Readers").
inline constexpr float kMinNormalCosine = 0.5f;

Rgb EstimateRadiance(const PhotonMap& map, const Vec3& p, const Vec3& n,
                     const RadianceEstimateSettings& settings,
                     const std::function<Rgb(const Vec3& wi)>& bsdf,
                     std::vector<PhotonNeighbour>& scratch) {
  map.NearestK(p, settings.neighbours, settings.max_radius, scratch);
  float r2 = 0;
  for (const PhotonNeighbour& nb : scratch) r2 = std::max(r2, nb.distance_squared);
  // Jensen's radius: that of the farthest photon found, when k were found. Fewer than k
  // means the whole max_radius disc was searched, so that disc is the area: dividing by
  // the farthest photon's distance instead would blow up one lonely photon near p. No
  // photon gives no estimate.
  if (scratch.size() < static_cast<std::size_t>(settings.neighbours))
    r2 = settings.max_radius * settings.max_radius;
  if (scratch.empty() || !(r2 > 0)) return {};
  const float r = std::sqrt(r2);
  const float cone_k = std::max(settings.cone_k, 1.0f);
  Rgb sum;
  for (const PhotonNeighbour& nb : scratch) {
    DecodedPhoton photon = map.photon(nb.index);
    if (Dot(photon.normal, n) < kMinNormalCosine) continue;
    float w = FilterKernel(settings.filter, std::sqrt(nb.distance_squared) / r, cone_k);
    sum += bsdf(photon.wi) * photon.power * w;
  }
  return sum / r2;
}

}  // namespace farm
