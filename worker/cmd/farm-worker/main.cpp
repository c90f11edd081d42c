// farm-worker: leases photon emission, render and composite tasks from a photonfarm
// coordinator. This file only wires the pieces together; see daemon/ for the logic and
// --help for usage.

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "daemon/flags.h"
#include "daemon/log.h"
#include "daemon/signals.h"
#include "daemon/worker.h"

int main(int argc, char** argv) {
  const farm::ParsedFlags flags =
      farm::ParseWorkerFlags(std::vector<std::string>(argv + 1, argv + argc), std::getenv);
  if (flags.help) {
    std::fputs(farm::kWorkerUsage, stdout);
    return 0;
  }
  if (!flags.error.empty()) {
    std::fprintf(stderr, "farm-worker: %s (see --help)\n", flags.error.c_str());
    return 2;
  }
  const farm::WorkerOptions& options = flags.options;

  std::optional<tbb::global_control> threads;
  if (options.threads > 0) {
    threads.emplace(tbb::global_control::max_allowed_parallelism, options.threads);
  }
  const unsigned cores = options.threads > 0
                             ? static_cast<unsigned>(options.threads)
                             : static_cast<unsigned>(tbb::info::default_concurrency());

  try {
    farm::Worker worker(options, cores);
    // First signal: finish the current task; any later one: abandon it.
    farm::SignalWatcher watcher([&worker](int count, int) {
      if (count == 1) {
        worker.Drain();
      } else {
        worker.Abort();
      }
    });
    return worker.Run();
  } catch (const std::exception& e) {
    farm::Log(farm::LogLevel::kError, "cannot start", {{"err", e.what()}});
    return 1;
  }
}
