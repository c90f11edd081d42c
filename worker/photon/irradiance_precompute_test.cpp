#include "photon/irradiance_precompute.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <random>

#include "photonmap/irradiance_format.h"
#include "photonmap/memory_photon_map.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

// Photons on two perpendicular planes meeting at a corner (normals +z and +x) and a few on
// the back of the z plane (normal -z): the precompute must ignore the photons facing away.
std::vector<DecodedPhoton> CornerPhotons(int n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<DecodedPhoton> photons;
  for (int i = 0; i < n; ++i) {
    DecodedPhoton p;
    const int kind = i % 5;
    if (kind < 3) {
      p.position = {u(rng), u(rng), 0};
      p.normal = {0, 0, 1};
    } else if (kind == 3) {
      p.position = {0, u(rng), u(rng)};
      p.normal = {1, 0, 0};
    } else {
      p.position = {u(rng), u(rng), 0};
      p.normal = {0, 0, -1};
    }
    p.wi = p.normal;
    p.power = Rgb(u(rng), u(rng), u(rng)) * 1e-3f;
    photons.push_back(p);
  }
  return photons;
}

// Jensen's box estimate written out the slow way: the k nearest within the radius, the
// disc through the farthest (the whole max_radius disc when fewer than k are in it),
// photons facing away dropped.
Rgb BruteForceIrradiance(const std::vector<DecodedPhoton>& photons, std::size_t i, int k,
                         float max_radius) {
  std::vector<std::pair<float, std::size_t>> near;
  for (std::size_t j = 0; j < photons.size(); ++j) {
    const float d2 = LengthSquared(photons[j].position - photons[i].position);
    if (d2 < max_radius * max_radius) near.push_back({d2, j});
  }
  std::sort(near.begin(), near.end());
  if (near.size() > std::size_t(k)) near.resize(k);
  const float r2 = near.size() < std::size_t(k) ? max_radius * max_radius : near.back().first;
  Rgb sum;
  for (const auto& [d2, j] : near)
    if (Dot(photons[j].normal, photons[i].normal) >= 0.5f) sum += photons[j].power;
  return sum / (std::numbers::pi_v<float> * r2);
}

SceneData SettingsOnly(int k, float radius) {
  SceneData data;
  data.photons.global_estimate.neighbours = k;
  data.photons.global_estimate.max_radius = radius;
  data.photons.global_estimate.filter = EstimateFilter::kCone;  // the precompute uses a box anyway
  return data;
}

TEST(IrradiancePrecompute, EqualsABruteForceBoxEstimateIgnoringPhotonsFacingAway) {
  std::mt19937 rng(7);
  const std::vector<DecodedPhoton> photons = CornerPhotons(3000, rng);
  const MemoryPhotonMap map(photons);
  for (double radius_scale : {1.0, 0.5}) {
    const SceneData data = SettingsOnly(40, 0.3f);
    const std::vector<Rgb> got = ComputeIrradiance(data, map, nullptr, 100, 2000, radius_scale);
    ASSERT_EQ(got.size(), 2000u);
    for (std::size_t j = 0; j < got.size(); ++j) {
      const Rgb want = BruteForceIrradiance(photons, 100 + j, 40, float(0.3 * radius_scale));
      ASSERT_NEAR(got[j].r, want.r, 1e-4f * want.r + 1e-9f) << "photon " << 100 + j;
      ASSERT_NEAR(got[j].g, want.g, 1e-4f * want.g + 1e-9f) << "photon " << 100 + j;
      ASSERT_NEAR(got[j].b, want.b, 1e-4f * want.b + 1e-9f) << "photon " << 100 + j;
    }
  }
}

TEST(IrradiancePrecompute, UniformPhotonsGiveTheirFluxDensity) {
  // 200 x 200 photons on a unit grid of spacing h, flux phi each: irradiance phi / h^2 away
  // from the edges (within the estimate's k/(k-1)-like bias and the grid's discreteness).
  std::vector<DecodedPhoton> photons;
  const float h = 0.01f, phi = 2e-4f;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x)
      photons.push_back({{(x + 0.5f) * h, (y + 0.5f) * h, 0}, Rgb(phi), {0, 0, 1}, {0, 0, 1}});
  const MemoryPhotonMap map(photons);
  const std::vector<Rgb> e = ComputeIrradiance(SettingsOnly(200, 1), map, nullptr, 0, map.size(), 1);
  const std::size_t centre = 100 * 200 + 100;
  EXPECT_NEAR(e[centre].g, phi / (h * h), 0.05 * phi / (h * h));
}

TEST(IrradiancePrecompute, RefusesARangeOutsideTheMapAndABadScale) {
  std::mt19937 rng(1);
  const MemoryPhotonMap map(CornerPhotons(10, rng));
  const SceneData data = SettingsOnly(5, 1);
  EXPECT_THROW(ComputeIrradiance(data, map, nullptr, 5, 6, 1), std::invalid_argument);
  EXPECT_THROW(ComputeIrradiance(data, map, nullptr, 11, 0, 1), std::invalid_argument);
  EXPECT_THROW(ComputeIrradiance(data, map, nullptr, 0, 10, 0), std::invalid_argument);
  EXPECT_NO_THROW(ComputeIrradiance(data, map, nullptr, 10, 0, 1));
}

// Through the product path: a Go-built snapshot (shared vector), shards of any split give
// the same values, and the same shard twice the same bytes.
TEST(IrradiancePrecompute, ShardsOfASnapshotAreDeterministicAndSplitFree) {
  const PhotonSnapshot snap = PhotonSnapshot::Open(std::filesystem::path(PHOTON_SNAPSHOT_VECTORS) /
                                                   "random-1000" / "snapshot.bin");
  pb::Scene s = MakeScene(4, 4, {0, 0, -5}, {0, 0, 0}, {0, 1, 0}, 40);
  AddLambert(s, "white", Rgb(0.5f));
  AddQuad(s, "white", {-1, -1, 0}, {2, 0, 0}, {0, 2, 0});
  AddPointLight(s, {0, 0, -3}, Rgb(1));  // a scene needs one; irradiance comes from the photons
  s.mutable_photons()->mutable_global_estimate()->set_neighbours(20);
  s.mutable_photons()->mutable_global_estimate()->set_max_radius(0.6);
  const Scene scene = Scene::Build(s, NoBlobs());
  const std::string whole = ComputeIrradianceShard(scene, snap, 0, 1000, 1.0);
  EXPECT_EQ(whole, ComputeIrradianceShard(scene, snap, 0, 1000, 1.0));
  const IrradianceShard w = DecodeIrradianceShard(whole);
  const IrradianceShard a = DecodeIrradianceShard(ComputeIrradianceShard(scene, snap, 0, 300, 1.0));
  const IrradianceShard b = DecodeIrradianceShard(ComputeIrradianceShard(scene, snap, 300, 700, 1.0));
  EXPECT_EQ(b.first_photon, 300u);
  const std::vector<Rgb> exact = ComputeIrradiance(scene.data(), *snap.map(PhotonMapKind::kGlobal),
                                                   snap.map(PhotonMapKind::kCaustic), 0, 1000, 1.0);
  for (std::size_t i = 0; i < 1000; ++i) {
    const Rgb part = i < 300 ? a.irradiance(i) : b.irradiance(i - 300);
    const Rgb want = exact[i];
    const float tol = std::max({want.r, want.g, want.b}) / 256 + 1e-30f;
    ASSERT_NEAR(w.irradiance(i).r, want.r, tol) << i;
    ASSERT_NEAR(part.r, want.r, tol) << i;
    ASSERT_NEAR(part.b, want.b, tol) << i;
  }
  EXPECT_THROW(ComputeIrradianceShard(scene, snap, 900, 101, 1.0), std::invalid_argument);
}

TEST(IrradiancePrecompute, ProgressCountsEveryPhotonOfTheRange) {
  std::mt19937 rng(3);
  const MemoryPhotonMap map(CornerPhotons(3000, rng));
  ProgressCounter counter{0};
  ComputeIrradiance(SettingsOnly(20, 0.3f), map, nullptr, 100, 2500, 1, {}, Progress(counter));
  EXPECT_EQ(counter.load(), 2500u);
}

}  // namespace
}  // namespace farm
