#include "photon/irradiance_precompute.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

#include "photon/photon_irradiance.h"
#include "photonmap/irradiance_format.h"

namespace farm {

std::vector<Rgb> ComputeIrradiance(const SceneData& scene, const PhotonMap& global,
                                   const PhotonMap* caustic, std::uint64_t first,
                                   std::uint64_t count, double radius_scale,
                                   std::stop_token stop, Progress progress) {
  if (first > global.size() || count > global.size() - first)
    throw std::invalid_argument("ComputeIrradiance: photons " + std::to_string(first) + "+" +
                                std::to_string(count) + " outside the global map's " +
                                std::to_string(global.size()));
  if (!(radius_scale > 0) || !std::isfinite(radius_scale))
    throw std::invalid_argument("ComputeIrradiance: radius_scale must be finite and > 0");
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

std::string ComputeIrradianceShard(const Scene& scene, const PhotonSnapshot& photons,
                                   std::uint64_t first_photon, std::uint64_t photon_count,
                                   double radius_scale, std::stop_token stop,
                                   Progress progress) {
  const PhotonMap* global = photons.map(PhotonMapKind::kGlobal);
  if (!global) throw std::invalid_argument("ComputeIrradianceShard: the snapshot has no global map");
  const std::vector<Rgb> irradiance =
      ComputeIrradiance(scene.data(), *global, photons.map(PhotonMapKind::kCaustic), first_photon,
                        photon_count, radius_scale, stop, progress);
  return EncodeIrradianceShard(first_photon, irradiance);
}

}  // namespace farm
