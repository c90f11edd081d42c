#include "daemon/sha256.h"

#include <gtest/gtest.h>

#include <string>

#include "contract/digest.h"

namespace farm {
namespace {

// Test vectors from FIPS 180-2 and NIST's SHA examples.
TEST(Sha256, KnownVectors) {
  EXPECT_EQ(Sha256Digest(""),
            "sha256:e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Digest("abc"),
            "sha256:ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Digest("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "sha256:248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(Sha256Digest(std::string(1000000, 'a')),
            "sha256:cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, IncrementalEqualsOneShot) {
  const std::string data = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
  Sha256 h;
  for (std::size_t at = 0; at < data.size(); at += 7) h.Update(std::string_view(data).substr(at, 7));
  EXPECT_EQ(h.Finish(), Sha256Digest(data));
}

TEST(Sha256, ValidDigestsOnly) {
  EXPECT_TRUE(contract::IsDigest(Sha256Digest("x")));
  EXPECT_FALSE(contract::IsDigest(""));
  EXPECT_FALSE(contract::IsDigest("sha256:"));
  EXPECT_FALSE(contract::IsDigest("md5:" + std::string(64, 'a')));
  EXPECT_FALSE(contract::IsDigest("sha256:" + std::string(63, 'a')));
  EXPECT_FALSE(contract::IsDigest("sha256:" + std::string(65, 'a')));
  EXPECT_FALSE(contract::IsDigest("sha256:" + std::string(64, 'A')));  // Lowercase only.
  EXPECT_FALSE(contract::IsDigest("sha256:../../" + std::string(58, 'a')));
}

}  // namespace
}  // namespace farm
