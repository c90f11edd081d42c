#include "photon/irradiance_precompute.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

#include "photon/surface_estimate.h"
#include "photonmap/irradiance_format.h"
#include "photonmap/radiance_estimate.h"
#include "sampling/hash.h"

namespace farm {
namespace {

RadianceEstimateSettings Scaled(const EstimateSettings& s, double radius_scale, bool force_box) {
  RadianceEstimateSettings r;
  r.neighbours = s.neighbours;
  r.max_radius = s.max_radius;
  r.cone_k = s.cone_k;
  switch (s.filter) {
    case EstimateFilter::kBox: r.filter = PhotonFilter::kBox; break;
    case EstimateFilter::kCone: r.filter = PhotonFilter::kCone; break;
    case EstimateFilter::kGaussian: r.filter = PhotonFilter::kGaussian; break;
  }
  // Christensen's precompute averages over the k nearest with equal weights: the value is
  // read once per gather ray, and gathering itself smooths it.
  if (force_box) r.filter = PhotonFilter::kBox;
  return ForRound(r, radius_scale);
}

Rgb One(const Vec3&) { return Rgb(1); }  // a BSDF of 1 turns the estimate into irradiance

}  // namespace

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
  const RadianceEstimateSettings global_settings =
      Scaled(scene.photons.global_estimate, radius_scale, /*force_box=*/true);
  const RadianceEstimateSettings caustic_settings =
      Scaled(scene.photons.caustic_estimate, radius_scale, /*force_box=*/false);
  std::vector<Rgb> out(count);
  // Each value is written by exactly one task and depends on nothing but i, so the
  // partition (and the thread count) cannot change a bit.
  tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, count, 256),
                    [&](const tbb::blocked_range<std::uint64_t>& r) {
                      std::vector<PhotonNeighbour> scratch;
                      for (std::uint64_t j = r.begin(); j < r.end(); ++j) {
                        if (stop.stop_requested()) return;
                        const DecodedPhoton photon = global.photon(first + j);
                        // The photon counts itself: final gathering reads the value of the
                        // photon nearest to a gather hit, and being the nearest leaves, on
                        // average, one photon fewer around it than a random photon has;
                        // counting itself gives that one back, so the reads are unbiased at
                        // any k (left out, they were 1/k low: 8% at k = 8). Each estimate is
                        // over the surface its disc covers (surface_estimate.h), no light
                        // lost at edges and corners.
                        const uint32_t seed = static_cast<uint32_t>(Hash(scene.seed, first + j));
                        Rgb e = EstimateOnSurface(scene, global, photon.position, photon.normal,
                                                  global_settings, One, scratch, seed);
                        if (caustic)
                          e += EstimateOnSurface(scene, *caustic, photon.position, photon.normal,
                                                 caustic_settings, One, scratch, seed);
                        out[j] = e.IsFinite() ? e : Rgb();
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
