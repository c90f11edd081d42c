#include "daemon/flags.h"

#include "daemon/coordinator_address.h"

#include <algorithm>
#include <charconv>
#include <optional>
#include <string_view>

namespace farm {

const char kWorkerUsage[] =
    "usage: farm-worker --coordinator HOST:PORT[,...] [--cache-dir DIR] [--cache-max-bytes N]\n"
    "                   [--download-range-bytes N] [--threads N] [--name NAME] [--token TOKEN]\n"
    "                   [--tls-ca FILE] [--insecure] [--texture-cache-mib N]\n"
    "\n"
    "Leases photon emission, render and composite tasks from a photonfarm coordinator until\n"
    "stopped.\n"
    "SIGTERM or SIGINT: finish the current task, report it and exit; a second one abandons\n"
    "the task (it goes back to the queue).\n"
    "\n"
    "  --coordinator HOST:PORT  the coordinator's gRPC address (required); replicas on one\n"
    "                           Redis: one DNS name that resolves to each, or a comma list of\n"
    "                           IP literals (10.0.0.1:50051,10.0.0.2:50051); calls are spread\n"
    "                           over the replicas that answer\n"
    "  --cache-dir DIR          where fetched scenes, meshes and photon snapshots are kept;\n"
    "                           workers sharing it share a snapshot's pages in memory\n"
    "                           (default, shared by this user's workers on the host:\n"
    "                           $XDG_CACHE_HOME/photonfarm/worker, else\n"
    "                           ~/.cache/photonfarm/worker)\n"
    "  --cache-max-bytes N      the most the cache folder may hold: the least recently used\n"
    "                           entries are deleted to make room, never a photon snapshot a\n"
    "                           task is using; suffix K, M, G or T for KiB to TiB (default 8G)\n"
    "  --download-range-bytes N how much of a photon snapshot one download call asks for: a\n"
    "                           cut connection resumes where the bytes stopped, and calls\n"
    "                           spread over the replicas (default 64M)\n"
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

// A byte count: a whole number, optionally followed by K, M, G or T (powers of 1024).
std::optional<std::uint64_t> ParseBytes(std::string_view s) {
  int shift = 0;
  if (!s.empty()) {
    switch (s.back()) {
      case 'K': shift = 10; break;
      case 'M': shift = 20; break;
      case 'G': shift = 30; break;
      case 'T': shift = 40; break;
      default: break;
    }
  }
  if (shift != 0) s.remove_suffix(1);
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size() || v > (UINT64_MAX >> shift)) return std::nullopt;
  return v << shift;
}

std::optional<int> ParseInt(std::string_view s) {
  int v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

// Printable ASCII without spaces: what a gRPC metadata value carries unchanged.
bool IsTokenText(std::string_view s) {
  for (const char c : s) {
    if (c <= ' ' || c > '~') return false;
  }
  return true;
}

}  // namespace

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
    if (name != "--coordinator" && name != "--cache-dir" && name != "--cache-max-bytes" &&
        name != "--download-range-bytes" && name != "--threads" && name != "--name" &&
        name != "--token" && name != "--tls-ca" && name != "--texture-cache-mib") {
      return fail("unknown flag " + std::string(name));
    }
    if (!value) {
      if (i + 1 >= args.size()) return fail(std::string(name) + " needs a value");
      value = args[++i];
    }
    if (name == "--coordinator") {
      if (const auto error = ParseCoordinatorAddresses(*value, out.options.coordinators)) {
        return fail("--coordinator: " + *error);
      }
      have_coordinator = true;
    } else if (name == "--cache-dir") {
      if (value->empty()) return fail("--cache-dir is empty");
      out.options.cache_dir = *value;
      have_cache_dir = true;
    } else if (name == "--cache-max-bytes" || name == "--download-range-bytes") {
      const auto n = ParseBytes(*value);
      const bool cache = name == "--cache-max-bytes";
      if (!n || *n == 0) {
        return fail(std::string(name) + " \"" + *value + "\" is not a positive byte count (e.g. " + (cache ? "8G" : "64M") + ")");
      }
      (cache ? out.options.cache_max_bytes : out.options.download_range_bytes) = *n;
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
  const bool all_loopback = std::ranges::all_of(out.options.coordinators, [](const std::string& a) { return IsLoopbackAddress(a); });
  if (out.options.token.empty()) {
    if (const char* t = getenv("FARM_WORKER_TOKEN"); t && t[0] != '\0') out.options.token = t;
  }
  if (!IsTokenText(out.options.token)) {
    return fail("the worker token has spaces or characters outside printable ASCII");
  }
  if (!out.options.token.empty() && out.options.tls_ca.empty() && !out.options.insecure &&
      !all_loopback) {
    return fail("refusing to send the worker token without TLS to " + JoinedAddresses(out.options) +
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
