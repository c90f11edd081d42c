#pragma once

// renderfarm.v1.Indirect and Sampling.light_samples with their defaults applied (the
// default_value of each field's rule in scene.proto, read through worker/contract): how the
// integrator computes indirect diffuse light and how many shadow rays it spends on direct
// light.

#include <cstdint>
#include <string>

namespace renderfarm::v1 {
class Scene;
}

namespace farm {

enum class IndirectMode {
  kFinalGather,  // gather rays reading irradiance precomputed at photons
  kPhotonMap,    // the global map's radiance estimate seen directly
};

struct IndirectSettings {
  IndirectMode mode = IndirectMode::kFinalGather;
  uint32_t gather_rays = 0;
  uint32_t secondary_gather_rays = 0;
  uint32_t light_samples = 0;

  // Reads scene.indirect and scene.sampling.light_samples, which have passed
  // contract::CheckRules; a field that is 0 takes its default.
  static IndirectSettings FromProto(const renderfarm::v1::Scene& scene);
  std::string ToString() const;
};

}  // namespace farm
