#include "daemon/blob_client.h"

#include <grpcpp/client_context.h>

#include <algorithm>
#include <exception>
#include <stop_token>
#include <system_error>

#include "contract/digest.h"
#include "contract/rules.h"
#include "daemon/log.h"
#include "daemon/retry.h"
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

// The largest blob the contract allows: a declared size past it is refused before anything
// is allocated or written.
std::int64_t MaxBlobBytes() { return static_cast<std::int64_t>(contract::RpcLimits().max_blob_bytes()); }

// Throws for a failed call about blob `digest`: a blob the store has not got, or holds
// damaged, as lost input.
void ThrowIfFailed(const grpc::Status& status, const std::string& digest) {
  if (status.error_code() == grpc::StatusCode::NOT_FOUND) {
    throw LostBlobError("blob " + digest + " is not in the coordinator's blob store");
  }
  if (status.error_code() == grpc::StatusCode::DATA_LOSS) throw LostBlobError(status.error_message());
  if (!status.ok()) {
    throw BlobError("cannot download blob " + digest + ": " + status.error_message());
  }
}

// The cache's errors keep their code (a full disk or cache is another kind of failure than a
// lost blob), named for the blob.
[[noreturn]] void ThrowCannotCache(const std::system_error& e, const std::string& digest) {
  throw std::system_error(e.code(), "cannot cache blob " + digest + ": " + e.what());
}

}  // namespace

BlobClient::BlobClient(std::shared_ptr<grpc::Channel> channel, const BlobCache* cache,
                       std::uint64_t range_bytes)
    : stub_(pb::BlobService::NewStub(std::move(channel))),
      cache_(cache),
      range_bytes_(static_cast<std::int64_t>(std::clamp<std::uint64_t>(range_bytes, 1, std::uint64_t{1} << 62))) {}

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

grpc::Status BlobClient::ReadCall(const pb::DownloadBlobRequest& request, std::stop_token stop,
                                  const Receiver& receiver, std::string& problem) {
  grpc::ClientContext ctx;
  PrepareContext(ctx);
  std::stop_callback cancel(stop, [&ctx] { ctx.TryCancel(); });
  auto reader = stub_->DownloadBlob(&ctx, request);
  pb::DownloadBlobResponse chunk;
  bool first = true;
  std::exception_ptr failed;  // The receiver's: rethrown once the call is over.
  while (problem.empty() && !failed && reader->Read(&chunk)) {
    try {
      if (first) problem = receiver.size(chunk.size_bytes());
      first = false;
      if (problem.empty()) problem = receiver.chunk(chunk.chunk());
    } catch (...) {
      failed = std::current_exception();
    }
  }
  if (!problem.empty() || failed) ctx.TryCancel();
  grpc::Status status = reader->Finish();
  if (failed) std::rethrow_exception(failed);
  // An empty blob may come as no message at all.
  if (status.ok() && problem.empty() && first) problem = receiver.size(0);
  return status;
}

BlobCache::Pinned BlobClient::FetchFile(const std::string& digest, std::stop_token stop,
                                        Progress progress) {
  if (!cache_) throw BlobError("no cache folder to keep blob " + digest + " in");
  if (!contract::IsDigest(digest)) throw BlobError("malformed blob digest \"" + digest + "\"");
  if (auto pinned = cache_->Pin(digest)) return std::move(*pinned);
  std::optional<BlobCache::Incoming> incoming;  // Made once the first message says the size.
  std::int64_t size = -1;
  do {
    const auto from = incoming ? static_cast<std::int64_t>(incoming->size()) : 0;
    FetchRange(digest, size < 0 ? range_bytes_ : std::min(size, from + range_bytes_), size, incoming, stop, progress);
  } while (static_cast<std::int64_t>(incoming->size()) < size);
  std::optional<BlobCache::Pinned> pinned;
  try {
    pinned = incoming->Commit();
  } catch (const std::system_error& e) {
    ThrowCannotCache(e, digest);
  }
  if (!pinned) ThrowMismatch(digest);
  return std::move(*pinned);
}

void BlobClient::FetchRange(const std::string& digest, std::int64_t end, std::int64_t& size,
                            std::optional<BlobCache::Incoming>& incoming, std::stop_token stop,
                            Progress progress) {
  std::string problem;  // Set when the bytes that came were wrong.
  const auto received = [&incoming] { return incoming ? static_cast<std::int64_t>(incoming->size()) : 0; };
  const Receiver receiver{
      [&](std::int64_t announced) -> std::string {
        if (size >= 0) {
          return announced == size ? "" : "its size changed from " + std::to_string(size) + " to " + std::to_string(announced) + " bytes";
        }
        if (announced < 0 || announced > MaxBlobBytes()) return "declared size " + std::to_string(announced) + " is out of range";
        size = announced;
        end = std::min(end, size);
        try {
          incoming.emplace(cache_->Receive(digest, static_cast<std::uint64_t>(size)));
        } catch (const std::system_error& e) {
          ThrowCannotCache(e, digest);
        }
        return {};
      },
      [&](std::string_view chunk) -> std::string {
        if (received() + static_cast<std::int64_t>(chunk.size()) > end) {
          return "more bytes than the range up to byte " + std::to_string(end) + " asked for";
        }
        try {
          incoming->Append(chunk);
        } catch (const std::system_error& e) {
          ThrowCannotCache(e, digest);
        }
        progress.Advance(chunk.size());
        return {};
      }};
  const grpc::Status status = RetryTransient(
      "download " + digest, stop, kGiveUpAfter,
      [&] {
        const std::int64_t from = received();
        if (incoming && from >= end) return grpc::Status::OK;  // The cut came after the last byte.
        pb::DownloadBlobRequest request;
        request.set_digest(digest);
        request.set_offset(from);
        request.set_length(end - from);
        const grpc::Status s = ReadCall(request, stop, receiver, problem);
        if (!problem.empty() || !s.ok()) return problem.empty() ? s : grpc::Status::OK;  // Bad bytes: not retried.
        if (received() < end) {
          problem = "the range ended at byte " + std::to_string(received()) + ", before byte " + std::to_string(end);
        }
        return grpc::Status::OK;
      },
      [&](const grpc::Status& s, Millis delay) {
        // The next call asks for the rest of the range, from the first byte not received.
        Log(LogLevel::kWarn, "download cut; resuming",
            {{"blob", digest}, {"at", received()}, {"of", size}, {"err", s.error_message()},
             {"code", static_cast<int>(s.error_code())}, {"retry_ms", delay.count()}});
      });
  ThrowIfFailed(status, digest);
  if (!problem.empty()) throw BlobError("blob " + digest + " from the store is corrupt: " + problem);
}

void BlobClient::ThrowMismatch(const std::string& digest) {
  // The whole was assembled from ranges the store sent unchecked: the store checks its copy.
  grpc::ClientContext ctx;
  PrepareContext(ctx);
  pb::GetBlobInfoRequest request;
  request.set_digest(digest);
  pb::GetBlobInfoResponse response;
  ThrowIfFailed(stub_->GetBlobInfo(&ctx, request, &response), digest);
  throw BlobError("blob " + digest + " from the store is corrupt: content does not match its digest");
}

std::string BlobClient::Download(const std::string& digest, std::stop_token stop,
                                 Progress progress) {
  if (!contract::IsDigest(digest)) throw BlobError("malformed blob digest \"" + digest + "\"");
  std::string bytes;
  std::int64_t expected = 0;
  std::optional<Sha256> hash;
  std::string problem;  // Set when the bytes arrived but were wrong.
  const Receiver receiver{
      [&](std::int64_t size) -> std::string {
        // Blobs larger than the contract allows are refused before anything is allocated.
        if (size < 0 || size > MaxBlobBytes()) return "declared size " + std::to_string(size) + " is out of range";
        expected = size;
        // Reserve what is declared, up to a point: the rest grows as bytes really arrive.
        bytes.reserve(static_cast<std::size_t>(std::min(expected, kMostReservedUpFront)));
        return {};
      },
      [&](std::string_view chunk) -> std::string {
        if (static_cast<std::int64_t>(bytes.size() + chunk.size()) > expected) {
          return "more bytes than the declared " + std::to_string(expected);
        }
        hash->Update(chunk);
        bytes += chunk;
        progress.Advance(chunk.size());
        return {};
      }};
  const grpc::Status status = RetryTransient("download " + digest, stop, kGiveUpAfter, [&] {
    bytes.clear();
    problem.clear();
    hash.emplace();
    expected = 0;
    pb::DownloadBlobRequest request;
    request.set_digest(digest);
    const grpc::Status s = ReadCall(request, stop, receiver, problem);
    if (!problem.empty() || !s.ok()) return problem.empty() ? s : grpc::Status::OK;  // Bad bytes: not retried.
    if (static_cast<std::int64_t>(bytes.size()) != expected) {
      problem = "got " + std::to_string(bytes.size()) + " bytes of the declared " + std::to_string(expected);
    } else if (hash->Finish() != digest) {
      problem = "content does not match its digest";
    }
    return grpc::Status::OK;
  });
  ThrowIfFailed(status, digest);
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
