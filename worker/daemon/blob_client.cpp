#include "daemon/blob_client.h"

#include <grpcpp/client_context.h>

#include <algorithm>
#include <stop_token>

#include "daemon/retry.h"
#include "contract/digest.h"
#include "contract/rules.h"
#include "daemon/sha256.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

// A transfer that has not finished in this long is stuck; big images still fit.
constexpr auto kTransferDeadline = std::chrono::minutes(10);
// A download reserves at most this much before the bytes arrive, so that a size the store
// declares but does not send costs little.
constexpr std::int64_t kMostReservedUpFront = 64 << 20;
// How long a blob operation keeps retrying an unreachable store before the task fails.
constexpr auto kGiveUpAfter = std::chrono::seconds(120);

void PrepareContext(grpc::ClientContext& ctx) {
  ctx.set_deadline(std::chrono::system_clock::now() + kTransferDeadline);
}

}  // namespace

BlobClient::BlobClient(std::shared_ptr<grpc::Channel> channel, const BlobCache* cache)
    : stub_(pb::BlobService::NewStub(std::move(channel))), cache_(cache) {}

std::string BlobClient::Fetch(const std::string& digest, std::stop_token stop,
                              Progress progress) {
  if (cache_) {
    if (auto cached = cache_->Get(digest)) return std::move(*cached);
  }
  std::string bytes = Download(digest, stop, progress);
  if (cache_) {
    try {
      cache_->Put(digest, bytes);
    } catch (const std::exception&) {
      // A full or read-only disk costs a download next time, not the task.
    }
  }
  return bytes;
}

BlobCache::Pinned BlobClient::FetchFile(const std::string& digest, std::stop_token stop,
                                        Progress progress) {
  if (!cache_) throw BlobError("no cache folder to keep blob " + digest + " in");
  if (auto pinned = cache_->Pin(digest)) return std::move(*pinned);
  {
    const std::string bytes = Download(digest, stop, progress);
    try {
      cache_->Put(digest, bytes);  // Atomic: a temporary file linked into place.
    } catch (const std::system_error& e) {
      // Keeps the error's code: a full disk or cache is another kind of failure than a
      // lost blob.
      throw std::system_error(e.code(), "cannot cache blob " + digest + ": " + e.what());
    }
  }  // The bytes are freed before the file is mapped.
  if (auto pinned = cache_->Pin(digest)) return std::move(*pinned);
  throw BlobError("blob " + digest + " vanished from the cache right after it was stored");
}

std::string BlobClient::Download(const std::string& digest, std::stop_token stop,
                                 Progress progress) {
  if (!contract::IsDigest(digest)) throw BlobError("malformed blob digest \"" + digest + "\"");
  std::string bytes;
  std::string problem;  // Set when the bytes arrived but were wrong.
  const grpc::Status status = RetryTransient("download " + digest, stop, kGiveUpAfter, [&] {
    bytes.clear();
    problem.clear();
    grpc::ClientContext ctx;
    PrepareContext(ctx);
    std::stop_callback cancel(stop, [&ctx] { ctx.TryCancel(); });
    pb::DownloadBlobRequest request;
    request.set_digest(digest);
    auto reader = stub_->DownloadBlob(&ctx, request);
    pb::DownloadBlobResponse chunk;
    std::int64_t expected = -1;
    // Blobs larger than the contract allows are refused before anything is allocated.
    const auto max_blob = static_cast<std::int64_t>(contract::RpcLimits().max_blob_bytes());
    Sha256 hash;
    while (reader->Read(&chunk)) {
      if (expected < 0) {
        expected = chunk.size_bytes();
        if (expected < 0 || expected > max_blob) {
          problem = "declared size " + std::to_string(expected) + " is out of range";
          ctx.TryCancel();
          break;
        }
        // Reserve what is declared, up to a point: the rest grows as bytes really arrive.
        bytes.reserve(static_cast<std::size_t>(std::min(expected, kMostReservedUpFront)));
      }
      if (static_cast<std::int64_t>(bytes.size() + chunk.chunk().size()) > expected) {
        problem = "more bytes than the declared " + std::to_string(expected);
        ctx.TryCancel();
        break;
      }
      hash.Update(chunk.chunk());
      bytes += chunk.chunk();
      progress.Advance(chunk.chunk().size());
    }
    grpc::Status s = reader->Finish();
    if (!problem.empty()) return grpc::Status::OK;  // Not retried: the store sent bad bytes.
    if (!s.ok()) return s;
    if (expected < 0) expected = 0;  // An empty blob may come as no message at all.
    if (static_cast<std::int64_t>(bytes.size()) != expected) {
      problem = "got " + std::to_string(bytes.size()) + " bytes of the declared " +
                std::to_string(expected);
    } else if (hash.Finish() != digest) {
      problem = "content does not match its digest";
    }
    return grpc::Status::OK;
  });
  if (status.error_code() == grpc::StatusCode::NOT_FOUND) {
    throw LostBlobError("blob " + digest + " is not in the coordinator's blob store");
  }
  if (status.error_code() == grpc::StatusCode::DATA_LOSS) throw LostBlobError(status.error_message());
  if (!status.ok()) {
    throw BlobError("cannot download blob " + digest + ": " + status.error_message());
  }
  if (!problem.empty()) throw BlobError("blob " + digest + " from the store is corrupt: " + problem);
  return bytes;
}

std::string BlobClient::Upload(std::string_view bytes, std::stop_token stop,
                               Progress progress) {
  const std::string digest = Sha256Digest(bytes);
  pb::UploadBlobResponse response;
  const grpc::Status status = RetryTransient("upload " + digest, stop, kGiveUpAfter, [&] {
    grpc::ClientContext ctx;
    PrepareContext(ctx);
    std::stop_callback cancel(stop, [&ctx] { ctx.TryCancel(); });
    auto writer = stub_->UploadBlob(&ctx, &response);
    pb::UploadBlobRequest part;
    part.mutable_header()->set_size_bytes(static_cast<std::int64_t>(bytes.size()));
    part.mutable_header()->set_digest(digest);
    bool ok = writer->Write(part);
    const std::size_t chunk = contract::RpcLimits().max_upload_chunk_bytes();
    for (std::size_t at = 0; ok && at < bytes.size(); at += chunk) {
      part.set_chunk(std::string(bytes.substr(at, chunk)));
      ok = writer->Write(part);
      if (ok) progress.Advance(part.chunk().size());
    }
    // A failed Write means the call is over; Finish tells why.
    writer->WritesDone();
    return writer->Finish();
  });
  // The coordinator's disk is full (or the blob over its size limit): not this worker's
  // fault, so it must not count toward blocking it.
  if (status.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED) {
    throw TaskError(renderfarm::v1::FAILURE_KIND_RESOURCE_EXHAUSTED,
                    "cannot upload blob " + digest + ": " + status.error_message());
  }
  if (!status.ok()) throw BlobError("cannot upload blob " + digest + ": " + status.error_message());
  if (response.digest() != digest) {
    throw BlobError("blob store stored " + response.digest() + " for upload " + digest);
  }
  return digest;
}

}  // namespace farm
