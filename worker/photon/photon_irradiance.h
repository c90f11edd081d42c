#pragma once

// The irradiance precomputed at one global-map photon (Christensen 1999), for the
// precompute phase (irradiance_precompute.h) and for the integrator's bias layer, which
// recomputes it at a gather ray's photon with the companion estimates
// (render/integrator.h).

#include <cstdint>
#include <vector>

#include "photon/surface_estimate.h"
#include "photonmap/photon_map.h"
#include "photonmap/radiance_estimate.h"
#include "sampling/hash.h"
#include "scene/scene_data.h"

namespace farm {

// The estimates a round's precompute takes: the scene's global and caustic estimates as
// ForRound(radius_scale) makes them, the global one a box (Christensen's precompute
// averages over the k nearest with equal weights: the value is read once per gather ray,
// and gathering itself smooths it).
struct PrecomputeEstimates {
  RadianceEstimateSettings global, caustic;
};

// A scene's estimate settings as the photon-map search takes them (the precompute's and
// the integrator's).
inline RadianceEstimateSettings ToRadianceEstimate(const EstimateSettings& s) {
  RadianceEstimateSettings r;
  r.neighbours = s.neighbours;
  r.max_radius = s.max_radius;
  r.cone_k = s.cone_k;
  switch (s.filter) {
    case EstimateFilter::kBox: r.filter = PhotonFilter::kBox; break;
    case EstimateFilter::kCone: r.filter = PhotonFilter::kCone; break;
    case EstimateFilter::kGaussian: r.filter = PhotonFilter::kGaussian; break;
  }
  return r;
}

inline PrecomputeEstimates PrecomputeEstimatesOf(const SceneData& scene, double radius_scale) {
  RadianceEstimateSettings global = ToRadianceEstimate(scene.photons.global_estimate);
  global.filter = PhotonFilter::kBox;
  return {ForRound(global, radius_scale), ForRound(ToRadianceEstimate(scene.photons.caustic_estimate), radius_scale)};
}

inline PrecomputeEstimates Companion(const PrecomputeEstimates& e) {
  return {Companion(e.global), Companion(e.caustic)};
}

// The irradiance at global photon `index` on the side of its normal: the global map's
// estimate there, i itself among the photons (the photon counts itself: final gathering
// reads the value of the photon nearest to a gather hit, and being the nearest leaves, on
// average, one photon fewer around it than a random photon has; counting itself gives
// that one back, so the reads are unbiased at any k, where left out they were 1/k low),
// plus the caustic map's if there is one, each over the surface its disc covers
// (surface_estimate.h, probes scrambled by the photon's index), 0 where not finite.
inline Rgb PhotonIrradiance(const SceneData& scene, const PhotonMap& global, const PhotonMap* caustic,
                            std::uint64_t index, const PrecomputeEstimates& estimates,
                            std::vector<PhotonNeighbour>& scratch) {
  const auto one = [](const Vec3&) { return Rgb(1); };  // a BSDF of 1: irradiance
  const DecodedPhoton photon = global.photon(index);
  const uint32_t seed = static_cast<uint32_t>(Hash(scene.seed, index));
  Rgb e = EstimateOnSurface(scene, global, photon.position, photon.normal, estimates.global, one, scratch, seed);
  if (caustic)
    e += EstimateOnSurface(scene, *caustic, photon.position, photon.normal, estimates.caustic, one, scratch, seed);
  return e.IsFinite() ? e : Rgb();
}

}  // namespace farm
