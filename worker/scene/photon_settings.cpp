#include "scene/photon_settings.h"

#include <cmath>

#include "renderfarm/v1/scene.pb.h"
#include "scene/scene.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

// A bound that keeps one estimate's neighbour list small enough for a worker thread's stack
// of scratch memory; Jensen's renderings use 50 to 500.
constexpr uint32_t kMaxNeighbours = 100'000;

EstimateSettings EstimateFromProto(const pb::RadianceEstimate& e, int default_k,
                                   float default_radius, EstimateFilter default_filter,
                                   const std::string& field) {
  EstimateSettings s;
  if (e.neighbours() > kMaxNeighbours)
    throw SceneError(field + ".neighbours: at most " + std::to_string(kMaxNeighbours) + ", got " +
                     std::to_string(e.neighbours()));
  s.neighbours = e.neighbours() == 0 ? default_k : static_cast<int>(e.neighbours());
  if (!std::isfinite(e.max_radius()) || e.max_radius() < 0)
    throw SceneError(field + ".max_radius: must be finite and >= 0");
  s.max_radius = e.max_radius() == 0 ? default_radius : static_cast<float>(e.max_radius());
  switch (e.filter()) {
    case pb::FILTER_UNSPECIFIED: s.filter = default_filter; break;
    case pb::FILTER_BOX: s.filter = EstimateFilter::kBox; break;
    case pb::FILTER_CONE: s.filter = EstimateFilter::kCone; break;
    case pb::FILTER_GAUSSIAN: s.filter = EstimateFilter::kGaussian; break;
    default: throw SceneError(field + ".filter: unknown value " + std::to_string(e.filter()));
  }
  if (!std::isfinite(e.cone_k()) || (e.cone_k() != 0 && e.cone_k() < 1))
    throw SceneError(field + ".cone_k: must be >= 1 (or 0 for the default)");
  s.cone_k = e.cone_k() == 0 ? 1.1f : static_cast<float>(e.cone_k());
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
  if (p.global_photons() != 0) s.global_photons = p.global_photons();
  if (p.caustic_photons() != 0) s.caustic_photons = p.caustic_photons();
  if (p.photons_per_shard() != 0) s.photons_per_shard = p.photons_per_shard();
  // A scene without geometry has no diagonal; any positive radius will do there.
  const float diagonal = scene_diagonal > 0 ? scene_diagonal : 1.0f;
  s.global_estimate = EstimateFromProto(p.global_estimate(), 100, diagonal / 20,
                                        EstimateFilter::kBox, "photons.global_estimate");
  s.caustic_estimate = EstimateFromProto(p.caustic_estimate(), 50, diagonal / 100,
                                         EstimateFilter::kCone, "photons.caustic_estimate");
  return s;
}

std::string EstimateSettings::ToString() const {
  return "Estimate{k=" + std::to_string(neighbours) + ", max_radius=" + std::to_string(max_radius) +
         ", filter=" + FilterName(filter) + ", cone_k=" + std::to_string(cone_k) + "}";
}

std::string PhotonSettings::ToString() const {
  return "PhotonSettings{global=" + std::to_string(global_photons) +
         ", caustic=" + std::to_string(caustic_photons) +
         ", per_shard=" + std::to_string(photons_per_shard) +
         ", global_estimate=" + global_estimate.ToString() +
         ", caustic_estimate=" + caustic_estimate.ToString() + "}";
}

}  // namespace farm
