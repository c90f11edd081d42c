#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "photonmap/photon_map.h"

namespace farm {

struct SnapshotData;

// A photon kd-tree snapshot (docs/photon-snapshot.md) mapped into memory: several workers
// on one host that open the same cached file share its pages. Validates the header and
// sizes on open and throws std::runtime_error naming what is wrong (snapshots are
// untrusted input).
class PhotonSnapshot {
 public:
  static PhotonSnapshot Open(const std::filesystem::path& file);
  static PhotonSnapshot FromBytes(std::string bytes);

  PhotonSnapshot(PhotonSnapshot&&) noexcept;
  PhotonSnapshot& operator=(PhotonSnapshot&&) noexcept;
  ~PhotonSnapshot();

  // Null when the job has no map of that kind.
  const PhotonMap* map(PhotonMapKind kind) const;
  // The global map's photons that carry precomputed irradiance, as a map of their own
  // whose photon i is the global map's photon i: the first irradiance_count photons of its
  // tree, a kd-tree by themselves (docs/photon-snapshot.md). Null without an irradiance
  // section.
  const PhotonMap* irradiance_sites() const;

 private:
  explicit PhotonSnapshot(std::unique_ptr<SnapshotData> data);
  std::unique_ptr<SnapshotData> data_;
};

}  // namespace farm
