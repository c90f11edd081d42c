#pragma once

// The farm-worker process: registers with the coordinator, leases tasks one at a time,
// performs them, reports the results, keeps its lease alive with heartbeats and shuts down
// cleanly. gRPC stays behind this header so main() compiles quickly.

#include <memory>

#include "daemon/options.h"

namespace farm {

class Worker {
 public:
  // Creates the cache directory and the channel (connection is lazy). Throws
  // std::runtime_error if the cache directory cannot be created. `cores` is what the
  // worker tells the coordinator it renders with.
  Worker(const WorkerOptions& options, unsigned cores);
  ~Worker();

  // Works until Drain() or Abort(), then unregisters. Returns the process exit code: 0
  // after a requested shutdown, 1 if the coordinator refused to register the worker.
  int Run();

  // Stop leasing; finish and report the current task, then return from Run(). Thread-safe.
  void Drain();
  // Stop leasing and abandon the current task (handed back with ReleaseTask). Thread-safe.
  void Abort();

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace farm
