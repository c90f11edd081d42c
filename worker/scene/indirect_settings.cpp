#include "scene/indirect_settings.h"

#include "renderfarm/v1/scene.pb.h"
#include "scene/scene.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

uint32_t CountOr(uint32_t value, uint32_t fallback, uint32_t limit, const char* field) {
  if (value > limit)
    throw SceneError(std::string(field) + ": at most " + std::to_string(limit) + ", got " +
                     std::to_string(value));
  return value == 0 ? fallback : value;
}

}  // namespace

IndirectSettings IndirectSettings::FromProto(const pb::Scene& scene) {
  IndirectSettings s;
  const pb::Indirect& in = scene.indirect();
  switch (in.mode()) {
    case pb::INDIRECT_MODE_UNSPECIFIED:
    case pb::INDIRECT_MODE_FINAL_GATHER: s.mode = IndirectMode::kFinalGather; break;
    case pb::INDIRECT_MODE_PHOTON_MAP: s.mode = IndirectMode::kPhotonMap; break;
    default: throw SceneError("indirect.mode: unknown value " + std::to_string(in.mode()));
  }
  s.gather_rays = CountOr(in.gather_rays(), kDefaultGatherRays, kMaxGatherRays, "indirect.gather_rays");
  s.secondary_gather_rays = CountOr(in.secondary_gather_rays(), kDefaultSecondaryGatherRays,
                                    kMaxGatherRays, "indirect.secondary_gather_rays");
  s.light_samples = CountOr(scene.sampling().light_samples(), kDefaultLightSamples,
                            kMaxLightSamples, "sampling.light_samples");
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
