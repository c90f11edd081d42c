#include "daemon/coordinator_address.h"

#include <arpa/inet.h>

#include <algorithm>
#include <charconv>

namespace farm {
namespace {

enum class Family { kName, kIPv4, kIPv6 };

std::string_view HostOf(std::string_view host_port) { return host_port.substr(0, host_port.rfind(':')); }

// HOST:PORT with a non-empty host (a name, an IPv4 address or a bracketed IPv6 address)
// and a port in 1..65535.
bool IsHostPort(std::string_view s) {
  const auto colon = s.rfind(':');
  if (colon == std::string_view::npos || colon == 0) return false;
  const std::string_view host = s.substr(0, colon);
  if (host.front() == '[' ? host.back() != ']' || host.size() < 3
                          : host.find_first_of(":/ ") != std::string_view::npos) {
    return false;
  }
  const std::string_view port_text = s.substr(colon + 1);
  int port = 0;
  const auto [end, ec] = std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
  return ec == std::errc() && end == port_text.data() + port_text.size() && port >= 1 && port <= 65535;
}

Family FamilyOf(std::string_view host) {
  unsigned char buffer[16];
  if (host.front() == '[') {
    const std::string inner(host.substr(1, host.size() - 2));
    return inet_pton(AF_INET6, inner.c_str(), buffer) == 1 ? Family::kIPv6 : Family::kName;
  }
  return inet_pton(AF_INET, std::string(host).c_str(), buffer) == 1 ? Family::kIPv4 : Family::kName;
}

constexpr const char* kListOfLiterals =
    "several addresses must be IP literals, all IPv4 or all IPv6 (gRPC's list targets take no names); "
    "for names, give one DNS name that resolves to every coordinator";

// "ADDRESS" then what is wrong with it. (Appended, not +: GCC 12 warns falsely of
// overlapping copies in "..." + std::string.)
std::string Quoted(std::string_view address, std::string_view what) {
  std::string line;
  line.append("\"").append(address).append("\" ").append(what);
  return line;
}

}  // namespace

std::optional<std::string> ParseCoordinatorAddresses(std::string_view text, std::vector<std::string>& out) {
  out.clear();
  std::optional<Family> family;
  for (std::size_t start = 0; start <= text.size();) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string_view address = text.substr(start, comma - start);
    start = comma + 1;
    if (!IsHostPort(address)) {
      return Quoted(address, "is not HOST:PORT (e.g. localhost:50051)");
    }
    const Family f = FamilyOf(HostOf(address));
    if (family && *family != f) {
      return kListOfLiterals;
    }
    family = f;
    if (std::find(out.begin(), out.end(), address) != out.end()) {
      return Quoted(address, "is listed twice");
    }
    out.emplace_back(address);
  }
  if (out.size() > 1 && family == Family::kName) {
    return kListOfLiterals;
  }
  return std::nullopt;
}

std::string CoordinatorTarget(const std::vector<std::string>& addresses) {
  if (addresses.size() == 1) return addresses.front();
  std::string target = FamilyOf(HostOf(addresses.front())) == Family::kIPv6 ? "ipv6:" : "ipv4:";
  for (std::size_t i = 0; i < addresses.size(); ++i) {
    if (i > 0) target += ',';
    target += addresses[i];
  }
  return target;
}

bool IsLoopbackAddress(std::string_view host_port) {
  const std::string_view host = HostOf(host_port);
  return host == "localhost" || host.starts_with("127.") || host == "[::1]";
}

}  // namespace farm
