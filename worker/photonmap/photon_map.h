#pragma once

#include <cstdint>
#include <vector>

#include "math/rgb.h"
#include "math/vec3.h"

namespace farm {

enum class PhotonMapKind : std::uint32_t { kGlobal = 1, kCaustic = 2, kVolume = 3 };

// Every kind, in the order a snapshot lists them (docs/photon-snapshot.md).
inline constexpr PhotonMapKind kPhotonMapKinds[] = {PhotonMapKind::kGlobal, PhotonMapKind::kCaustic,
                                                    PhotonMapKind::kVolume};
inline constexpr bool IsPhotonMapKind(std::uint32_t kind) { return kind >= 1 && kind <= 3; }
// "global", "caustic", "volume": the map's name in messages and settings.
inline constexpr const char* PhotonMapName(PhotonMapKind kind) {
  switch (kind) {
    case PhotonMapKind::kGlobal: return "global";
    case PhotonMapKind::kCaustic: return "caustic";
    case PhotonMapKind::kVolume: return "volume";
  }
  return "?";
}

// A photon as the renderer sees it, decoded from its compact stored form.
struct DecodedPhoton {
  Vec3 position;
  Rgb power;   // flux carried, already divided by the number of paths emitted
  Vec3 wi;     // unit direction towards where the photon came from
  Vec3 normal; // unit normal of the surface it landed on (+z, unused, in the volume map)
};

struct PhotonNeighbour {
  std::uint32_t index;   // into the map
  float distance_squared;
};

// One balanced kd-tree of photons, read in place from a snapshot (see
// docs/photon-snapshot.md). Read-only and safe to share between threads.
class PhotonMap {
 public:
  virtual ~PhotonMap() = default;
  virtual std::size_t size() const = 0;
  virtual DecodedPhoton photon(std::size_t index) const = 0;
  // Fills out with the (at most) k photons nearest to p within max_radius, in no particular
  // order. Reuses out's storage.
  virtual void NearestK(const Vec3& p, int k, float max_radius,
                        std::vector<PhotonNeighbour>& out) const = 0;

  // Irradiance precomputed at each photon (Christensen 1999; only the irradiance sites of a
  // snapshot merged with its irradiance shards, PhotonSnapshot::irradiance_sites, and maps
  // built in memory by tests have it): the light arriving at the photon's position on the
  // side of its normal, in index order with photon(i).
  virtual bool has_irradiance() const { return false; }
  virtual Rgb irradiance(std::size_t /*index*/) const { return {}; }
};

}  // namespace farm
