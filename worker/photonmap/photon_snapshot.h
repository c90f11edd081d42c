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

 private:
  explicit PhotonSnapshot(std::unique_ptr<SnapshotData> data);
  std::unique_ptr<SnapshotData> data_;
};

}  // namespace farm
