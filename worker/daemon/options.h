#pragma once

#include <filesystem>
#include <string>

namespace farm {

// How a farm-worker process is configured (from its command line).
struct WorkerOptions {
  std::string coordinator;           // HOST:PORT of the coordinator's gRPC endpoint.
  std::filesystem::path cache_dir;   // Where fetched scenes and meshes are kept.
  int threads = 0;                   // Render threads; 0 means all cores.
  std::string name;                  // Shown as the worker's hostname; empty: the host's.
  std::string token;                 // Worker token sent on every RPC; empty: none.
  std::filesystem::path tls_ca;      // PEM CA file: connect with TLS trusting it; empty: plaintext.
  bool insecure = false;             // Allow a token in plaintext to a non-loopback address.
  int texture_cache_mib = 512;       // Bound of the texture tile cache, MiB.
};

}  // namespace farm
