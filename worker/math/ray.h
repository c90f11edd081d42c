#pragma once

// Rays, and the offset that keeps a spawned ray from hitting the surface it starts on.

#include <limits>
#include <string>

#include "math/vec3.h"

namespace farm {

struct Ray {
  Vec3 origin;
  Vec3 direction;  // unit length by convention: t is then a distance
  float t_max = std::numeric_limits<float>::infinity();

  Vec3 At(float t) const { return origin + direction * t; }
};

inline std::string ToString(const Ray& r) {
  return "Ray{o=" + ToString(r.origin) + ", d=" + ToString(r.direction) +
         ", t_max=" + std::to_string(r.t_max) + "}";
}

// Relative part of the ray offset. Hit points are first projected back onto their surface
// (see scene/shapes.h), which leaves an error of a few float ulps of the point's largest
// coordinate (2^-23 relative); 4e-6 is ~34 ulps, well above that, and small enough that
// a scene moved far from the origin (1e6 units) keeps its contact shadows.
inline constexpr float kRayOffsetRelative = 4e-6f;

// Moves p off its surface along the geometric normal n, to the side that w points into.
// The offset is scale-aware: it grows with the magnitude of p (float error is relative)
// plus an absolute floor, `scene_epsilon`, derived from the scene's size, that covers
// points near the origin of a large scene, where the rounding of the primitives' own
// coordinates dominates.
inline Vec3 OffsetRayOrigin(const Vec3& p, const Vec3& n, const Vec3& w, float scene_epsilon) {
  const float d = kRayOffsetRelative * MaxComponent(Abs(p)) + scene_epsilon;
  const Vec3 offset = n * d;
  return Dot(w, n) < 0 ? p - offset : p + offset;
}

}  // namespace farm
