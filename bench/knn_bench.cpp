// farm_bench_knn SNAPSHOT...: nearest-k queries per second on the farm's own kd-tree (the
// snapshot the Go builder wrote, mapped as a worker maps it) against nanoflann built over
// the same points, with the same queries, in the same run. Prints q/s, the ratio and bytes
// per photon. Single-threaded on both sides: the render threads each query on their own.

#include <nanoflann.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>
#include <vector>

#include "photonmap/photon_snapshot.h"

namespace {

using farm::Vec3;
using Clock = std::chrono::steady_clock;

struct Cloud {
  std::vector<float> xyz;
  std::size_t kdtree_get_point_count() const { return xyz.size() / 3; }
  float kdtree_get_pt(std::size_t i, std::size_t dim) const { return xyz[3 * i + dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using NanoTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud, 3>;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// Queries near the photons (each a photon's position plus a small offset), as a renderer
// queries at surface points: a box-uniform query would mostly land in empty space for
// photons on surfaces.
std::vector<Vec3> MakeQueries(const farm::PhotonMap& map, int count) {
  std::mt19937 rng(1234);
  std::uniform_int_distribution<std::size_t> pick(0, map.size() - 1);
  std::normal_distribution<float> jitter(0, 0.005f);
  std::vector<Vec3> queries;
  for (int i = 0; i < count; ++i) {
    Vec3 p = map.photon(pick(rng)).position;
    queries.push_back(p + Vec3(jitter(rng), jitter(rng), jitter(rng)));
  }
  return queries;
}

void Run(const std::filesystem::path& file) {
  auto start = Clock::now();
  farm::PhotonSnapshot snap = farm::PhotonSnapshot::Open(file);
  const double open_s = Seconds(start);
  const farm::PhotonMap* map = snap.map(farm::PhotonMapKind::kGlobal);
  if (!map || map->size() == 0) {
    std::printf("%s: no global photons\n", file.c_str());
    return;
  }
  const std::size_t n = map->size();
  Cloud cloud;
  cloud.xyz.reserve(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 p = map->photon(i).position;
    cloud.xyz.insert(cloud.xyz.end(), {p.x, p.y, p.z});
  }
  start = Clock::now();
  NanoTree nano(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  const double nano_build_s = Seconds(start);
  const double file_bytes = double(std::filesystem::file_size(file));
  std::printf("%s: %zu photons, snapshot %.1f B/photon (%.1f MB), opened+validated in %.0f ms; "
              "nanoflann: 12 B/photon of points + index, built in %.0f ms\n",
              file.filename().c_str(), n, file_bytes / double(n), file_bytes / 1e6, open_s * 1e3,
              nano_build_s * 1e3);

  for (int k : {50, 500}) {
    const int count = k == 50 ? 100000 : 20000;
    std::vector<Vec3> queries = MakeQueries(*map, count);
    std::vector<farm::PhotonNeighbour> ours;
    double checksum_ours = 0, checksum_nano = 0;
    start = Clock::now();
    for (const Vec3& q : queries) {
      map->NearestK(q, k, 1e3f, ours);
      for (const auto& nb : ours) checksum_ours += nb.distance_squared;
    }
    const double ours_s = Seconds(start);
    std::vector<std::uint32_t> idx(k);
    std::vector<float> d2(k);
    start = Clock::now();
    for (const Vec3& q : queries) {
      const float qp[3] = {q.x, q.y, q.z};
      std::size_t found = nano.knnSearch(qp, k, idx.data(), d2.data());
      for (std::size_t j = 0; j < found; ++j) checksum_nano += d2[j];
    }
    const double nano_s = Seconds(start);
    // Same neighbours (as distances) on both sides, or the comparison means nothing.
    const double rel = std::abs(checksum_ours - checksum_nano) / std::max(checksum_nano, 1e-30);
    std::printf("  k=%-3d  ours %10.0f q/s   nanoflann %10.0f q/s   ours/nanoflann %.2fx   "
                "(%d queries, results %s)\n",
                k, count / ours_s, count / nano_s, nano_s / ours_s, count,
                rel < 1e-6 ? "agree" : "DIFFER");
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: farm_bench_knn SNAPSHOT...\n");
    return 2;
  }
  try {
    for (int i = 1; i < argc; ++i) Run(argv[i]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "farm_bench_knn: %s\n", e.what());
    return 1;
  }
  return 0;
}
