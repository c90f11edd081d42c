#pragma once

// renderfarm.v1.Indirect and Sampling.light_samples with their defaults applied
// (scene.proto documents them): how the integrator computes indirect diffuse light and how
// many shadow rays it spends on direct light.

#include <cstdint>
#include <string>

namespace renderfarm::v1 {
class Scene;
}

namespace farm {

inline constexpr uint32_t kDefaultGatherRays = 64;
inline constexpr uint32_t kDefaultSecondaryGatherRays = 8;
inline constexpr uint32_t kDefaultLightSamples = 16;
// Bounds that keep one camera sample's work finite (docs/limits.md): 4096 gather rays is
// already 64 times the default.
inline constexpr uint32_t kMaxGatherRays = 4096;
inline constexpr uint32_t kMaxLightSamples = 4096;

enum class IndirectMode {
  kFinalGather,  // gather rays reading irradiance precomputed at photons
  kPhotonMap,    // the global map's radiance estimate seen directly
};

struct IndirectSettings {
  IndirectMode mode = IndirectMode::kFinalGather;
  uint32_t gather_rays = kDefaultGatherRays;
  uint32_t secondary_gather_rays = kDefaultSecondaryGatherRays;
  uint32_t light_samples = kDefaultLightSamples;

  // Reads scene.indirect and scene.sampling.light_samples. Throws SceneError naming the
  // field ("indirect.gather_rays") for values out of range.
  static IndirectSettings FromProto(const renderfarm::v1::Scene& scene);
  std::string ToString() const;
};

}  // namespace farm
