#include "daemon/blob_cache.h"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <system_error>

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
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(temp, ignored);
      throw std::runtime_error("cannot write cache file " + temp.string());
    }
  }
  std::error_code ec;
  std::filesystem::rename(temp, final_path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw std::runtime_error("cannot store cache file " + final_path.string() + ": " + ec.message());
  }
}

}  // namespace farm
