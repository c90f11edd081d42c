#pragma once

// renderfarm.v1.PhotonMapping with its defaults applied: how many photon paths each map
// gets and how radiance is estimated from them. Counts and cone_k take the default_value
// of their field's rule (scene.proto, through worker/contract); the neighbours, radius and
// filter defaults depend on the map, as the fields' notes say.

#include <cstdint>
#include <string>

namespace renderfarm::v1 {
class PhotonMapping;
}

namespace farm {

enum class EstimateFilter { kBox, kCone, kGaussian };

struct EstimateSettings {
  int neighbours = 0;
  float max_radius = 0;  // scene units
  EstimateFilter filter = EstimateFilter::kBox;
  float cone_k = 1;

  std::string ToString() const;
};

struct PhotonSettings {
  uint64_t global_photons = 0;
  uint64_t caustic_photons = 0;
  uint64_t volume_photons = 0;
  uint64_t photons_per_shard = 0;
  EstimateSettings global_estimate;
  EstimateSettings caustic_estimate;
  EstimateSettings volume_estimate;  // its filter is always box (scene.proto)

  // Reads `photons`, which has passed contract::CheckRules. The default search radii are
  // fractions of the scene's bounding box diagonal.
  static PhotonSettings FromProto(const renderfarm::v1::PhotonMapping& photons,
                                  float scene_diagonal);
  std::string ToString() const;
};

}  // namespace farm
