#pragma once

// The worker process's peak resident memory over one task (the "scale" item: a
// task's log line says what it took). Linux keeps a high-water mark of resident memory
// (VmHWM in /proc/self/status); writing "5" to /proc/self/clear_refs (Linux 4.0 and later)
// resets it to the current resident size. Where it cannot be reset (an older kernel, a
// /proc that refuses the write) the mark is the process's since it started, and says so.

#include <cstdint>
#include <optional>

namespace farm {

class PeakMemory {
 public:
  // Starts measuring: resets the mark if it can.
  static PeakMemory Start();

  // The peak resident bytes since Start (or since the process started: see since_start),
  // or nothing where /proc does not say.
  std::optional<std::uint64_t> Bytes() const;
  // Whether Bytes counts from the start of the process rather than from Start.
  bool since_start() const { return !reset_; }

 private:
  bool reset_ = false;
};

}  // namespace farm
