#include "daemon/blob_cache.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <stdexcept>
#include <system_error>
#include <utility>
#include <vector>

#include "contract/digest.h"
#include "daemon/sha256.h"

namespace farm {
namespace {

// A file descriptor closed on every way out.
struct Fd {
  int fd = -1;
  Fd() = default;
  explicit Fd(int f) : fd(f) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
  int release() { return std::exchange(fd, -1); }
};

// Marks the file used now, with the clock's full precision (file systems stamp their own
// times coarsely, a few milliseconds apart).
void Touch(int fd) {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                      std::chrono::system_clock::now().time_since_epoch())
                      .count();
  const timespec now{static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
  const timespec times[2] = {now, now};
  ::futimens(fd, times);  // Failing costs only the order of eviction.
}

// Whether fd is still the file at path (not replaced or deleted since it was opened).
bool StillAt(int fd, const std::filesystem::path& path) {
  struct stat open_file {}, named {};
  return ::fstat(fd, &open_file) == 0 && ::stat(path.c_str(), &named) == 0 &&
         open_file.st_dev == named.st_dev && open_file.st_ino == named.st_ino;
}

// Reads fd to its end and checks the bytes against digest; the bytes are kept if `keep`.
bool ReadsAs(int fd, std::string_view digest, std::string* keep) {
  Sha256 hash;
  std::string chunk(1 << 20, '\0');
  while (true) {
    const ssize_t n = ::read(fd, chunk.data(), chunk.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return false;
    if (n == 0) break;
    const std::string_view part(chunk.data(), static_cast<std::size_t>(n));
    hash.Update(part);
    if (keep) keep->append(part);
  }
  return hash.Finish() == digest;
}

std::system_error NoSpace(const std::string& what) {
  return std::system_error(std::make_error_code(std::errc::no_space_on_device), what);
}

// A download in progress writes its temporary file every few milliseconds; one untouched
// for this long was left by a worker that died mid-download (a snapshot's can be
// gigabytes), and is deleted the next time room is made.
constexpr auto kStaleTemporary = std::chrono::hours(1);

void RemoveIfStale(const std::filesystem::path& temporary) {
  std::error_code ec;
  const auto written = std::filesystem::last_write_time(temporary, ec);
  if (!ec && std::filesystem::file_time_type::clock::now() - written > kStaleTemporary) {
    std::filesystem::remove(temporary, ec);
  }
}

struct Entry {
  std::filesystem::path path;
  std::uint64_t size;
  std::chrono::nanoseconds used;
};

}  // namespace

BlobCache::Pinned::Pinned(Pinned&& other) noexcept
    : path_(std::move(other.path_)), fd_(std::exchange(other.fd_, -1)) {}

BlobCache::Pinned& BlobCache::Pinned::operator=(Pinned&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(other.path_);
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

BlobCache::Pinned::~Pinned() {
  if (fd_ >= 0) ::close(fd_);  // Releases the lock.
}

BlobCache::BlobCache(std::filesystem::path dir, std::uint64_t max_bytes)
    : dir_(std::move(dir)), max_bytes_(max_bytes) {
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
  Fd file(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (file.fd < 0) return std::nullopt;
  std::string bytes;
  if (!ReadsAs(file.fd, digest, &bytes)) {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    return std::nullopt;
  }
  Touch(file.fd);
  return bytes;
}

std::optional<BlobCache::Pinned> BlobCache::Pin(std::string_view digest) const {
  if (!contract::IsDigest(digest)) return std::nullopt;
  return PinAt(PathOf(digest), digest);
}

std::optional<BlobCache::Pinned> BlobCache::PinAt(std::filesystem::path path, std::string_view digest) {
  Fd file(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (file.fd < 0) return std::nullopt;
  // Locked first, then checked to be still the entry: an eviction between the open and the
  // lock would leave a deleted file, which callers that map the path cannot use.
  while (::flock(file.fd, LOCK_SH) != 0) {
    if (errno != EINTR) return std::nullopt;
  }
  if (!StillAt(file.fd, path)) return std::nullopt;
  if (!ReadsAs(file.fd, digest, nullptr)) {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    return std::nullopt;
  }
  Touch(file.fd);
  return Pinned(std::move(path), file.release());
}

void BlobCache::MakeRoom(std::string_view digest, std::uint64_t needed) const {
  if (needed > max_bytes_) {
    throw NoSpace("blob " + std::string(digest) + " of " + std::to_string(needed) +
                  " bytes is larger than the worker's cache of " + std::to_string(max_bytes_) +
                  " bytes (--cache-max-bytes)");
  }
  std::vector<Entry> entries;
  std::uint64_t total = 0;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir_ / "sha256", ec)) {
    if (e.path().filename().string().find('.') != std::string::npos) {
      RemoveIfStale(e.path());
      continue;  // A download in progress, here or in another worker.
    }
    struct stat st {};
    if (::stat(e.path().c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;
    const auto used = std::chrono::seconds(st.st_mtim.tv_sec) + std::chrono::nanoseconds(st.st_mtim.tv_nsec);
    entries.push_back({e.path(), static_cast<std::uint64_t>(st.st_size), used});
    total += static_cast<std::uint64_t>(st.st_size);
  }
  if (total + needed <= max_bytes_) return;
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.used != b.used ? a.used < b.used : a.path < b.path;
  });
  std::uint64_t pinned = 0;
  for (const Entry& e : entries) {
    if (total + needed <= max_bytes_) return;
    Fd file(::open(e.path.c_str(), O_RDONLY | O_CLOEXEC));
    if (file.fd < 0) {  // Gone already: another worker evicted it.
      total -= e.size;
      continue;
    }
    // An exclusive lock fails while anyone holds the entry pinned.
    if (::flock(file.fd, LOCK_EX | LOCK_NB) != 0 || !StillAt(file.fd, e.path)) {
      pinned += e.size;
      continue;
    }
    std::filesystem::remove(e.path, ec);
    total -= e.size;
  }
  if (total + needed > max_bytes_) {
    throw NoSpace("the worker's cache is full: blob " + std::string(digest) + " of " + std::to_string(needed) +
                  " bytes does not fit beside " + std::to_string(pinned) + " bytes of entries in use, in " +
                  std::to_string(max_bytes_) + " bytes (--cache-max-bytes)");
  }
}

void BlobCache::Put(std::string_view digest, std::string_view bytes) const {
  if (!contract::IsDigest(digest)) {
    throw std::invalid_argument("malformed blob digest \"" + std::string(digest) + "\"");
  }
  if (std::filesystem::exists(PathOf(digest))) return;  // Checked whenever it is read.
  Incoming incoming = Receive(digest, bytes.size());
  incoming.Append(bytes);
  if (!incoming.Commit()) {
    throw std::invalid_argument("blob content does not match digest " + std::string(digest));
  }
}

BlobCache::Incoming BlobCache::Receive(std::string_view digest, std::uint64_t size) const {
  if (!contract::IsDigest(digest)) {
    throw std::invalid_argument("malformed blob digest \"" + std::string(digest) + "\"");
  }
  MakeRoom(digest, size);
  // A name unique to this process and call, linked into place once complete; a name with a
  // dot is never taken for an entry.
  static std::atomic<unsigned> counter{0};
  auto temp = PathOf(digest);
  temp += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw std::system_error(errno, std::generic_category(), "cannot create cache file " + temp.string());
  }
  return Incoming(std::string(digest), PathOf(digest), std::move(temp), fd);
}

BlobCache::Incoming::Incoming(Incoming&& other) noexcept
    : digest_(std::move(other.digest_)),
      path_(std::move(other.path_)),
      temp_(std::move(other.temp_)),
      fd_(std::exchange(other.fd_, -1)),
      hash_(std::move(other.hash_)),
      written_(other.written_) {}

BlobCache::Incoming::~Incoming() {
  if (fd_ < 0) return;  // Moved from, or committed.
  ::close(fd_);
  std::error_code ignored;
  std::filesystem::remove(temp_, ignored);
}

void BlobCache::Incoming::Append(std::string_view bytes) {
  for (std::size_t at = 0; at < bytes.size();) {
    const ssize_t n = ::write(fd_, bytes.data() + at, bytes.size() - at);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw std::system_error(errno, std::generic_category(), "cannot write cache file " + temp_.string());
    at += static_cast<std::size_t>(n);
  }
  hash_.Update(bytes);
  written_ += bytes.size();
}

std::optional<BlobCache::Pinned> BlobCache::Incoming::Commit() {
  Fd file(std::exchange(fd_, -1));
  std::error_code ignored;
  if (hash_.Finish() != digest_) {
    std::filesystem::remove(temp_, ignored);
    return std::nullopt;
  }
  Touch(file.fd);
  // Pinned before it is visible: the lock belongs to the file, whichever name opens it, so
  // no worker can evict the entry between its link and the caller's use. The lock lives on
  // in a duplicate, so that closing the writer still reports late write errors (NFS).
  while (::flock(file.fd, LOCK_SH) != 0) {
    if (errno != EINTR) break;  // Unpinned, then: a rare eviction costs a download.
  }
  Fd pin(::dup(file.fd));
  if (::close(file.release()) != 0 || pin.fd < 0) {
    const std::error_code error(errno, std::generic_category());
    std::filesystem::remove(temp_, ignored);
    throw std::system_error(error, "cannot write cache file " + temp_.string());
  }
  // A link, unlike a rename, never replaces an entry another worker stored meanwhile (which
  // it may have pinned); the content is the same.
  const int linked = ::link(temp_.c_str(), path_.c_str());
  const std::error_code error(errno, std::generic_category());
  std::filesystem::remove(temp_, ignored);
  if (linked == 0) return Pinned(path_, pin.release());
  if (error != std::errc::file_exists) {
    throw std::system_error(error, "cannot store cache file " + path_.string());
  }
  return PinAt(path_, digest_);
}

}  // namespace farm
