#pragma once

// renderfarm.v1.PhotonMapping with its defaults applied (scene.proto documents them per
// field): how many photon paths each map gets and how radiance is estimated from them.

#include <cstdint>
#include <string>

namespace renderfarm::v1 {
class PhotonMapping;
}

namespace farm {

inline constexpr uint64_t kDefaultGlobalPhotons = 200'000;
inline constexpr uint64_t kDefaultCausticPhotons = 200'000;
inline constexpr uint64_t kDefaultPhotonsPerShard = 100'000;

enum class EstimateFilter { kBox, kCone, kGaussian };

struct EstimateSettings {
  int neighbours = 100;
  float max_radius = 1;  // scene units
  EstimateFilter filter = EstimateFilter::kBox;
  float cone_k = 1.1f;

  std::string ToString() const;
};

struct PhotonSettings {
  uint64_t global_photons = kDefaultGlobalPhotons;
  uint64_t caustic_photons = kDefaultCausticPhotons;
  uint64_t photons_per_shard = kDefaultPhotonsPerShard;
  EstimateSettings global_estimate;
  EstimateSettings caustic_estimate;

  // Defaults depend on the scene's bounding box diagonal (search radii). Throws SceneError
  // naming the field ("photons.caustic_estimate.cone_k") for values out of range.
  static PhotonSettings FromProto(const renderfarm::v1::PhotonMapping& photons,
                                  float scene_diagonal);
  std::string ToString() const;
};

}  // namespace farm
