#include "scene/indirect_settings.h"

#include "contract/failure.h"
#include "contract/rules.h"
#include "renderfarm/v1/scene.pb.h"

namespace farm {

namespace pb = renderfarm::v1;
using contract::OrDefault;

IndirectSettings IndirectSettings::FromProto(const pb::Scene& scene) {
  const pb::Indirect& in = scene.indirect();
  IndirectSettings s;
  const pb::IndirectMode mode = OrDefault<pb::Indirect>(in.mode(), "mode");
  switch (mode) {
    case pb::INDIRECT_MODE_FINAL_GATHER: s.mode = IndirectMode::kFinalGather; break;
    case pb::INDIRECT_MODE_PHOTON_MAP: s.mode = IndirectMode::kPhotonMap; break;
    default:  // a mode the contract declares and this worker does not know
      throw UnsupportedError("indirect.mode: " + pb::IndirectMode_Name(mode) + " is not supported by this worker");
  }
  s.gather_rays = OrDefault<pb::Indirect>(in.gather_rays(), "gather_rays");
  s.secondary_gather_rays = OrDefault<pb::Indirect>(in.secondary_gather_rays(), "secondary_gather_rays");
  s.light_samples = OrDefault<pb::Sampling>(scene.sampling().light_samples(), "light_samples");
  return s;
}

std::string IndirectSettings::ToString() const {
  return std::string("Indirect{mode=") +
         (mode == IndirectMode::kFinalGather ? "final_gather" : "photon_map") +
         ", gather_rays=" + std::to_string(gather_rays) +
         ", secondary_gather_rays=" + std::to_string(secondary_gather_rays) +
         ", light_samples=" + std::to_string(light_samples) + "}";
}

}  // namespace farm
