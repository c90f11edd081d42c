#pragma once

// The one gRPC channel a farm-worker talks to its coordinator over: plaintext or TLS, and
// the worker token on every call. Every stub (WorkerService, BlobService) is made on it,
// so no call can leave without the token.

#include <grpcpp/channel.h>

#include <memory>

#include "daemon/options.h"

namespace farm {

// Creates the channel to options.coordinator (the connection is lazy). With
// options.tls_ca set it uses TLS trusting that CA file; with options.token set every call
// carries the metadata "authorization: Bearer TOKEN". Throws std::runtime_error if the
// CA file cannot be read.
std::shared_ptr<grpc::Channel> MakeCoordinatorChannel(const WorkerOptions& options);

}  // namespace farm
