#pragma once

// The SHARD format (docs/photon-snapshot.md): the photons one emission task stores, as the
// worker uploads them and the coordinator's snapshot builder reads them. The photon tracer
// collects ShardPhotons and calls EncodeShard; DecodeShard exists for tests and tools.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "math/rgb.h"
#include "math/vec3.h"
#include "photonmap/photon_map.h"

namespace farm {

inline constexpr char kShardMagic[8] = {'P', 'F', 'S', 'H', 'A', 'R', 'D', '1'};
inline constexpr std::uint32_t kShardVersion = 1;
inline constexpr std::size_t kShardHeaderSize = 40;
inline constexpr std::size_t kShardRecordSize = 28;

// A photon as the tracer produces it. power is already divided by the paths emitted for the
// map; normal is flipped to the side wi points to (see the format's field table).
struct ShardPhoton {
  Vec3 position;
  Rgb power;
  Vec3 wi;
  Vec3 normal;
};

// A stored shard record with its directions still encoded, exactly as on the wire.
struct ShardRecord {
  Vec3 position;
  Rgb power;
  std::uint16_t wi_oct8 = 0;
  std::uint16_t normal_oct7 = 0;
};

struct DecodedShard {
  PhotonMapKind kind = PhotonMapKind::kGlobal;
  std::uint64_t first_photon = 0;
  std::uint64_t photon_count = 0;
  std::vector<ShardRecord> records;
};

// Serialises one shard. Throws std::invalid_argument if a position is not finite or a
// power component is negative or not finite (the coordinator would refuse the shard).
std::string EncodeShard(PhotonMapKind kind, std::uint64_t first_photon,
                        std::uint64_t photon_count, const std::vector<ShardPhoton>& photons);

// Parses and validates a shard; throws std::runtime_error naming what is wrong.
DecodedShard DecodeShard(std::string_view bytes);

}  // namespace farm
