#pragma once

// Where rays travel in which medium (docs/media.md): the scene's medium fills its ball,
// a shape's interior medium the shape, entered and left by crossing its surface; a grid
// medium holds something only inside its placed box. Shared by camera paths (render/) and
// photon paths (photon/).

#include "math/ray.h"
#include "math/rgb.h"
#include "media/medium.h"

namespace farm {

struct SceneData;
struct SurfaceHit;

// The medium a ray travels in (null: vacuum) and the part [t0, t1] of the ray it may
// act on; what light transport asks of that stretch (media/medium.h), t along the ray.
struct MediumSegment {
  const Medium* medium = nullptr;
  Ray ray;
  float t0 = 0, t1 = 0;

  bool empty() const { return !medium || !(t1 > t0); }
  // The transmittance from the ray's origin to t (0 <= t).
  Rgb TransmittanceTo(float t) const;
  // sigma_s at the ray's point t.
  Rgb ScatteringAt(float t) const;
  // A distance in [t0, t1] (SampleDistance), the density it draws t with (DistancePdf),
  // and a free flight (SampleFlight: photons, volumetric paths).
  std::optional<DistanceSample> SampleDistance(float u_channel, float u) const;
  float DistancePdf(float t) const;
  FreeFlight SampleFlight(float u_channel, float u) const;
};

// The part of [0, t_end] of a ray in `medium`: the scene's medium fills its ball
// (SceneData::medium_ball), a shape's interior medium the whole segment; either clipped
// to a grid's box.
MediumSegment SegmentIn(const SceneData& scene, const Medium* medium, const Ray& ray, float t_end);

// The medium a ray leaving hit along wi (arriving along wo) travels in: crossing a shape
// that has an interior medium from its front to its back enters it, the other way leaves
// it for the scene's; otherwise `current`. Camera paths and photon paths alike.
const Medium* MediumBeyond(const SceneData& scene, const SurfaceHit& hit, const Vec3& wo, const Vec3& wi,
                           const Medium* current);

// The transmittance of `medium` between two points (the scene's clipped to its ball).
Rgb TransmittanceBetween(const SceneData& scene, const Medium* medium, const Vec3& a, const Vec3& b);

}  // namespace farm
