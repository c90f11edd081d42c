#include "daemon/blob_cache.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <unistd.h>

#include <fstream>
#include <string>
#include <system_error>
#include <vector>

using namespace std::string_literals;

#include "daemon/sha256.h"

namespace farm {
namespace {

constexpr std::uint64_t kRoomy = std::uint64_t{1} << 30;

// A blob of n bytes, different for each tag.
std::string Blob(char tag, std::size_t n) { return std::string(n, tag); }

class BlobCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("blob_cache_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path dir_;
};

TEST_F(BlobCacheTest, PutThenGet) {
  BlobCache cache(dir_, kRoomy);
  const std::string bytes = "mesh bytes\0with a nul"s;
  const std::string digest = Sha256Digest(bytes);
  EXPECT_FALSE(cache.Get(digest));
  cache.Put(digest, bytes);
  EXPECT_EQ(cache.Get(digest), bytes);
  // Another cache over the same folder (a restarted worker) sees it too.
  EXPECT_EQ(BlobCache(dir_, kRoomy).Get(digest), bytes);
}

TEST_F(BlobCacheTest, WriteErrorsKeepTheirErrorCode) {
  BlobCache cache(dir_, kRoomy);
  // The folder entries go in is a file now: creating one fails with ENOTDIR.
  std::filesystem::remove_all(dir_ / "sha256");
  std::ofstream(dir_ / "sha256") << "not a folder";
  try {
    cache.Put(Sha256Digest("x"), "x");
    FAIL() << "stored";
  } catch (const std::system_error& e) {
    EXPECT_EQ(e.code(), std::errc::not_a_directory) << e.what();
  }
}

TEST_F(BlobCacheTest, RefusesBytesThatDoNotMatchTheDigest) {
  BlobCache cache(dir_, kRoomy);
  EXPECT_THROW(cache.Put(Sha256Digest("one"), "two"), std::invalid_argument);
  EXPECT_THROW(cache.Put("sha256:../../etc/passwd", "two"), std::invalid_argument);
  EXPECT_FALSE(cache.Get(Sha256Digest("one")));
}

TEST_F(BlobCacheTest, DropsCorruptEntries) {
  BlobCache cache(dir_, kRoomy);
  const std::string digest = Sha256Digest("original");
  cache.Put(digest, "original");
  const auto file = dir_ / "sha256" / digest.substr(7);
  ASSERT_TRUE(std::filesystem::exists(file));
  std::ofstream(file, std::ios::binary | std::ios::trunc) << "tampered";
  EXPECT_FALSE(cache.Get(digest));
  EXPECT_FALSE(std::filesystem::exists(file));
}

TEST_F(BlobCacheTest, IgnoresMalformedDigests) {
  BlobCache cache(dir_, kRoomy);
  EXPECT_FALSE(cache.Get("sha256:../x"));
  EXPECT_FALSE(cache.Get(""));
  EXPECT_FALSE(cache.Pin("sha256:../x"));
}

TEST_F(BlobCacheTest, PinOfAVerifiedEntryLargerThanOneChunk) {
  BlobCache cache(dir_, kRoomy);
  std::string bytes(3 * (1 << 20) + 17, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 31 % 251);
  const std::string digest = Sha256Digest(bytes);
  EXPECT_FALSE(cache.Pin(digest));
  cache.Put(digest, bytes);
  const auto pinned = cache.Pin(digest);
  ASSERT_TRUE(pinned);
  EXPECT_EQ(std::filesystem::file_size(pinned->path()), bytes.size());
  // Storing the same blob again (another worker sharing the folder) keeps it valid.
  BlobCache(dir_, kRoomy).Put(digest, bytes);
  EXPECT_EQ(cache.Pin(digest)->path(), pinned->path());
}

TEST_F(BlobCacheTest, PinDropsCorruptEntries) {
  BlobCache cache(dir_, kRoomy);
  const std::string digest = Sha256Digest("snapshot");
  cache.Put(digest, "snapshot");
  const auto file = dir_ / "sha256" / digest.substr(7);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << "snapshoT";
  EXPECT_FALSE(cache.Pin(digest));
  EXPECT_FALSE(std::filesystem::exists(file));
}

// Least recently used first: each read marks an entry used.
TEST_F(BlobCacheTest, EvictsTheLeastRecentlyUsedToStayWithinItsSize) {
  BlobCache cache(dir_, 3000);
  const std::string a = Blob('a', 1000), b = Blob('b', 1000), c = Blob('c', 1000), d = Blob('d', 1000);
  cache.Put(Sha256Digest(a), a);
  cache.Put(Sha256Digest(b), b);
  cache.Put(Sha256Digest(c), c);
  ASSERT_TRUE(cache.Get(Sha256Digest(a)));  // a is now the most recently used; b the least
  cache.Put(Sha256Digest(d), d);
  EXPECT_TRUE(cache.Get(Sha256Digest(a)));
  EXPECT_FALSE(cache.Get(Sha256Digest(b))) << "the least recently used entry was kept";
  EXPECT_TRUE(cache.Get(Sha256Digest(c)));
  EXPECT_TRUE(cache.Get(Sha256Digest(d)));
  std::uint64_t total = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir_ / "sha256")) total += e.file_size();
  EXPECT_LE(total, 3000u);
}

// A pinned entry (a mapped photon snapshot) is never evicted, by this cache or another
// over the same folder (another worker process): a blob that does not fit beside it is
// refused as a full disk, which the worker reports as resource exhaustion.
TEST_F(BlobCacheTest, NeverEvictsAPinnedEntry) {
  BlobCache cache(dir_, 2500);
  const std::string snapshot = Blob('s', 2000), other = Blob('o', 1000);
  cache.Put(Sha256Digest(snapshot), snapshot);
  {
    const auto pinned = cache.Pin(Sha256Digest(snapshot));
    ASSERT_TRUE(pinned);
    BlobCache neighbour(dir_, 2500);
    try {
      neighbour.Put(Sha256Digest(other), other);
      FAIL() << "stored beside a pinned entry, over the size";
    } catch (const std::system_error& e) {
      EXPECT_EQ(e.code(), std::errc::no_space_on_device) << e.what();
      EXPECT_NE(std::string(e.what()).find("--cache-max-bytes"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(std::filesystem::exists(pinned->path()));
    EXPECT_TRUE(cache.Get(Sha256Digest(snapshot)));
  }
  // Unpinned, it is the least recently used entry and makes room.
  BlobCache(dir_, 2500).Put(Sha256Digest(other), other);
  EXPECT_FALSE(cache.Get(Sha256Digest(snapshot)));
  EXPECT_TRUE(cache.Get(Sha256Digest(other)));
}

TEST_F(BlobCacheTest, RefusesABlobLargerThanTheWholeCache) {
  BlobCache cache(dir_, 100);
  const std::string big = Blob('b', 101);
  try {
    cache.Put(Sha256Digest(big), big);
    FAIL() << "stored";
  } catch (const std::system_error& e) {
    EXPECT_EQ(e.code(), std::errc::no_space_on_device) << e.what();
  }
  EXPECT_FALSE(cache.Get(Sha256Digest(big)));
}

// The files in the cache folder whose names mark them temporary (a download in progress).
std::vector<std::filesystem::path> Temporaries(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(dir / "sha256")) {
    if (e.path().filename().string().find('.') != std::string::npos) out.push_back(e.path());
  }
  return out;
}

// A download goes into the cache as it arrives, in pieces, never held whole: once the
// pieces match the digest it is an entry, returned pinned (another worker cannot evict it).
TEST_F(BlobCacheTest, ReceivesABlobInPiecesAndCommitsItPinned) {
  BlobCache cache(dir_, 4000);
  std::string bytes(3000, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 7 % 253);
  const std::string digest = Sha256Digest(bytes);
  auto incoming = cache.Receive(digest, bytes.size());
  for (std::size_t at = 0; at < bytes.size(); at += 1024) {
    incoming.Append(std::string_view(bytes).substr(at, 1024));
    EXPECT_EQ(incoming.size(), std::min(at + 1024, bytes.size()));
  }
  EXPECT_FALSE(cache.Get(digest)) << "visible before it was whole";
  const auto pinned = incoming.Commit();
  ASSERT_TRUE(pinned);
  EXPECT_EQ(pinned->path(), dir_ / "sha256" / digest.substr(7));
  EXPECT_EQ(cache.Get(digest), bytes);
  EXPECT_TRUE(Temporaries(dir_).empty());
  const std::string other = Blob('o', 2000);
  EXPECT_THROW(BlobCache(dir_, 4000).Put(Sha256Digest(other), other), std::system_error)
      << "evicted the pinned entry it just committed";
}

// Bytes that do not match the digest, or a download given up on, leave nothing behind.
TEST_F(BlobCacheTest, DropsAReceivedBlobThatDoesNotMatchOrIsAbandoned) {
  BlobCache cache(dir_, kRoomy);
  const std::string digest = Sha256Digest("the snapshot");
  auto wrong = cache.Receive(digest, 12);
  wrong.Append("the snapshoT");
  EXPECT_FALSE(wrong.Commit());
  EXPECT_FALSE(cache.Get(digest));
  {
    auto abandoned = cache.Receive(digest, 12);
    abandoned.Append("the snap");
    EXPECT_EQ(Temporaries(dir_).size(), 1u);
  }
  EXPECT_TRUE(Temporaries(dir_).empty());
  EXPECT_FALSE(cache.Get(digest));
}

// Room is made before the first byte: a blob larger than the cache is refused at once, as
// a full disk.
TEST_F(BlobCacheTest, ReceiveRefusesABlobLargerThanTheCacheBeforeAnyByte) {
  BlobCache cache(dir_, 100);
  try {
    cache.Receive(Sha256Digest(Blob('b', 101)), 101);
    FAIL() << "receiving";
  } catch (const std::system_error& e) {
    EXPECT_EQ(e.code(), std::errc::no_space_on_device) << e.what();
  }
  EXPECT_TRUE(Temporaries(dir_).empty());
}

// Two workers sharing the folder download the same blob: the second to commit keeps the
// first one's entry, pinned.
TEST_F(BlobCacheTest, ACommitAfterAnotherWorkersKeepsTheirEntry) {
  BlobCache cache(dir_, kRoomy);
  const std::string bytes = Blob('s', 5000), digest = Sha256Digest(bytes);
  auto first = cache.Receive(digest, bytes.size());
  auto second = BlobCache(dir_, kRoomy).Receive(digest, bytes.size());
  first.Append(bytes);
  second.Append(bytes);
  const auto a = first.Commit();
  const auto b = second.Commit();
  ASSERT_TRUE(a);
  ASSERT_TRUE(b);
  EXPECT_EQ(a->path(), b->path());
  EXPECT_EQ(cache.Get(digest), bytes);
  EXPECT_TRUE(Temporaries(dir_).empty());
}

// A worker killed mid-download leaves its temporary file: once it has not been written for
// an hour it is deleted when room is next made; a fresh one (a download in progress) is
// left alone.
TEST_F(BlobCacheTest, MakingRoomDeletesTheTemporaryFilesOfDeadDownloads) {
  BlobCache cache(dir_, kRoomy);
  const auto stale = dir_ / "sha256" / "abc.tmp.99999.0";
  const auto fresh = dir_ / "sha256" / "def.tmp.99999.1";
  std::ofstream(stale) << "half a snapshot";
  std::ofstream(fresh) << "a download in progress";
  std::filesystem::last_write_time(stale, std::filesystem::file_time_type::clock::now() - std::chrono::hours(2));
  cache.Put(Sha256Digest("x"), "x");
  EXPECT_FALSE(std::filesystem::exists(stale));
  EXPECT_TRUE(std::filesystem::exists(fresh));
}

}  // namespace
}  // namespace farm
