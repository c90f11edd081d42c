#pragma once

// The worker's on-disk blob cache: scenes, meshes and photon snapshots are fetched once per
// machine, not once per task. Entries are named by digest and checked against it when
// read, so a damaged or tampered file is noticed, dropped and fetched again.
//
// The cache holds at most a given number of bytes (--cache-max-bytes): to make room for a
// new entry it deletes the least recently used ones (each read or store of an entry marks
// it used, in its file's modification time, which every worker sharing the folder sees).
// An entry in use, a photon snapshot a task has mapped, is pinned (a shared lock on its
// file) and never deleted, by this process or any other sharing the folder: a new entry
// that does not fit beside the pinned ones is refused with ENOSPC, which the worker
// reports as resource exhaustion (retried elsewhere, the worker not blamed).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "daemon/sha256.h"

namespace farm {

class BlobCache {
 public:
  // A cached file in use: while it lives, no worker sharing the folder deletes the entry.
  class Pinned {
   public:
    Pinned(std::filesystem::path path, int fd) : path_(std::move(path)), fd_(fd) {}
    Pinned(Pinned&& other) noexcept;
    Pinned& operator=(Pinned&& other) noexcept;
    Pinned(const Pinned&) = delete;
    Pinned& operator=(const Pinned&) = delete;
    ~Pinned();
    const std::filesystem::path& path() const { return path_; }

   private:
    std::filesystem::path path_;
    int fd_ = -1;  // holds the shared lock
  };

  // A blob being written into the cache as it arrives, never held in memory: a temporary
  // file in the cache folder, hashed as it grows, linked into place by Commit once whole.
  // Dropped (its file removed) if destroyed uncommitted; the file of a worker killed
  // mid-download is deleted once it has not been written for an hour, when room is next
  // made.
  class Incoming {
   public:
    Incoming(Incoming&& other) noexcept;
    Incoming& operator=(Incoming&&) = delete;
    Incoming(const Incoming&) = delete;
    Incoming& operator=(const Incoming&) = delete;
    ~Incoming();

    // Bytes received so far: where a cut download resumes.
    std::uint64_t size() const { return written_; }
    // Writes `bytes` at the end. Throws std::system_error with the failing call's error
    // code (ENOSPC for a full disk).
    void Append(std::string_view bytes);
    // If the bytes received match the digest, links the file into place (an entry another
    // worker stored meanwhile is kept instead) and returns it pinned, without reading it
    // again; else drops the file and returns nothing. Call once.
    std::optional<Pinned> Commit();

   private:
    friend class BlobCache;
    Incoming(std::string digest, std::filesystem::path path, std::filesystem::path temp, int fd)
        : digest_(std::move(digest)), path_(std::move(path)), temp_(std::move(temp)), fd_(fd) {}

    std::string digest_;
    std::filesystem::path path_;  // The entry's, once committed.
    std::filesystem::path temp_;
    int fd_ = -1;
    Sha256 hash_;
    std::uint64_t written_ = 0;
  };

  // Creates `dir` if needed; throws std::runtime_error if it cannot. The entries take at
  // most max_bytes together (workers sharing the folder may overshoot it by the blobs they
  // store at the same moment).
  BlobCache(std::filesystem::path dir, std::uint64_t max_bytes);

  // The blob's bytes if cached and intact. A cached file whose content does not match its
  // digest is deleted and reported as absent.
  std::optional<std::string> Get(std::string_view digest) const;

  // The blob's file, pinned, if cached and intact (its content is hashed, in chunks, to
  // check), for blobs that are mapped into memory rather than read (photon snapshots). A
  // cached file whose content does not match its digest is deleted and reported absent.
  std::optional<Pinned> Pin(std::string_view digest) const;

  // Stores `bytes` under `digest` (atomically: concurrent readers and other worker
  // processes sharing the folder never see a partial file; an entry already there is
  // kept), first deleting the least recently used entries that are not pinned until it
  // fits. Throws std::invalid_argument if the digest is malformed or does not match the
  // bytes, std::system_error with ENOSPC if the blob does not fit beside the pinned entries
  // (or at all), and with the failing call's error code on I/O errors.
  void Put(std::string_view digest, std::string_view bytes) const;

  // Starts receiving the blob `digest` of `size` bytes, as it arrives (Incoming), first
  // deleting the least recently used unpinned entries until it fits. Throws as Put does.
  Incoming Receive(std::string_view digest, std::uint64_t size) const;

  const std::filesystem::path& dir() const { return dir_; }
  std::uint64_t max_bytes() const { return max_bytes_; }

 private:
  std::filesystem::path PathOf(std::string_view digest) const;
  // Pin of the entry at `path`.
  static std::optional<Pinned> PinAt(std::filesystem::path path, std::string_view digest);
  // Deletes least recently used unpinned entries until `needed` more bytes fit.
  void MakeRoom(std::string_view digest, std::uint64_t needed) const;

  std::filesystem::path dir_;
  std::uint64_t max_bytes_;
};

}  // namespace farm
