#include "photonmap/shard_format.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "photonmap/byte_io.h"
#include "photonmap/oct_direction.h"

namespace farm {
namespace {

bool ValidPower(float c) { return std::isfinite(c) && c >= 0; }

}  // namespace

std::string EncodeShard(PhotonMapKind kind, std::uint64_t first_photon,
                        std::uint64_t photon_count, const std::vector<ShardPhoton>& photons) {
  if (!IsPhotonMapKind(static_cast<std::uint32_t>(kind))) {
    throw std::invalid_argument("EncodeShard: unknown map kind " +
                                std::to_string(static_cast<std::uint32_t>(kind)));
  }
  std::string out;
  out.reserve(kShardHeaderSize + kShardRecordSize * photons.size());
  out.append(kShardMagic, sizeof kShardMagic);
  byte_io::Append(out, kShardVersion);
  byte_io::Append(out, static_cast<std::uint32_t>(kind));
  byte_io::Append(out, first_photon);
  byte_io::Append(out, photon_count);
  byte_io::Append(out, static_cast<std::uint64_t>(photons.size()));
  for (std::size_t i = 0; i < photons.size(); ++i) {
    const ShardPhoton& p = photons[i];
    if (!IsFinite(p.position)) {
      throw std::invalid_argument("EncodeShard: photon " + std::to_string(i) +
                                  ": position is not finite: " + ToString(p.position));
    }
    if (!ValidPower(p.power.r) || !ValidPower(p.power.g) || !ValidPower(p.power.b)) {
      throw std::invalid_argument("EncodeShard: photon " + std::to_string(i) +
                                  ": power must be finite and >= 0: " + ToString(p.power));
    }
    for (float f : {p.position.x, p.position.y, p.position.z, p.power.r, p.power.g, p.power.b}) {
      byte_io::Append(out, f);
    }
    byte_io::Append(out, EncodeOct8(p.wi));
    byte_io::Append(out, EncodeOct7Normal(p.normal));
  }
  return out;
}

DecodedShard DecodeShard(std::string_view bytes) {
  if (bytes.size() < kShardHeaderSize) {
    throw std::runtime_error("shard: " + std::to_string(bytes.size()) +
                             " bytes is shorter than the 40-byte header");
  }
  if (std::memcmp(bytes.data(), kShardMagic, sizeof kShardMagic) != 0) {
    throw std::runtime_error("shard: bad magic (want PFSHARD1)");
  }
  const char* p = bytes.data();
  auto version = byte_io::Load<std::uint32_t>(p + 8);
  if (version != kShardVersion) {
    throw std::runtime_error("shard: unsupported version " + std::to_string(version));
  }
  auto kind = byte_io::Load<std::uint32_t>(p + 12);
  if (!IsPhotonMapKind(kind)) {
    throw std::runtime_error("shard: unknown map kind " + std::to_string(kind));
  }
  DecodedShard shard;
  shard.kind = static_cast<PhotonMapKind>(kind);
  shard.first_photon = byte_io::Load<std::uint64_t>(p + 16);
  shard.photon_count = byte_io::Load<std::uint64_t>(p + 24);
  auto records = byte_io::Load<std::uint64_t>(p + 32);
  // Divide rather than multiply so a huge record_count cannot overflow the check.
  std::size_t body = bytes.size() - kShardHeaderSize;
  if (body % kShardRecordSize != 0 || body / kShardRecordSize != records) {
    throw std::runtime_error("shard: record_count " + std::to_string(records) +
                             " does not match " + std::to_string(bytes.size()) + " bytes");
  }
  shard.records.resize(records);
  for (std::size_t i = 0; i < records; ++i) {
    const char* r = p + kShardHeaderSize + i * kShardRecordSize;
    ShardRecord& out = shard.records[i];
    out.position = {byte_io::Load<float>(r), byte_io::Load<float>(r + 4),
                    byte_io::Load<float>(r + 8)};
    out.power = {byte_io::Load<float>(r + 12), byte_io::Load<float>(r + 16),
                 byte_io::Load<float>(r + 20)};
    out.wi_oct8 = byte_io::Load<std::uint16_t>(r + 24);
    out.normal_oct7 = byte_io::Load<std::uint16_t>(r + 26);
    if (!IsFinite(out.position)) {
      throw std::runtime_error("shard: record " + std::to_string(i) + ": position not finite");
    }
    if (!ValidPower(out.power.r) || !ValidPower(out.power.g) || !ValidPower(out.power.b)) {
      throw std::runtime_error("shard: record " + std::to_string(i) +
                               ": power must be finite and >= 0");
    }
    if ((out.normal_oct7 & 3u) != 0) {
      throw std::runtime_error("shard: record " + std::to_string(i) +
                               ": normal bits 0-1 must be zero");
    }
  }
  return shard;
}

}  // namespace farm
