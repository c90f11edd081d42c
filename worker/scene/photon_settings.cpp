#include "scene/photon_settings.h"

#include "contract/failure.h"
#include "contract/rules.h"
#include "renderfarm/v1/scene.pb.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;
using contract::OrDefault;

// What 0 selects for a map's estimate where the field's rule has no single default (the
// notes of RadianceEstimate.neighbours, max_radius and filter in scene.proto).
struct MapDefaults {
  int neighbours;
  float diagonal_over_radius;  // the default radius is the scene's diagonal over this
  EstimateFilter filter;
};
constexpr MapDefaults kGlobalMap{100, 20, EstimateFilter::kBox};
constexpr MapDefaults kCausticMap{50, 100, EstimateFilter::kCone};
constexpr MapDefaults kVolumeMap{50, 20, EstimateFilter::kBox};

EstimateSettings EstimateFromProto(const pb::RadianceEstimate& e, const MapDefaults& map,
                                   float diagonal) {
  EstimateSettings s;
  s.neighbours = e.neighbours() == 0 ? map.neighbours : static_cast<int>(e.neighbours());
  s.max_radius = e.max_radius() == 0 ? diagonal / map.diagonal_over_radius : static_cast<float>(e.max_radius());
  switch (e.filter()) {
    case pb::FILTER_UNSPECIFIED: s.filter = map.filter; break;
    case pb::FILTER_BOX: s.filter = EstimateFilter::kBox; break;
    case pb::FILTER_CONE: s.filter = EstimateFilter::kCone; break;
    case pb::FILTER_GAUSSIAN: s.filter = EstimateFilter::kGaussian; break;
    default:  // a filter the contract declares and this worker does not know
      throw UnsupportedError("photons filter " + pb::Filter_Name(e.filter()) + " is not supported by this worker");
  }
  s.cone_k = static_cast<float>(OrDefault<pb::RadianceEstimate>(e.cone_k(), "cone_k"));
  return s;
}

const char* FilterName(EstimateFilter f) {
  switch (f) {
    case EstimateFilter::kBox: return "box";
    case EstimateFilter::kCone: return "cone";
    case EstimateFilter::kGaussian: return "gaussian";
  }
  return "?";
}

}  // namespace

PhotonSettings PhotonSettings::FromProto(const pb::PhotonMapping& p, float scene_diagonal) {
  PhotonSettings s;
  s.global_photons = OrDefault<pb::PhotonMapping>(p.global_photons(), "global_photons");
  s.caustic_photons = OrDefault<pb::PhotonMapping>(p.caustic_photons(), "caustic_photons");
  s.volume_photons = OrDefault<pb::PhotonMapping>(p.volume_photons(), "volume_photons");
  s.photons_per_shard = OrDefault<pb::PhotonMapping>(p.photons_per_shard(), "photons_per_shard");
  // A scene without geometry has no diagonal; any positive radius will do there.
  const float diagonal = scene_diagonal > 0 ? scene_diagonal : 1.0f;
  s.global_estimate = EstimateFromProto(p.global_estimate(), kGlobalMap, diagonal);
  s.caustic_estimate = EstimateFromProto(p.caustic_estimate(), kCausticMap, diagonal);
  // Counting every photon in the sphere alike: the volume estimate has no filter.
  s.volume_estimate = EstimateFromProto(p.volume_estimate(), kVolumeMap, diagonal);
  s.volume_estimate.filter = EstimateFilter::kBox;
  return s;
}

std::string EstimateSettings::ToString() const {
  return "Estimate{k=" + std::to_string(neighbours) + ", max_radius=" + std::to_string(max_radius) +
         ", filter=" + FilterName(filter) + ", cone_k=" + std::to_string(cone_k) + "}";
}

std::string PhotonSettings::ToString() const {
  return "PhotonSettings{global=" + std::to_string(global_photons) +
         ", caustic=" + std::to_string(caustic_photons) + ", volume=" + std::to_string(volume_photons) +
         ", per_shard=" + std::to_string(photons_per_shard) +
         ", global_estimate=" + global_estimate.ToString() +
         ", caustic_estimate=" + caustic_estimate.ToString() + ", volume_estimate=" + volume_estimate.ToString() + "}";
}

}  // namespace farm
