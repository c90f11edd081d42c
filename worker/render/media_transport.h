#pragma once

// Light transport through homogeneous media along camera paths (docs/media.md): where a
// ray travels in a medium, what it reaches is attenuated by the medium's closed-form
// transmittance, and light from every light scattered once towards the ray along the way
// (single scattering) is added:
//
//   L_ss = integral over t of T(t0, t) sigma_s p(wo, wi) L_light(x(t), wi) T_shadow dt,
//
// estimated by picking a light in proportion to power and a distance along the segment:
// equiangularly towards point and spot lights (media/equiangular.h: it cancels their 1 /
// d^2, which is what makes their halos clean), by the truncated free-flight density
// otherwise. Shadow rays from media and from surfaces are attenuated by the transmittance
// of the medium they cross.

#include <functional>
#include <optional>

#include "math/bounds.h"
#include "math/ray.h"
#include "math/rgb.h"
#include "media/homogeneous_medium.h"
#include "scene/lights.h"

namespace farm {

struct SceneData;

// The medium a ray travels in (null: vacuum) and the part [t0, t1] of the ray it fills.
struct MediumSegment {
  const HomogeneousMedium* medium = nullptr;
  float t0 = 0, t1 = 0;

  bool empty() const { return !medium || !(t1 > t0); }
  // The transmittance from the ray's origin to t (0 <= t).
  Rgb TransmittanceTo(float t) const;
};

// The part of [0, t_end] of a ray in `medium`: the scene's medium fills its ball
// (SceneData::medium_ball), a shape's interior medium the whole segment.
MediumSegment SegmentIn(const SceneData& scene, const HomogeneousMedium* medium, const Ray& ray, float t_end);

// The transmittance of `medium` between two points (the scene's clipped to its ball).
Rgb TransmittanceBetween(const SceneData& scene, const HomogeneousMedium* medium, const Vec3& a, const Vec3& b);

// The light a light sample reaches x with, times the transmittance of the way; zero where
// something blocks it.
using ShadowTransmittance = std::function<Rgb(const Vec3& x, const LightSample& sample)>;

// The random numbers of one single-scattering sample.
struct InScatterDimensions {
  Vec2 light;  // the point on the light (SampleLi)
  float channel = 0;  // which channel's free-flight density (lights that are not points)
  float distance = 0;
};

// One sample of the single-scattered radiance arriving at the ray's origin from `light`
// (picked with probability pick_pmf) along the segment; ray.direction unit.
Rgb InScatter(const MediumSegment& segment, const Ray& ray, const Light& light, float pick_pmf,
              const InScatterDimensions& u, const ShadowTransmittance& shadow);

}  // namespace farm
