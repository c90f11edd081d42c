#pragma once

// Axis-aligned boxes and bounding spheres: the scene's extent (which sets default photon
// search radii and the sun's emission disc) and the targets caustic photons are aimed at.

#include <limits>
#include <string>

#include "math/vec3.h"

namespace farm {

struct Bounds3 {
  // Empty: min above max, so that the first Extend sets both.
  Vec3 min{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
           std::numeric_limits<float>::infinity()};
  Vec3 max{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
           -std::numeric_limits<float>::infinity()};

  bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  void Extend(const Vec3& p) {
    min = Min(min, p);
    max = Max(max, p);
  }
  void Extend(const Bounds3& b) {
    if (b.empty()) return;
    Extend(b.min);
    Extend(b.max);
  }
  Vec3 Center() const { return empty() ? Vec3() : (min + max) * 0.5f; }
  float Diagonal() const { return empty() ? 0.0f : Length(max - min); }

  std::string ToString() const {
    return "Bounds3{min=" + farm::ToString(min) + ", max=" + farm::ToString(max) + "}";
  }
};

struct BoundingSphere {
  Vec3 center;
  float radius = 0;

  static BoundingSphere Of(const Bounds3& b) { return {b.Center(), b.Diagonal() / 2}; }
  std::string ToString() const {
    return "BoundingSphere{center=" + farm::ToString(center) +
           ", radius=" + std::to_string(radius) + "}";
  }
};

}  // namespace farm
