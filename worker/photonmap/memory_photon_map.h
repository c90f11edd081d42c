#pragma once

// For tests and tools only (not linked into the worker): a PhotonMap over decoded photons
// held in memory, searched with nanoflann, optionally with irradiance per photon. Lets a
// test trace photons and render with them without a coordinator-built snapshot.

#include <nanoflann.hpp>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <vector>

#include "photonmap/photon_map.h"

namespace farm {

class MemoryPhotonMap final : public PhotonMap {
 public:
  explicit MemoryPhotonMap(std::vector<DecodedPhoton> photons)
      : cloud_{std::move(photons)},
        tree_(std::make_unique<Tree>(3, cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(10))) {
    tree_->buildIndex();
  }

  std::size_t size() const override { return cloud_.photons.size(); }
  DecodedPhoton photon(std::size_t i) const override { return cloud_.photons[i]; }

  void NearestK(const Vec3& p, int k, float max_radius,
                std::vector<PhotonNeighbour>& out) const override {
    out.clear();
    if (k <= 0 || size() == 0 || !(max_radius > 0)) return;
    const std::size_t kk = std::min<std::size_t>(k, size());
    std::vector<std::uint32_t> index(kk);
    std::vector<float> d2(kk);
    const float q[3] = {p.x, p.y, p.z};
    const std::size_t found = tree_->knnSearch(q, kk, index.data(), d2.data());
    for (std::size_t i = 0; i < found; ++i)
      if (d2[i] < max_radius * max_radius) out.push_back({index[i], d2[i]});
  }

  void set_irradiance(std::vector<Rgb> irradiance) {
    if (irradiance.size() != size()) throw std::invalid_argument("one irradiance per photon");
    irradiance_ = std::move(irradiance);
  }
  bool has_irradiance() const override { return !irradiance_.empty() || size() == 0; }
  Rgb irradiance(std::size_t i) const override { return irradiance_[i]; }

 private:
  struct Cloud {
    std::vector<DecodedPhoton> photons;
    std::size_t kdtree_get_point_count() const { return photons.size(); }
    float kdtree_get_pt(std::size_t i, std::size_t dim) const {
      const Vec3& p = photons[i].position;
      return dim == 0 ? p.x : dim == 1 ? p.y : p.z;
    }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
      return false;
    }
  };
  using Tree =
      nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud, 3,
                                          std::uint32_t>;
  Cloud cloud_;
  std::unique_ptr<Tree> tree_;  // holds a reference to cloud_: the map is not movable
  std::vector<Rgb> irradiance_;

 public:
  MemoryPhotonMap(const MemoryPhotonMap&) = delete;
  MemoryPhotonMap& operator=(const MemoryPhotonMap&) = delete;
};

}  // namespace farm
