#include "daemon/flags.h"

#include <charconv>
#include <optional>
#include <string_view>

namespace farm {

const char kWorkerUsage[] =
    "usage: farm-worker --coordinator HOST:PORT [--cache-dir DIR] [--threads N] [--name NAME]\n"
    "                   [--token TOKEN] [--tls-ca FILE] [--insecure] [--texture-cache-mib N]\n"
    "\n"
    "Leases photon emission, render and composite tasks from a photonfarm coordinator until\n"
    "stopped.\n"
    "SIGTERM or SIGINT: finish the current task, report it and exit; a second one abandons\n"
    "the task (it goes back to the queue).\n"
    "\n"
    "  --coordinator HOST:PORT  the coordinator's gRPC address (required)\n"
    "  --cache-dir DIR          where fetched scenes, meshes and photon snapshots are kept;\n"
    "                           workers sharing it share a snapshot's pages in memory\n"
    "                           (default, shared by this user's workers on the host:\n"
    "                           $XDG_CACHE_HOME/photonfarm/worker, else\n"
    "                           ~/.cache/photonfarm/worker)\n"
    "  --threads N              render threads (default: all cores)\n"
    "  --name NAME              the name the farm shows for this worker (default: hostname)\n"
    "  --token TOKEN            worker token the coordinator was given, sent on every call\n"
    "                           (default: $FARM_WORKER_TOKEN); prefer the variable, a\n"
    "                           command line is visible to every user of the host\n"
    "  --tls-ca FILE            connect with TLS, trusting the CA certificates in FILE (PEM)\n"
    "  --insecure               allow a token without TLS to a coordinator not on loopback\n"
    "  --texture-cache-mib N    memory for texture tiles, MiB (default 512); textures are\n"
    "                           prepared once into DIR/textures under the cache directory\n"
    "  --help                   show this help\n";

namespace {

constexpr int kMaxThreads = 4096;
constexpr int kMaxTextureCacheMib = 1 << 20;

std::optional<int> ParseInt(std::string_view s) {
  int v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

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
  const auto port = ParseInt(s.substr(colon + 1));
  return port && *port >= 1 && *port <= 65535;
}

// Printable ASCII without spaces: what a gRPC metadata value carries unchanged.
bool IsTokenText(std::string_view s) {
  for (const char c : s) {
    if (c <= ' ' || c > '~') return false;
  }
  return true;
}

}  // namespace

bool IsLoopbackAddress(const std::string& host_port) {
  const auto colon = host_port.rfind(':');
  const std::string_view host = std::string_view(host_port).substr(0, colon);
  return host == "localhost" || host.starts_with("127.") || host == "[::1]";
}

ParsedFlags ParseWorkerFlags(const std::vector<std::string>& args,
                             const std::function<const char*(const char*)>& getenv) {
  ParsedFlags out;
  auto fail = [&out](std::string message) {
    out.error = std::move(message);
    return out;
  };
  bool have_coordinator = false;
  bool have_cache_dir = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string_view arg = args[i];
    if (arg == "--help" || arg == "-h") {
      out.help = true;
      return out;
    }
    if (!arg.starts_with("--")) return fail("unexpected argument \"" + std::string(arg) + "\"");
    if (arg == "--insecure") {
      out.options.insecure = true;
      continue;
    }
    std::string_view name = arg;
    std::optional<std::string> value;
    if (const auto eq = arg.find('='); eq != std::string_view::npos) {
      name = arg.substr(0, eq);
      value = std::string(arg.substr(eq + 1));
    }
    if (name != "--coordinator" && name != "--cache-dir" && name != "--threads" &&
        name != "--name" && name != "--token" && name != "--tls-ca" && name != "--texture-cache-mib") {
      return fail("unknown flag " + std::string(name));
    }
    if (!value) {
      if (i + 1 >= args.size()) return fail(std::string(name) + " needs a value");
      value = args[++i];
    }
    if (name == "--coordinator") {
      if (!IsHostPort(*value)) {
        return fail("--coordinator \"" + *value + "\" is not HOST:PORT (e.g. localhost:50051)");
      }
      out.options.coordinator = *value;
      have_coordinator = true;
    } else if (name == "--cache-dir") {
      if (value->empty()) return fail("--cache-dir is empty");
      out.options.cache_dir = *value;
      have_cache_dir = true;
    } else if (name == "--threads" || name == "--texture-cache-mib") {
      const bool threads = name == "--threads";
      const int max = threads ? kMaxThreads : kMaxTextureCacheMib;
      const auto n = ParseInt(*value);
      if (!n || *n < 1 || *n > max) {
        return fail(std::string(name) + " \"" + *value + "\" is not a whole number from 1 to " + std::to_string(max));
      }
      (threads ? out.options.threads : out.options.texture_cache_mib) = *n;
    } else if (name == "--token") {
      if (value->empty()) return fail("--token is empty");
      out.options.token = *value;
    } else if (name == "--tls-ca") {
      if (value->empty()) return fail("--tls-ca is empty");
      out.options.tls_ca = *value;
    } else {
      if (value->empty()) return fail("--name is empty");
      out.options.name = *value;
    }
  }
  if (!have_coordinator) return fail("--coordinator HOST:PORT is required");
  if (out.options.token.empty()) {
    if (const char* t = getenv("FARM_WORKER_TOKEN"); t && t[0] != '\0') out.options.token = t;
  }
  if (!IsTokenText(out.options.token)) {
    return fail("the worker token has spaces or characters outside printable ASCII");
  }
  if (!out.options.token.empty() && out.options.tls_ca.empty() && !out.options.insecure &&
      !IsLoopbackAddress(out.options.coordinator)) {
    return fail("refusing to send the worker token without TLS to " + out.options.coordinator +
                " (not loopback): pass --tls-ca FILE, or --insecure on a trusted network");
  }
  if (!have_cache_dir) {
    const char* xdg = getenv("XDG_CACHE_HOME");
    const char* home = getenv("HOME");
    // The XDG spec says a relative XDG_CACHE_HOME is invalid and must be ignored.
    if (xdg && xdg[0] == '/') {
      out.options.cache_dir = std::filesystem::path(xdg) / "photonfarm" / "worker";
    } else if (home && home[0] != '\0') {
      out.options.cache_dir = std::filesystem::path(home) / ".cache" / "photonfarm" / "worker";
    } else {
      return fail("neither XDG_CACHE_HOME nor HOME is set; pass --cache-dir DIR");
    }
  }
  return out;
}

}  // namespace farm
