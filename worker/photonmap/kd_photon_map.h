#pragma once

// A PhotonMap read in place from a snapshot's left-balanced kd-tree array of 20-byte
// photons (docs/photon-snapshot.md). Holds a pointer into memory owned by the snapshot.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "photonmap/photon_map.h"

namespace farm {

inline constexpr std::size_t kSnapshotRecordSize = 20;
inline constexpr unsigned kLeafAxis = 3;

class KdPhotonMap final : public PhotonMap {
 public:
  // records: count * 20 bytes, 4-byte aligned, already validated by the snapshot.
  KdPhotonMap(PhotonMapKind kind, const unsigned char* records, std::uint32_t count,
              float power_scale, std::uint64_t paths_emitted)
      : kind_(kind),
        records_(records),
        count_(count),
        power_scale_(power_scale),
        paths_emitted_(paths_emitted) {}

  // irradiance: count * 4 bytes of RGB9E5 relative to irradiance_scale, or null.
  void set_irradiance(const unsigned char* irradiance, float irradiance_scale) {
    irradiance_ = irradiance;
    irradiance_scale_ = irradiance_scale;
  }

  // The map of this one's first count photons in tree order (count at most size()): the top
  // of the tree, itself a left-balanced kd-tree, sharing the records.
  KdPhotonMap prefix(std::uint32_t count) const {
    return KdPhotonMap(kind_, records_, std::min(count, count_), power_scale_, paths_emitted_);
  }

  std::size_t size() const override { return count_; }
  bool has_irradiance() const override { return irradiance_ != nullptr; }
  Rgb irradiance(std::size_t index) const override;
  DecodedPhoton photon(std::size_t index) const override;
  // The k photons with the smallest (distance_squared, index) among those strictly within
  // max_radius: a tie in distance goes to the lower index, so the set found depends on the
  // map and the query alone, never on the order the search happens to visit the tree.
  void NearestK(const Vec3& p, int k, float max_radius,
                std::vector<PhotonNeighbour>& out) const override;

  PhotonMapKind kind() const { return kind_; }
  float power_scale() const { return power_scale_; }
  std::uint64_t paths_emitted() const { return paths_emitted_; }
  // 0-2 the split axis of node index, 3 for a leaf.
  unsigned split_axis(std::size_t index) const;
  std::uint32_t packed_power(std::size_t index) const;
  std::uint16_t wi_code(std::size_t index) const;
  std::uint16_t normal_code(std::size_t index) const;  // axis bits cleared

 private:
  PhotonMapKind kind_;
  const unsigned char* records_;
  std::uint32_t count_;
  float power_scale_;
  std::uint64_t paths_emitted_;
  const unsigned char* irradiance_ = nullptr;
  float irradiance_scale_ = 0;
};

}  // namespace farm
