#pragma once

// The photon tracer behind TracePhotonShard, with the photons still decoded: for tests,
// tools and the benchmark.

#include <cstdint>
#include <stop_token>
#include <vector>

#include "photon/photon_emission.h"
#include "photon/photon_random.h"
#include "photon/photon_tracer.h"
#include "photonmap/shard_format.h"
#include "scene/scene_data.h"

namespace farm {

struct PhotonTraceOptions {
  // Also store photons at the first non-specular hit of global paths (Jensen's original
  // global map, with direct light). The farm never sets it: direct light comes from shadow
  // rays. Tests use it to check emitted flux against closed forms of direct irradiance.
  bool store_direct = false;
  // The most photons the request's paths may store; 0 selects the contract's
  // scene_limits.max_shard_photons. A shard that stores more would hold the worker's memory
  // (28 bytes a photon in the shard, about as much again while it is traced): tracing
  // stops and throws BadInputError saying to lower photons_per_shard.
  std::uint64_t max_photons = 0;
  // The wavelength, nm, of every photon a dispersive surface makes monochromatic in RGB
  // mode (in spectral mode the photon keeps its hero); 0 draws it (the farm). Tests fix it
  // to measure a prism's deviation at one wavelength.
  double wavelength_nm = 0;
};

// Appends the photons path `index` of the map stores, in bounce order. power_scale is
// 1 / (paths emitted for the map).
void TracePhotonPath(const SceneData& scene, PhotonMapKind kind, uint64_t index,
                     float power_scale, const PhotonTraceOptions& options,
                     std::vector<ShardPhoton>& out);

// The rest of a path once emitted, drawing from the path's random numbers where EmitPhoton
// left them (tests trace photons emitted otherwise, to compare emission schemes).
void ContinuePhotonPath(const SceneData& scene, PhotonMapKind kind, const PhotonRay& emitted,
                        PhotonRandom& random, float power_scale, const PhotonTraceOptions& options,
                        std::vector<ShardPhoton>& out);

// The photons of request's paths in path-index order, traced in parallel over chunks of
// the range. Throws std::invalid_argument for a bad request, BadInputError (naming the
// setting to lower) once the paths store more than options.max_photons; returns early
// (partial) if stop is requested. progress advances by each chunk's paths once they are traced.
std::vector<ShardPhoton> TracePhotons(const Scene& scene, const PhotonShardRequest& request,
                                      const PhotonTraceOptions& options = {},
                                      std::stop_token stop = {}, Progress progress = {});

}  // namespace farm
