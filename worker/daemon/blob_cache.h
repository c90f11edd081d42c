#pragma once

// The worker's on-disk blob cache: scenes and meshes are fetched once per machine, not once
// per task. Entries are named by digest and checked against it when read, so a damaged or
// tampered file is noticed, dropped and fetched again.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace farm {

class BlobCache {
 public:
  // Creates `dir` if needed; throws std::runtime_error if it cannot.
  explicit BlobCache(std::filesystem::path dir);

  // The blob's bytes if cached and intact. A cached file whose content does not match its
  // digest is deleted and reported as absent.
  std::optional<std::string> Get(std::string_view digest) const;

  // The path of the blob's file if cached and intact (its content is hashed, in chunks,
  // to check), for blobs that are mapped into memory rather than read (photon snapshots).
  // A cached file whose content does not match its digest is deleted and reported absent.
  // Entries are only ever replaced by a rename of identical content, so a file mapped by
  // one worker stays valid while others share the folder.
  std::optional<std::filesystem::path> Path(std::string_view digest) const;

  // Stores `bytes` under `digest` (atomically: concurrent readers and other worker
  // processes sharing the folder never see a partial file). Throws std::invalid_argument if
  // the digest is malformed or does not match the bytes, std::system_error with the
  // failing call's error code (ENOSPC for a full disk) on I/O errors.
  void Put(std::string_view digest, std::string_view bytes) const;

  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path PathOf(std::string_view digest) const;

  std::filesystem::path dir_;
};

}  // namespace farm
