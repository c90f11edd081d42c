#pragma once

// For tests (not linked into the worker) of code that reports progress: what a heartbeat
// reading the counter from another thread sees while the work runs.

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

#include "util/progress.h"

namespace farm::testing {

// Runs work(Progress(counter)) while another thread polls counter, and returns the values
// that thread saw, each change once.
template <typename Work>
std::vector<std::uint64_t> ProgressSeenDuring(ProgressCounter& counter, Work&& work) {
  std::atomic<bool> done{false};
  std::vector<std::uint64_t> seen;
  std::jthread watcher([&] {
    while (!done.load()) {
      const std::uint64_t now = counter.load();
      if (seen.empty() || now != seen.back()) seen.push_back(now);
    }
  });
  work(Progress(counter));
  done = true;
  watcher.join();
  return seen;
}

}  // namespace farm::testing
