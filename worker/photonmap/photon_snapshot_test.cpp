#include "photonmap/photon_snapshot.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "photonmap/byte_io.h"
#include "photonmap/kd_photon_map.h"
#include "photonmap/oct_direction.h"
#include "photonmap/rgb9e5.h"
#include "photonmap/shard_format.h"
#include "util/read_file.h"

namespace farm {
namespace {

namespace fs = std::filesystem;

struct VectorCase {
  std::string name;
  std::vector<DecodedShard> shards;
  fs::path snapshot;
};

std::vector<VectorCase> LoadVectors() {
  std::vector<VectorCase> cases;
  for (const auto& dir : fs::directory_iterator(PHOTON_SNAPSHOT_VECTORS)) {
    if (!dir.is_directory()) continue;
    VectorCase c{dir.path().filename().string(), {}, dir.path() / "snapshot.bin"};
    std::vector<fs::path> shards;
    for (const auto& f : fs::directory_iterator(dir.path())) {
      if (f.path().filename().string().starts_with("shard-")) shards.push_back(f.path());
    }
    std::sort(shards.begin(), shards.end());
    for (const auto& s : shards) c.shards.push_back(DecodeShard(ReadFile(s)));
    cases.push_back(std::move(c));
  }
  std::sort(cases.begin(), cases.end(),
            [](const VectorCase& a, const VectorCase& b) { return a.name < b.name; });
  return cases;
}

using PhotonKey = std::tuple<float, float, float, std::uint32_t, std::uint16_t, std::uint16_t>;

// Every node's subtree lies within the bounds its ancestors' split planes set.
void CheckTree(const KdPhotonMap& map, std::size_t i, Vec3 lo, Vec3 hi) {
  if (i >= map.size()) return;
  Vec3 p = map.photon(i).position;
  for (int c = 0; c < 3; ++c) {
    ASSERT_TRUE(p[c] >= lo[c] && p[c] <= hi[c]) << "node " << i << " at " << p;
  }
  unsigned a = map.split_axis(i);
  ASSERT_EQ(a == kLeafAxis, 2 * i + 1 >= map.size()) << "node " << i;
  if (a == kLeafAxis) return;
  Vec3 left_hi = hi, right_lo = lo;
  float* lh = &left_hi.x;
  float* rl = &right_lo.x;
  lh[a] = p[a];
  rl[a] = p[a];
  CheckTree(map, 2 * i + 1, lo, left_hi);
  CheckTree(map, 2 * i + 2, right_lo, hi);
}

using Neighbour = std::pair<float, std::uint32_t>;  // (distance_squared, index)

// The k photons strictly within radius with the smallest (distance_squared, index): ties
// in distance go to the lower index, as KdPhotonMap::NearestK promises.
std::vector<Neighbour> BruteForce(const PhotonMap& map, const Vec3& q, int k, float radius) {
  std::vector<Neighbour> all;
  const float r2 = radius * radius;
  for (std::size_t i = 0; i < map.size(); ++i) {
    Vec3 p = map.photon(i).position;
    // Same float expression as the search, so boundary cases agree bit for bit.
    float dx = q.x - p.x, dy = q.y - p.y, dz = q.z - p.z;
    float d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < r2) all.emplace_back(d2, std::uint32_t(i));
  }
  std::sort(all.begin(), all.end());
  if (all.size() > std::size_t(std::max(k, 0))) all.resize(std::max(k, 0));
  return all;
}

TEST(PhotonSnapshotVectors, DecodedPhotonsEqualTheShardPhotons) {
  auto cases = LoadVectors();
  ASSERT_GE(cases.size(), 5u) << "no vectors under " << PHOTON_SNAPSHOT_VECTORS;
  int volume_maps = 0;  // the vectors' three-maps and volume-only cases
  for (const VectorCase& c : cases) {
    SCOPED_TRACE(c.name);
    PhotonSnapshot snap = PhotonSnapshot::Open(c.snapshot);
    volume_maps += snap.map(PhotonMapKind::kVolume) != nullptr;
    for (PhotonMapKind kind : kPhotonMapKinds) {
      std::vector<ShardRecord> input;
      std::uint64_t paths = 0;
      bool present = false;
      for (const DecodedShard& s : c.shards) {
        if (s.kind != kind) continue;
        present = true;
        paths += s.photon_count;
        input.insert(input.end(), s.records.begin(), s.records.end());
      }
      const auto* map = dynamic_cast<const KdPhotonMap*>(snap.map(kind));
      ASSERT_EQ(map != nullptr, present);
      if (!map) continue;
      ASSERT_EQ(map->size(), input.size());
      EXPECT_EQ(map->paths_emitted(), paths);
      float scale = 0;
      for (const ShardRecord& r : input) scale = std::max({scale, r.power.r, r.power.g, r.power.b});
      if (scale == 0) scale = 1;
      ASSERT_EQ(map->power_scale(), scale);
      // Quantise the input ourselves, following the spec, and compare multisets.
      std::map<PhotonKey, int> want;
      for (const ShardRecord& r : input) {
        auto power = EncodeRgb9e5(double(r.power.r) / scale, double(r.power.g) / scale,
                                  double(r.power.b) / scale);
        ++want[{r.position.x, r.position.y, r.position.z, power, r.wi_oct8, r.normal_oct7}];
      }
      for (std::size_t i = 0; i < map->size(); ++i) {
        DecodedPhoton p = map->photon(i);
        PhotonKey key{p.position.x, p.position.y, p.position.z, map->packed_power(i),
                      map->wi_code(i), map->normal_code(i)};
        ASSERT_GT(want[key]--, 0) << "photon " << i << " not in the shards: " << p.position;
        EXPECT_EQ(p.power, DecodeRgb9e5(map->packed_power(i)) * scale);
        EXPECT_EQ(p.wi, DecodeOct8(map->wi_code(i)));
      }
      CheckTree(*map, 0, Vec3(-INFINITY, -INFINITY, -INFINITY),
                Vec3(INFINITY, INFINITY, INFINITY));
    }
  }
  EXPECT_GE(volume_maps, 2);
}

// Every map, and the irradiance sites: the top of the global map's tree searched alone.
TEST(PhotonSnapshotVectors, NearestKEqualsBruteForce) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.2f, 1.2f);
  std::vector<PhotonNeighbour> found;
  for (const VectorCase& c : LoadVectors()) {
    SCOPED_TRACE(c.name);
    PhotonSnapshot snap = PhotonSnapshot::Open(c.snapshot);
    std::vector<const PhotonMap*> maps{snap.irradiance_sites()};
    for (PhotonMapKind kind : kPhotonMapKinds) maps.push_back(snap.map(kind));
    for (const PhotonMap* map : maps) {
      if (!map) continue;
      for (int query = 0; query < 200; ++query) {
        Vec3 q(u(rng), u(rng), u(rng));
        if (query % 4 == 0 && map->size() > 0) q = map->photon(query % map->size()).position;
        for (int k : {1, 7, 50, int(map->size()) + 5}) {
          for (float radius : {0.05f, 0.3f, 10.0f}) {
            map->NearestK(q, k, radius, found);
            std::vector<Neighbour> got;
            for (const PhotonNeighbour& n : found) {
              ASSERT_LT(n.index, map->size());
              Vec3 d = q - map->photon(n.index).position;
              ASSERT_EQ(n.distance_squared, d.x * d.x + d.y * d.y + d.z * d.z);
              got.emplace_back(n.distance_squared, n.index);
            }
            std::sort(got.begin(), got.end());
            ASSERT_EQ(got, BruteForce(*map, q, k, radius))
                << "query " << q << " k " << k << " radius " << radius;
          }
        }
      }
      map->NearestK(Vec3(0, 0, 0), 0, 1, found);
      EXPECT_TRUE(found.empty());
    }
  }
}

TEST(PhotonSnapshot, FromBytesMatchesOpen) {
  for (const VectorCase& c : LoadVectors()) {
    PhotonSnapshot a = PhotonSnapshot::Open(c.snapshot);
    PhotonSnapshot b = PhotonSnapshot::FromBytes(ReadFile(c.snapshot));
    PhotonSnapshot moved = std::move(b);
    for (PhotonMapKind kind : kPhotonMapKinds) {
      ASSERT_EQ(a.map(kind) == nullptr, moved.map(kind) == nullptr) << c.name;
      if (!a.map(kind)) continue;
      ASSERT_EQ(a.map(kind)->size(), moved.map(kind)->size());
      for (std::size_t i = 0; i < a.map(kind)->size(); ++i) {
        ASSERT_EQ(a.map(kind)->photon(i).position, moved.map(kind)->photon(i).position);
      }
    }
  }
}

TEST(PhotonSnapshot, RefusesMalformedSnapshots) {
  const std::string good = ReadFile(fs::path(PHOTON_SNAPSHOT_VECTORS) / "random-1000" / "snapshot.bin");
  ASSERT_NO_THROW(PhotonSnapshot::FromBytes(good));
  auto put32 = [&](std::size_t off, std::uint32_t v) {
    std::string b = good;
    std::memcpy(b.data() + off, &v, 4);
    return b;
  };
  auto put64 = [&](std::size_t off, std::uint64_t v) {
    std::string b = good;
    std::memcpy(b.data() + off, &v, 8);
    return b;
  };
  const std::size_t dir0 = 64, dir1 = 128;
  const std::uint64_t off0 = byte_io::Load<std::uint64_t>(good.data() + dir0 + 16);
  std::string bad_axis = good;
  bad_axis[off0 + 18] = static_cast<char>(bad_axis[off0 + 18] | 3);  // root marked a leaf
  std::string bad_leaf = good;
  std::uint32_t n0 = byte_io::Load<std::uint32_t>(good.data() + dir0 + 4);
  bad_leaf[off0 + 20 * (n0 - 1) + 18] = static_cast<char>(bad_leaf[off0 + 20 * (n0 - 1) + 18] & ~3);
  std::string nan_pos = good;
  std::uint32_t nan_bits = 0x7fc00000;
  std::memcpy(nan_pos.data() + off0 + 20 * 5 + 4, &nan_bits, 4);
  struct Case {
    const char* name;
    std::string bytes;
    const char* message;
  } cases[] = {
      {"empty", "", "shorter"},
      {"short", good.substr(0, 63), "shorter"},
      {"magic", "X" + good.substr(1), "magic"},
      {"version 1 (no irradiance section)", put32(8, 1), "version"},
      {"irradiance count without a section", put32(40, 5), "irradiance"},
      {"irradiance offset past the end", put64(32, 64 * 1000), "irradiance"},
      {"header size", put32(12, 32), "header_size"},
      {"map count", put32(16, 4), "map_count"},
      {"entry size", put32(20, 32), "directory_entry_size"},
      {"file size", put64(24, good.size() + 1), "file_size"},
      {"truncated", good.substr(0, good.size() - 20), "file_size"},
      {"kind", put32(dir0, 5), "kind"},
      {"kind order", put32(dir1, 1), "kinds must increase"},
      {"count over limit", put32(dir0 + 4, 0x80000000u), "photon_count"},
      {"count past end", put32(dir1 + 4, 100000), "run past the end"},
      {"offset misaligned", put64(dir0 + 16, off0 + 4), "offset"},
      {"offset in directory", put64(dir0 + 16, 128), "offset"},
      {"offset past end", put64(dir1 + 16, 1ull << 62), "offset"},
      {"scale zero", put32(dir0 + 48, 0), "power_scale"},
      {"scale inf", put32(dir0 + 48, 0x7f800000u), "power_scale"},
      {"record size", put32(dir0 + 52, 24), "record_size"},
      {"inner node marked leaf", bad_axis, "split axis"},
      {"leaf with an axis", bad_leaf, "split axis"},
      {"nan position", nan_pos, "not finite"},
  };
  for (const Case& c : cases) {
    try {
      PhotonSnapshot::FromBytes(c.bytes);
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos)
          << c.name << ": " << e.what();
    }
  }
  EXPECT_THROW(PhotonSnapshot::Open("/nonexistent/snapshot.bin"), std::runtime_error);
}

}  // namespace
}  // namespace farm
