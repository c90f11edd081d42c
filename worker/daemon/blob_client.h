#pragma once

// Moving blobs between the worker and the coordinator's blob store, in chunks, with every
// download checked against its digest. Internal to daemon/.

#include <grpcpp/channel.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <stop_token>
#include <string>
#include <string_view>

#include "contract/failure.h"
#include "daemon/blob_cache.h"
#include "daemon/options.h"
#include "renderfarm/v1/blob.grpc.pb.h"
#include "util/progress.h"

namespace farm {

// A blob could not be fetched or stored: the bytes that came were wrong, or the store
// stayed unreachable. The message names the digest.
class BlobError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The coordinator's blob store does not have the blob (NOT_FOUND) or holds it damaged
// (DATA_LOSS): no attempt can succeed until it is stored again, so the task fails as lost
// input (the job fails at once; no worker is blamed). The message names the digest.
class LostBlobError : public TaskError {
 public:
  explicit LostBlobError(const std::string& what)
      : TaskError(renderfarm::v1::FAILURE_KIND_LOST_INPUT, what) {}
};

// Every transfer advances `progress` by the bytes it moves, chunk by chunk, so a task
// fetching a big photon snapshot is not taken for stuck (a retried transfer counts again).
class BlobClient {
 public:
  // `cache` may be null (nothing is cached). FetchFile asks for `range_bytes` a call.
  BlobClient(std::shared_ptr<grpc::Channel> channel, const BlobCache* cache,
             std::uint64_t range_bytes = kDefaultDownloadRangeBytes);

  // The blob's bytes, from the cache if there, else downloaded, verified and cached. Use for
  // blobs many tasks need (scenes, meshes).
  std::string Fetch(const std::string& digest, std::stop_token stop, Progress progress = {});

  // The blob's verified file in the cache, pinned (not evicted while the result lives),
  // downloading it first if it is not there. Use for big blobs mapped into memory (photon
  // snapshots): the download goes straight into the cache file, never held in memory, in
  // ranges of range_bytes, each call resuming where the bytes stopped when a connection is
  // cut; the file is hashed as it grows and checked against the digest once whole (a
  // mismatch asks GetBlobInfo whether the stored blob is damaged: LostBlobError, else
  // BlobError). Throws BlobError if the blob cannot be fetched or the client has no cache
  // to keep it in, std::system_error with ENOSPC if it does not fit in the cache.
  BlobCache::Pinned FetchFile(const std::string& digest, std::stop_token stop,
                              Progress progress = {});

  // Downloads and verifies without caching. Use for blobs read once (tile EXRs).
  std::string Download(const std::string& digest, std::stop_token stop, Progress progress = {});

  // Uploads `bytes` (a header with size and digest, then chunks of the contract's largest
  // upload chunk) and returns the digest. Uploading a blob the store already has is cheap.
  std::string Upload(std::string_view bytes, std::stop_token stop, Progress progress = {});

 private:
  // What one DownloadBlob call hands over: the blob's size (the first message), then each
  // chunk. Either returns a problem (the bytes are wrong: the call is cancelled and not
  // retried), empty if none.
  struct Receiver {
    std::function<std::string(std::int64_t size)> size;
    std::function<std::string(std::string_view chunk)> chunk;
  };
  // One DownloadBlob call of `request`, read to its end into `receiver`; sets `problem` if
  // the receiver found one.
  grpc::Status ReadCall(const renderfarm::v1::DownloadBlobRequest& request, std::stop_token stop,
                        const Receiver& receiver, std::string& problem);
  // Fetches [incoming->size(), end) of the blob into *incoming (made at the first message,
  // which says the blob's size, *size), retrying transient failures from where the bytes
  // stopped. Throws as FetchFile does.
  void FetchRange(const std::string& digest, std::int64_t end, std::int64_t& size,
                  std::optional<BlobCache::Incoming>& incoming, std::stop_token stop, Progress progress);
  // The error of a fetched blob whose bytes do not match its digest.
  [[noreturn]] void ThrowMismatch(const std::string& digest);

  std::unique_ptr<renderfarm::v1::BlobService::Stub> stub_;
  const BlobCache* cache_;
  std::int64_t range_bytes_;
};

}  // namespace farm
