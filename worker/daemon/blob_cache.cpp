#include "daemon/blob_cache.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "contract/digest.h"
#include "daemon/sha256.h"

namespace farm {

BlobCache::BlobCache(std::filesystem::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  std::filesystem::create_directories(dir_ / "sha256", ec);
  if (ec) throw std::runtime_error("cannot create cache dir " + dir_.string() + ": " + ec.message());
}

std::filesystem::path BlobCache::PathOf(std::string_view digest) const {
  // Only a validated digest reaches here, so the file name cannot leave the folder.
  return dir_ / "sha256" / std::string(digest.substr(digest.find(':') + 1));
}

std::optional<std::string> BlobCache::Get(std::string_view digest) const {
  if (!contract::IsDigest(digest)) return std::nullopt;
  const auto path = PathOf(digest);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad() || Sha256Digest(bytes) != digest) {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    return std::nullopt;
  }
  return bytes;
}

std::optional<std::filesystem::path> BlobCache::Path(std::string_view digest) const {
  if (!contract::IsDigest(digest)) return std::nullopt;
  auto path = PathOf(digest);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  Sha256 hash;
  std::string chunk(1 << 20, '\0');
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    hash.Update(std::string_view(chunk.data(), static_cast<std::size_t>(in.gcount())));
  }
  if (in.bad() || hash.Finish() != digest) {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    return std::nullopt;
  }
  return path;
}

void BlobCache::Put(std::string_view digest, std::string_view bytes) const {
  if (!contract::IsDigest(digest)) {
    throw std::invalid_argument("malformed blob digest \"" + std::string(digest) + "\"");
  }
  if (Sha256Digest(bytes) != digest) {
    throw std::invalid_argument("blob content does not match digest " + std::string(digest));
  }
  // A name unique to this process and call, renamed into place once complete.
  static std::atomic<unsigned> counter{0};
  const auto final_path = PathOf(digest);
  auto temp = final_path;
  temp += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  struct File {  // closed on every way out
    int fd;
    ~File() {
      if (fd >= 0) ::close(fd);
    }
  } file{::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644)};
  const auto fail = [&temp](const char* what) {
    const std::error_code error(errno, std::generic_category());
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw std::system_error(error, what + temp.string());
  };
  if (file.fd < 0) fail("cannot create cache file ");
  for (std::size_t at = 0; at < bytes.size();) {
    const ssize_t n = ::write(file.fd, bytes.data() + at, bytes.size() - at);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail("cannot write cache file ");
    at += static_cast<std::size_t>(n);
  }
  const int closed = ::close(std::exchange(file.fd, -1));  // close reports late write errors (NFS)
  if (closed != 0) fail("cannot write cache file ");
  std::error_code ec;
  std::filesystem::rename(temp, final_path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw std::system_error(ec, "cannot store cache file " + final_path.string());
  }
}

}  // namespace farm
