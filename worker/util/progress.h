#pragma once

// How far a task has come: a counter the running task owns and its code advances as it
// works, so that the heartbeat can tell the coordinator the task is moving (HeldLease.progress
// in worker.proto; a lease whose progress stops growing is revoked as stuck).

#include <atomic>
#include <cstdint>

namespace farm {

// A task's progress counter. Its unit is whatever the work counts (camera samples, photon
// paths, tiles, bytes transferred); only its growth means anything.
using ProgressCounter = std::atomic<std::uint64_t>;

// A handle on a ProgressCounter, passed by value next to the stop token into the code that
// does the work, from any number of threads. A default Progress counts nowhere, so callers
// that do not report (tests, tools, the benchmark) pass nothing. The counter must outlive
// every copy of the handle.
//
// Kept apart from the stop token rather than bundled with it: the stop token also reaches
// code with nothing to count (retries, sleeps), and a defaulted trailing parameter leaves
// every existing call unchanged.
class Progress {
 public:
  Progress() = default;
  explicit Progress(ProgressCounter& counter) : counter_(&counter) {}

  // Relaxed is enough: a reader needs only a value that never goes back, which the single
  // modification order of one atomic gives; it orders nothing else.
  void Advance(std::uint64_t amount = 1) const noexcept {
    if (counter_ != nullptr) counter_->fetch_add(amount, std::memory_order_relaxed);
  }

 private:
  ProgressCounter* counter_ = nullptr;
};

}  // namespace farm
