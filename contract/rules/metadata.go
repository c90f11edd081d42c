package rules

// WorkerSecretMetadata is the gRPC metadata key that carries a worker's registration
// secret on every call about that worker (RegisterWorkerResponse.worker_secret,
// worker.proto). The C++ worker sends the same key (worker/daemon/worker.cpp).
const WorkerSecretMetadata = "farm-worker-secret"
