#include "photonmap/shard_format.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "photonmap/oct_direction.h"

namespace farm {
namespace {

Vec3 RandomUnit(std::mt19937& rng) {
  std::normal_distribution<float> g;
  for (;;) {
    Vec3 v(g(rng), g(rng), g(rng));
    if (LengthSquared(v) > 1e-6f) return Normalize(v);
  }
}

float AngleDegrees(const Vec3& a, const Vec3& b) {
  float c = std::fmin(1.0f, std::fmax(-1.0f, Dot(a, b)));
  return std::acos(c) * 180.0f / std::numbers::pi_v<float>;
}

TEST(OctDirection, RoundTripErrorIsSmall) {
  std::mt19937 rng(7);
  float worst8 = 0, worst7 = 0;
  for (int i = 0; i < 200000; ++i) {
    Vec3 d = RandomUnit(rng);
    worst8 = std::fmax(worst8, AngleDegrees(d, DecodeOct8(EncodeOct8(d))));
    worst7 = std::fmax(worst7, AngleDegrees(d, DecodeOct7Normal(EncodeOct7Normal(d))));
  }
  EXPECT_LT(worst8, 1.0f);  // Cigolle et al. 2014 give ~0.94 degrees for oct16
  EXPECT_LT(worst7, 2.0f);
}

TEST(OctDirection, AxesAndNormalLowBits) {
  for (Vec3 d : {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1),
                 Vec3(0, 0, -1)}) {
    EXPECT_LT(AngleDegrees(d, DecodeOct8(EncodeOct8(d))), 1e-3f) << d;
    std::uint16_t n = EncodeOct7Normal(d);
    EXPECT_EQ(n & 3u, 0u);
    EXPECT_LT(AngleDegrees(d, DecodeOct7Normal(n)), 1e-3f) << d;
    EXPECT_LT(AngleDegrees(d, DecodeOct7Normal(n | 3u)), 1e-3f) << "axis bits are ignored";
  }
  EXPECT_LT(AngleDegrees(Vec3(0, 0, 1), DecodeOct8(EncodeOct8(Vec3(0, 0, 0)))), 1e-3f);
}

TEST(ShardFormat, RoundTripsHeaderAndRecords) {
  std::mt19937 rng(3);
  std::vector<ShardPhoton> photons;
  for (int i = 0; i < 10; ++i) {
    photons.push_back({Vec3(float(i), -2.5f, 1e6f), Rgb(0.25f, float(i), 0), RandomUnit(rng),
                       RandomUnit(rng)});
  }
  std::string bytes = EncodeShard(PhotonMapKind::kCaustic, 1000, 500, photons);
  ASSERT_EQ(bytes.size(), kShardHeaderSize + kShardRecordSize * photons.size());
  EXPECT_EQ(bytes.substr(0, 8), "PFSHARD1");
  DecodedShard shard = DecodeShard(bytes);
  EXPECT_EQ(shard.kind, PhotonMapKind::kCaustic);
  EXPECT_EQ(shard.first_photon, 1000u);
  EXPECT_EQ(shard.photon_count, 500u);
  ASSERT_EQ(shard.records.size(), photons.size());
  for (std::size_t i = 0; i < photons.size(); ++i) {
    EXPECT_EQ(shard.records[i].position, photons[i].position);
    EXPECT_EQ(shard.records[i].power, photons[i].power);
    EXPECT_EQ(shard.records[i].wi_oct8, EncodeOct8(photons[i].wi));
    EXPECT_EQ(shard.records[i].normal_oct7, EncodeOct7Normal(photons[i].normal));
  }
}

TEST(ShardFormat, EncodeRefusesBadPhotons) {
  const float nan = std::nanf("");
  const float inf = INFINITY;
  struct Case {
    const char* name;
    ShardPhoton photon;
  } cases[] = {
      {"nan position", {Vec3(nan, 0, 0), Rgb(1), Vec3(0, 0, 1), Vec3(0, 0, 1)}},
      {"inf position", {Vec3(0, inf, 0), Rgb(1), Vec3(0, 0, 1), Vec3(0, 0, 1)}},
      {"negative power", {Vec3(0, 0, 0), Rgb(1, -1, 1), Vec3(0, 0, 1), Vec3(0, 0, 1)}},
      {"nan power", {Vec3(0, 0, 0), Rgb(1, 1, nan), Vec3(0, 0, 1), Vec3(0, 0, 1)}},
  };
  for (const Case& c : cases) {
    EXPECT_THROW(EncodeShard(PhotonMapKind::kGlobal, 0, 1, {c.photon}), std::invalid_argument)
        << c.name;
  }
}

TEST(ShardFormat, DecodeRefusesMalformedShards) {
  std::string good =
      EncodeShard(PhotonMapKind::kGlobal, 0, 1, {{Vec3(1, 2, 3), Rgb(1), Vec3(0, 0, 1),
                                                  Vec3(0, 0, 1)}});
  auto with = [&](std::size_t offset, unsigned char byte) {
    std::string b = good;
    b[offset] = static_cast<char>(byte);
    return b;
  };
  struct Case {
    const char* name;
    std::string bytes;
  } cases[] = {
      {"empty", ""},
      {"short header", good.substr(0, 39)},
      {"magic", with(0, 'X')},
      {"version", with(8, 2)},
      {"kind", with(12, 4)},
      {"record count", with(32, 2)},
      {"truncated record", good.substr(0, good.size() - 1)},
      {"trailing byte", good + "x"},
      {"nan position", with(43, 0xff)},  // exponent bits of x all ones
      {"negative power", with(55, 0x80 | static_cast<unsigned char>(good[55]))},
      {"normal low bits", with(66, static_cast<unsigned char>(good[66]) | 1u)},
  };
  for (const Case& c : cases) {
    EXPECT_THROW(DecodeShard(c.bytes), std::runtime_error) << c.name;
  }
  EXPECT_NO_THROW(DecodeShard(good));
}

}  // namespace
}  // namespace farm
