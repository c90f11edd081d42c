#include "daemon/peak_memory.h"

#include <fstream>
#include <sstream>
#include <string>

namespace farm {

PeakMemory PeakMemory::Start() {
  PeakMemory peak;
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  peak.reset_ = static_cast<bool>(clear);
  return peak;
}

std::optional<std::uint64_t> PeakMemory::Bytes() const {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (!line.starts_with("VmHWM:")) continue;
    std::istringstream fields(line.substr(6));
    std::uint64_t kib = 0;
    std::string unit;
    if (fields >> kib >> unit && unit == "kB") return kib * 1024;
    return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace farm
