#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace farm {

// --cache-max-bytes by default: room for a job's two largest photon snapshots (2.1 and 2.5
// GB at max_snapshot_photons, before and after the irradiance merge: docs/limits.md)
// beside the scenes and meshes of the jobs at hand.
inline constexpr std::uint64_t kDefaultCacheMaxBytes = std::uint64_t{8} << 30;

// --download-range-bytes by default: a cut connection costs at most this much of a photon
// snapshot's download, and each call lasts seconds, not minutes.
inline constexpr std::uint64_t kDefaultDownloadRangeBytes = std::uint64_t{64} << 20;

// How a farm-worker process is configured (from its command line).
struct WorkerOptions {
  std::vector<std::string> coordinators;  // HOST:PORT of each coordinator replica (coordinator_address.h).
  std::filesystem::path cache_dir;   // Where fetched scenes and meshes are kept.
  std::uint64_t cache_max_bytes = kDefaultCacheMaxBytes;  // The most the cache may hold.
  std::uint64_t download_range_bytes = kDefaultDownloadRangeBytes;  // Of a big blob, per call.
  int threads = 0;                   // Render threads; 0 means all cores.
  std::string name;                  // Shown as the worker's hostname; empty: the host's.
  std::string token;                 // Worker token sent on every RPC; empty: none.
  std::filesystem::path tls_ca;      // PEM CA file: connect with TLS trusting it; empty: plaintext.
  bool insecure = false;             // Allow a token in plaintext to a non-loopback address.
  int texture_cache_mib = 512;       // Bound of the texture tile cache, MiB.
};

// The coordinator addresses as the worker's lines show them.
inline std::string JoinedAddresses(const WorkerOptions& options) {
  std::string joined;
  for (const std::string& address : options.coordinators) joined += (joined.empty() ? "" : ",") + address;
  return joined;
}

}  // namespace farm
