#include "daemon/blob_cache.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <unistd.h>

#include <fstream>
#include <string>
#include <system_error>

using namespace std::string_literals;

#include "daemon/sha256.h"

namespace farm {
namespace {

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
  BlobCache cache(dir_);
  const std::string bytes = "mesh bytes\0with a nul"s;
  const std::string digest = Sha256Digest(bytes);
  EXPECT_FALSE(cache.Get(digest));
  cache.Put(digest, bytes);
  EXPECT_EQ(cache.Get(digest), bytes);
  // Another cache over the same folder (a restarted worker) sees it too.
  EXPECT_EQ(BlobCache(dir_).Get(digest), bytes);
}

TEST_F(BlobCacheTest, WriteErrorsKeepTheirErrorCode) {
  BlobCache cache(dir_);
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
  BlobCache cache(dir_);
  EXPECT_THROW(cache.Put(Sha256Digest("one"), "two"), std::invalid_argument);
  EXPECT_THROW(cache.Put("sha256:../../etc/passwd", "two"), std::invalid_argument);
  EXPECT_FALSE(cache.Get(Sha256Digest("one")));
}

TEST_F(BlobCacheTest, DropsCorruptEntries) {
  BlobCache cache(dir_);
  const std::string digest = Sha256Digest("original");
  cache.Put(digest, "original");
  const auto file = dir_ / "sha256" / digest.substr(7);
  ASSERT_TRUE(std::filesystem::exists(file));
  std::ofstream(file, std::ios::binary | std::ios::trunc) << "tampered";
  EXPECT_FALSE(cache.Get(digest));
  EXPECT_FALSE(std::filesystem::exists(file));
}

TEST_F(BlobCacheTest, IgnoresMalformedDigests) {
  BlobCache cache(dir_);
  EXPECT_FALSE(cache.Get("sha256:../x"));
  EXPECT_FALSE(cache.Get(""));
  EXPECT_FALSE(cache.Path("sha256:../x"));
}

TEST_F(BlobCacheTest, PathOfAVerifiedEntryLargerThanOneChunk) {
  BlobCache cache(dir_);
  std::string bytes(3 * (1 << 20) + 17, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 31 % 251);
  const std::string digest = Sha256Digest(bytes);
  EXPECT_FALSE(cache.Path(digest));
  cache.Put(digest, bytes);
  const auto path = cache.Path(digest);
  ASSERT_TRUE(path);
  EXPECT_EQ(std::filesystem::file_size(*path), bytes.size());
  // Storing the same blob again (another worker sharing the folder) keeps it valid.
  BlobCache(dir_).Put(digest, bytes);
  EXPECT_EQ(cache.Path(digest), path);
}

TEST_F(BlobCacheTest, PathDropsCorruptEntries) {
  BlobCache cache(dir_);
  const std::string digest = Sha256Digest("snapshot");
  cache.Put(digest, "snapshot");
  const auto file = dir_ / "sha256" / digest.substr(7);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << "snapshoT";
  EXPECT_FALSE(cache.Path(digest));
  EXPECT_FALSE(std::filesystem::exists(file));
}

}  // namespace
}  // namespace farm
