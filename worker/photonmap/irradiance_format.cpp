#include "photonmap/irradiance_format.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "photonmap/byte_io.h"
#include "photonmap/rgb9e5.h"

namespace farm {
namespace {

constexpr char kMagic[8] = {'P', 'F', 'I', 'R', 'R', 'A', 'D', '1'};
constexpr std::uint32_t kVersion = 1;
constexpr std::uint32_t kRecordSize = 4;

[[noreturn]] void Fail(const std::string& what) {
  throw std::runtime_error("irradiance shard: " + what);
}

}  // namespace

Rgb IrradianceShard::irradiance(std::size_t i) const { return DecodeRgb9e5(packed[i]) * scale; }

std::string EncodeIrradianceShard(std::uint64_t first_photon, std::span<const Rgb> irradiance) {
  float scale = 0;
  for (const Rgb& e : irradiance) {
    for (float c : {e.r, e.g, e.b}) {
      if (!std::isfinite(c) || c < 0)
        throw std::invalid_argument("EncodeIrradianceShard: component " + std::to_string(c) +
                                    " is negative or not finite");
      scale = std::max(scale, c);
    }
  }
  // The brightest component of the shard: every record is relative to it, so all lie in
  // [0, 1] as RGB9E5 wants; 1 when everything is black (a dark room is a real answer).
  if (!(scale > 0)) scale = 1;
  std::string out;
  out.reserve(kIrradianceShardHeaderSize + kRecordSize * irradiance.size());
  out.append(kMagic, sizeof kMagic);
  byte_io::Append(out, kVersion);
  byte_io::Append(out, kRecordSize);
  byte_io::Append(out, first_photon);
  byte_io::Append(out, std::uint64_t{irradiance.size()});
  byte_io::Append(out, scale);
  byte_io::Append(out, std::uint32_t{0});  // reserved
  const double s = scale;
  for (const Rgb& e : irradiance) byte_io::Append(out, EncodeRgb9e5(e.r / s, e.g / s, e.b / s));
  return out;
}

IrradianceShard DecodeIrradianceShard(std::string_view b) {
  if (b.size() < kIrradianceShardHeaderSize)
    Fail(std::to_string(b.size()) + " bytes is shorter than the 40-byte header");
  if (std::memcmp(b.data(), kMagic, sizeof kMagic) != 0) Fail("bad magic (want PFIRRAD1)");
  const char* h = b.data();
  if (auto v = byte_io::Load<std::uint32_t>(h + 8); v != kVersion)
    Fail("unsupported version " + std::to_string(v));
  if (byte_io::Load<std::uint32_t>(h + 12) != kRecordSize) Fail("record_size is not 4");
  IrradianceShard shard;
  shard.first_photon = byte_io::Load<std::uint64_t>(h + 16);
  const auto count = byte_io::Load<std::uint64_t>(h + 24);
  shard.scale = byte_io::Load<float>(h + 32);
  if (!(shard.scale > 0) || !std::isfinite(shard.scale)) Fail("irradiance_scale must be finite and > 0");
  if (byte_io::Load<std::uint32_t>(h + 36) != 0) Fail("reserved bytes are not zero");
  if (count != (b.size() - kIrradianceShardHeaderSize) / kRecordSize ||
      (b.size() - kIrradianceShardHeaderSize) % kRecordSize != 0)
    Fail("photon_count " + std::to_string(count) + " does not match " + std::to_string(b.size()) +
         " bytes");
  shard.packed.resize(count);
  for (std::uint64_t i = 0; i < count; ++i)
    shard.packed[i] = byte_io::Load<std::uint32_t>(h + kIrradianceShardHeaderSize + kRecordSize * i);
  return shard;
}

}  // namespace farm
