#pragma once

// The IRRADIANCE SHARD format (docs/photon-snapshot.md): what a worker returns for one
// precompute task, the irradiance at global-map photons [first_photon, first_photon +
// photon_count) in the snapshot's tree order, 4 bytes a photon (RGB9E5 relative to the
// shard's largest component). The coordinator merges the shards into the snapshot.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "math/rgb.h"

namespace farm {

inline constexpr std::size_t kIrradianceShardHeaderSize = 40;

struct IrradianceShard {
  std::uint64_t first_photon = 0;
  float scale = 1;                        // irradiance_scale of the header
  std::vector<std::uint32_t> packed;      // RGB9E5 of irradiance / scale, one per photon
  Rgb irradiance(std::size_t i) const;    // decoded: float(m * 2^(e-24)) * scale
};

// Throws std::invalid_argument for a negative or non-finite component.
std::string EncodeIrradianceShard(std::uint64_t first_photon, std::span<const Rgb> irradiance);

// Throws std::runtime_error naming what is wrong with a malformed shard.
IrradianceShard DecodeIrradianceShard(std::string_view bytes);

}  // namespace farm
