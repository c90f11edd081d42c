#include "daemon/log.h"

#include <cstdio>
#include <ctime>
#include <string>

namespace farm {

void LogLine(std::string_view message) {
  char stamp[32] = "";
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  if (gmtime_r(&now, &utc)) std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", &utc);
  std::string line = std::string(stamp) + " farm-worker: ";
  line.append(message);
  line += '\n';
  // One write per line: stdio locks the stream for the call.
  std::fwrite(line.data(), 1, line.size(), stderr);
}

}  // namespace farm
