#pragma once

// Integrators turn a camera ray into the values of one pixel sample. This milestone has one,
// direct lighting; photon mapping adds passes (emit, gather) that prepare shared data before
// rendering and a caustic and an indirect term in the sample result.

#include <string>

#include "math/ray.h"
#include "math/rgb.h"
#include "sampling/pixel_sampler.h"
#include "scene/scene_data.h"

namespace farm {

// Everything one camera sample contributes to its pixel. AOV layers (direct, indirect,
// caustic, albedo, normal, depth) become further members, written to channels of their own
// by the tile renderer.
struct SampleResult {
  Rgb radiance;      // beauty
  float alpha = 0;   // 1 if the camera ray hit geometry, 0 if it escaped
};

// Direct lighting by next-event estimation: radiance emitted toward the camera by the
// surface it sees (front of an emitter), plus, at Lambert surfaces, one light sample: a
// light picked in proportion to power, a point on it sampled by the light, and a shadow ray.
// Soft shadows come from sampling area lights over the pixel's samples.
class DirectLightingIntegrator {
 public:
  explicit DirectLightingIntegrator(const SceneData& scene) : scene_(scene) {}

  // Consumes sampler dimensions after the camera's. Never returns NaN or infinity.
  SampleResult Li(const Ray& camera_ray, PixelSampler& sampler) const;

  std::string ToString() const { return "DirectLightingIntegrator{}"; }

 private:
  // Reflected radiance along wo at hit from one light sample.
  Rgb SampleDirect(const SurfaceHit& hit, const Vec3& wo, const Material& material,
                   PixelSampler& sampler) const;

  const SceneData& scene_;
};

}  // namespace farm
