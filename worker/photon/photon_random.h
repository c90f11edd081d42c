#pragma once

// The random numbers of one photon path: a counter-based stream hashed from (scene seed,
// map, photon index, draw number), so a photon's path is the same whichever shard, thread
// or worker traces it. Hashing (rather than a Sobol sequence over photon indices) keeps
// every dimension independent of the others without knowing the total photon count.

#include <cstdint>

#include "math/vec3.h"
#include "photonmap/photon_map.h"
#include "sampling/hash.h"
#include "sampling/sobol.h"

namespace farm {

class PhotonRandom {
 public:
  PhotonRandom(uint64_t seed, PhotonMapKind kind, uint64_t photon_index)
      : key_(Hash(seed, static_cast<uint32_t>(kind), photon_index)) {}

  float Get1D() { return FractionToFloat(static_cast<uint32_t>(Hash(key_, draw_++))); }

  Vec2 Get2D() {
    const uint64_t h = Hash(key_, draw_++);
    return {FractionToFloat(static_cast<uint32_t>(h)), FractionToFloat(static_cast<uint32_t>(h >> 32))};
  }

 private:
  uint64_t key_;
  uint64_t draw_ = 0;
};

}  // namespace farm
