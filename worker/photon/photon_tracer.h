#pragma once

#include <cstdint>
#include <stop_token>
#include <string>

#include "photonmap/photon_map.h"
#include "scene/scene.h"
#include "util/progress.h"

namespace farm {

struct PhotonShardRequest {
  PhotonMapKind map = PhotonMapKind::kGlobal;
  std::uint64_t first_photon = 0;
  std::uint64_t photon_count = 0;
  // Paths emitted for this map over all shards of the round; each photon's power is divided
  // by it.
  std::uint64_t total_photons = 0;
  // Path indices are counted from here: round r of N paths per round starts at (r-1)·N, so
  // every round traces fresh photons. first_photon and the shard's header count from it.
  std::uint64_t round_offset = 0;
};

// Traces photon paths [first_photon, first_photon + photon_count) of one map and returns
// the photons they store, in photon index order, as shard bytes (docs/photon-snapshot.md).
// A photon's random numbers depend only on (scene seed, map, photon index), so any split of
// the index range into shards gives the same photons. Throws std::invalid_argument for a
// bad request; returns early (result to be discarded) if stop is requested. progress
// advances by the paths of each batch as it is traced: photon_count in all.
std::string TracePhotonShard(const Scene& scene, const PhotonShardRequest& request,
                             std::stop_token stop = {}, Progress progress = {});

}  // namespace farm
