#pragma once

// The farm-worker command line, parsed apart from main() so it can be tested.

#include <functional>
#include <string>
#include <vector>

#include "daemon/options.h"

namespace farm {

extern const char kWorkerUsage[];

struct ParsedFlags {
  WorkerOptions options;
  bool help = false;   // --help was given: print kWorkerUsage and exit 0.
  std::string error;   // Non-empty: a one-line description of what is wrong.
};

// Parses the arguments after the program name. Flags take their value as the next
// argument or after "=". `getenv` supplies XDG_CACHE_HOME and HOME for the default cache
// directory ($XDG_CACHE_HOME/photonfarm/worker, else ~/.cache/photonfarm/worker) and
// FARM_WORKER_TOKEN when --token is not given. A token without --tls-ca is refused for a
// coordinator that is not on loopback unless --insecure is given.
ParsedFlags ParseWorkerFlags(const std::vector<std::string>& args,
                             const std::function<const char*(const char*)>& getenv);

}  // namespace farm
