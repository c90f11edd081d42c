#pragma once

#include <cstdint>
#include <stop_token>
#include <string>
#include <vector>

#include "math/rgb.h"
#include "photonmap/photon_map.h"
#include "photonmap/photon_snapshot.h"
#include "scene/scene.h"
#include "scene/scene_data.h"
#include "util/progress.h"

namespace farm {

// Irradiance at global-map photons [first_photon, first_photon + photon_count), in the
// snapshot's tree order (Christensen 1999), as irradiance-shard bytes
// (docs/photon-snapshot.md); the coordinator merges the shards into the snapshot so that
// final gathering reads one precomputed value per gather ray instead of a k-nearest
// estimate. radius_scale shrinks the search radius as in RoundSettings. Deterministic.
// progress advances as in ComputeIrradiance.
std::string ComputeIrradianceShard(const Scene& scene, const PhotonSnapshot& photons,
                                   std::uint64_t first_photon, std::uint64_t photon_count,
                                   double radius_scale, std::stop_token stop = {},
                                   Progress progress = {});

// What ComputeIrradianceShard encodes, for any PhotonMap (tests use in-memory maps): for
// each photon i of the range, the irradiance on the side of its normal from the global
// map's k nearest photons, i itself among them (box filter, the scene's global estimate as
// ForRound(radius_scale) makes it: radius and k shrink with the rounds) plus, if there is
// a caustic map, its estimate (the scene's caustic estimate, likewise), each over the
// surface its disc covers (surface_estimate.h: no light lost at edges): all the light the global map's photon holds but direct light, which final
// gathering samples with shadow rays at the gather hit instead. Parallel (TBB) and
// deterministic: each value depends only on the maps and i. Throws std::invalid_argument
// for a range outside the map or a radius_scale that is not finite and > 0. progress
// advances by the photons of each batch once their values are computed: photon_count in
// all.
std::vector<Rgb> ComputeIrradiance(const SceneData& scene, const PhotonMap& global,
                                   const PhotonMap* caustic, std::uint64_t first_photon,
                                   std::uint64_t photon_count, double radius_scale,
                                   std::stop_token stop = {}, Progress progress = {});

}  // namespace farm
