#pragma once

// For tests and in-process benchmarks: a scene's photons of one map traced into an
// in-memory map, what a round's EMIT and BUILD phases give its tiles (minus the snapshot's
// quantisation).

#include <memory>
#include <utility>
#include <vector>

#include "photon/trace_photons.h"
#include "photonmap/memory_photon_map.h"

namespace farm::testing {

// The photons of `paths` paths of map `kind`, from path index round_offset on (a round's
// own photons); null when they store none.
inline std::unique_ptr<MemoryPhotonMap> TraceIntoMemory(const Scene& scene, PhotonMapKind kind, uint64_t paths,
                                                        uint64_t round_offset = 0) {
  std::vector<DecodedPhoton> photons;
  for (const ShardPhoton& p : TracePhotons(scene, {kind, 0, paths, paths, round_offset}))
    photons.push_back({p.position, p.power, p.wi, p.normal});
  if (photons.empty()) return nullptr;
  return std::make_unique<MemoryPhotonMap>(std::move(photons));
}

}  // namespace farm::testing
