#include "photonmap/irradiance_format.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "photonmap/byte_io.h"
#include "photonmap/photon_snapshot.h"
#include "photonmap/rgb9e5.h"
#include "util/read_file.h"

namespace farm {
namespace {

namespace fs = std::filesystem;

TEST(IrradianceShard, RoundTripsWithinRgb9e5Precision) {
  const std::vector<Rgb> values = {Rgb(0), Rgb(1, 2, 3), Rgb(1e-3f, 0, 5), Rgb(7, 7, 7)};
  const std::string bytes = EncodeIrradianceShard(42, values);
  ASSERT_EQ(bytes.size(), kIrradianceShardHeaderSize + 4 * values.size());
  const IrradianceShard shard = DecodeIrradianceShard(bytes);
  EXPECT_EQ(shard.first_photon, 42u);
  EXPECT_EQ(shard.scale, 7.0f);  // the brightest component
  ASSERT_EQ(shard.packed.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    const Rgb got = shard.irradiance(i), want = values[i];
    const float tolerance = std::max({want.r, want.g, want.b}) / 512;
    EXPECT_NEAR(got.r, want.r, tolerance) << i;
    EXPECT_NEAR(got.g, want.g, tolerance) << i;
    EXPECT_NEAR(got.b, want.b, tolerance) << i;
  }
}

TEST(IrradianceShard, AllBlackHasScaleOneAndEmptyIsValid) {
  EXPECT_EQ(DecodeIrradianceShard(EncodeIrradianceShard(0, std::vector<Rgb>(3))).scale, 1.0f);
  EXPECT_TRUE(DecodeIrradianceShard(EncodeIrradianceShard(5, {})).packed.empty());
}

TEST(IrradianceShard, EncoderRefusesNegativeAndNonFinite) {
  EXPECT_THROW(EncodeIrradianceShard(0, std::vector<Rgb>{Rgb(-1, 0, 0)}), std::invalid_argument);
  EXPECT_THROW(EncodeIrradianceShard(0, std::vector<Rgb>{Rgb(NAN, 0, 0)}), std::invalid_argument);
}

TEST(IrradianceShard, DecoderRefusesMalformedShards) {
  const std::string good = EncodeIrradianceShard(0, std::vector<Rgb>{Rgb(1), Rgb(2)});
  struct Case {
    const char* what;
    std::string bytes;
  };
  auto with = [&](std::size_t at, std::string_view patch) {
    std::string b = good;
    b.replace(at, patch.size(), patch);
    return b;
  };
  const float zero = 0, inf = INFINITY;
  const std::uint64_t huge = ~0ull;
  const Case cases[] = {
      {"short", good.substr(0, 39)},
      {"magic", with(0, "PFIRRAD2")},
      {"version", with(8, std::string("\x02\0\0\0", 4))},
      {"record size", with(12, std::string("\x08\0\0\0", 4))},
      {"count too big", with(24, std::string(reinterpret_cast<const char*>(&huge), 8))},
      {"truncated record", good.substr(0, good.size() - 1)},
      {"trailing byte", good + "x"},
      {"zero scale", with(32, std::string(reinterpret_cast<const char*>(&zero), 4))},
      {"infinite scale", with(32, std::string(reinterpret_cast<const char*>(&inf), 4))},
      {"reserved", with(36, "x")},
  };
  for (const Case& c : cases)
    EXPECT_THROW(DecodeIrradianceShard(c.bytes), std::runtime_error) << c.what;
}

// The shared vectors (tests/vectors/photon-snapshot): cases with irradiance-NNN.bin hold
// the snapshot after coordinator/photonmap.MergeIrradiance. The C++ reader must see each
// photon's irradiance re-encoded relative to the largest decoded component, exactly as the
// spec's recipe says, bit for bit.
TEST(IrradianceSnapshotVectors, ReaderSeesTheMergedShardsBitForBit) {
  int cases = 0;
  for (const auto& dir : fs::directory_iterator(PHOTON_SNAPSHOT_VECTORS)) {
    if (!dir.is_directory()) continue;
    std::vector<fs::path> files;
    for (const auto& f : fs::directory_iterator(dir.path()))
      if (f.path().filename().string().starts_with("irradiance-")) files.push_back(f.path());
    if (files.empty()) continue;
    ++cases;
    std::sort(files.begin(), files.end());
    std::vector<Rgb> values;
    for (const fs::path& f : files) {
      const IrradianceShard shard = DecodeIrradianceShard(ReadFile(f));
      ASSERT_EQ(shard.first_photon, values.size()) << f;
      for (std::size_t i = 0; i < shard.packed.size(); ++i) values.push_back(shard.irradiance(i));
    }
    float scale = 0;
    for (const Rgb& v : values) scale = std::max({scale, v.r, v.g, v.b});
    if (!(scale > 0)) scale = 1;
    const PhotonSnapshot snap = PhotonSnapshot::Open(dir.path() / "snapshot.bin");
    const PhotonMap* global = snap.map(PhotonMapKind::kGlobal);
    ASSERT_NE(global, nullptr) << dir.path();
    // The irradiance is at the global map's first photons, a map of their own.
    EXPECT_FALSE(global->has_irradiance());
    const PhotonMap* sites = snap.irradiance_sites();
    ASSERT_NE(sites, nullptr) << dir.path();
    ASSERT_TRUE(sites->has_irradiance());
    ASSERT_EQ(sites->size(), values.size());
    ASSERT_LT(sites->size(), global->size());
    for (std::size_t i = 0; i < values.size(); ++i) {
      const double s = scale;
      const Rgb want = DecodeRgb9e5(EncodeRgb9e5(values[i].r / s, values[i].g / s, values[i].b / s)) * scale;
      ASSERT_EQ(sites->photon(i).position, global->photon(i).position);
      const Rgb got = sites->irradiance(i);
      ASSERT_EQ(got.r, want.r) << dir.path() << " photon " << i;
      ASSERT_EQ(got.g, want.g) << dir.path() << " photon " << i;
      ASSERT_EQ(got.b, want.b) << dir.path() << " photon " << i;
    }
    if (const PhotonMap* caustic = snap.map(PhotonMapKind::kCaustic)) {
      EXPECT_FALSE(caustic->has_irradiance());
    }
  }
  EXPECT_GE(cases, 1);
}

// The sites are 1 to all of the global map's photons (the precompute picks how many:
// farm::IrradianceSites); a forged count outside that range is refused, naming it.
TEST(IrradianceSnapshotVectors, ReaderRefusesASiteCountOutsideTheGlobalMap) {
  const std::string good = ReadFile(fs::path(PHOTON_SNAPSHOT_VECTORS) / "irradiance" / "snapshot.bin");
  const PhotonSnapshot snap = PhotonSnapshot::FromBytes(good);
  const auto photons = std::uint32_t(snap.map(PhotonMapKind::kGlobal)->size());
  for (const std::uint32_t count : {0u, photons + 1}) {
    std::string forged = good;
    std::memcpy(forged.data() + 40, &count, 4);
    try {
      PhotonSnapshot::FromBytes(forged);
      ADD_FAILURE() << "irradiance_count " << count << " accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("irradiance_count"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace farm
