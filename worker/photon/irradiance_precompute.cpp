#include "photon/irradiance_precompute.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "photon/photon_irradiance.h"
#include "photonmap/irradiance_format.h"

namespace farm {
namespace {

void CheckRadiusScale(const char* who, double radius_scale) {
  if (!(radius_scale > 0) || !std::isfinite(radius_scale))
    throw std::invalid_argument(std::string(who) + ": radius_scale must be finite and > 0");
}

}  // namespace

std::vector<Rgb> ComputeIrradiance(const SceneData& scene, const PhotonMap& global,
                                   const PhotonMap* caustic, std::uint64_t first,
                                   std::uint64_t count, double radius_scale,
                                   std::stop_token stop, Progress progress) {
  if (first > global.size() || count > global.size() - first)
    throw std::invalid_argument("ComputeIrradiance: photons " + std::to_string(first) + "+" +
                                std::to_string(count) + " outside the global map's " +
                                std::to_string(global.size()));
  CheckRadiusScale("ComputeIrradiance", radius_scale);
  const PrecomputeEstimates estimates = PrecomputeEstimatesOf(scene, radius_scale);
  std::vector<Rgb> out(count);
  // Each value is written by exactly one task and depends on nothing but i, so the
  // partition (and the thread count) cannot change a bit.
  tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, count, 256),
                    [&](const tbb::blocked_range<std::uint64_t>& r) {
                      std::vector<PhotonNeighbour> scratch;
                      for (std::uint64_t j = r.begin(); j < r.end(); ++j) {
                        if (stop.stop_requested()) return;
                        out[j] = PhotonIrradiance(scene, global, caustic, first + j, estimates, scratch);
                      }
                      progress.Advance(r.size());  // A batch is at most the grain, 256.
                    });
  return out;
}

std::uint64_t IrradianceSites(std::uint64_t photons, int neighbours) {
  const std::uint64_t k = std::uint64_t(std::max(neighbours, 1));
  std::uint64_t sites = 1;  // 2^L - 1 for L = 1, 2, ...
  while (sites < photons && sites * k < kSiteNeighbourShare * photons) sites = 2 * sites + 1;
  return std::min(sites, photons);
}

int GatheredNeighbours(const PhotonMap& global, const RadianceEstimateSettings& estimate) {
  std::vector<int> found;
  std::vector<PhotonNeighbour> scratch;
  for (std::size_t i = 0; i < std::min<std::size_t>(63, global.size()); ++i) {
    global.NearestK(global.photon(i).position, estimate.neighbours, estimate.max_radius, scratch);
    found.push_back(int(scratch.size()));
  }
  if (found.empty()) return estimate.neighbours;
  std::nth_element(found.begin(), found.begin() + found.size() / 8, found.end());
  return found[found.size() / 8];
}

std::string ComputeIrradianceShard(const Scene& scene, const PhotonSnapshot& photons, std::uint32_t part,
                                   std::uint32_t parts, double radius_scale, std::stop_token stop,
                                   Progress progress) {
  if (part >= parts)
    throw std::invalid_argument("ComputeIrradianceShard: part " + std::to_string(part) + " of " +
                                std::to_string(parts));
  CheckRadiusScale("ComputeIrradianceShard", radius_scale);
  const PhotonMap* global = photons.map(PhotonMapKind::kGlobal);
  if (!global) throw std::invalid_argument("ComputeIrradianceShard: the snapshot has no global map");
  const std::uint64_t sites = IrradianceSites(
      global->size(), GatheredNeighbours(*global, PrecomputeEstimatesOf(scene.data(), radius_scale).global));
  const std::uint64_t first = sites * part / parts, end = sites * (part + 1) / parts;
  const std::vector<Rgb> irradiance = ComputeIrradiance(scene.data(), *global, photons.map(PhotonMapKind::kCaustic),
                                                        first, end - first, radius_scale, stop, progress);
  return EncodeIrradianceShard(first, irradiance);
}

}  // namespace farm
