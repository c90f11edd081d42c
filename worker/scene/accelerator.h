#pragma once

// The Embree 3 device and BVH over a scene's shapes. Geometry IDs equal shape indices, so a
// hit names the shape directly. Embree headers stay out of this header: every render file
// includes it.

#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "math/ray.h"
#include "scene/shapes.h"

namespace farm {

// What Embree reports of a closest hit.
struct RawHit {
  float t = 0;
  uint32_t shape = 0;      // geometry ID = index into the scene's shapes
  uint32_t primitive = 0;  // triangle index within a mesh; 0 for spheres and quads
};

class Accelerator {
 public:
  Accelerator();  // empty: every ray misses
  // Throws SceneError if Embree refuses the geometry.
  static Accelerator Build(std::span<const ShapeGeometry> shapes);

  Accelerator(Accelerator&&) noexcept;
  Accelerator& operator=(Accelerator&&) noexcept;
  ~Accelerator();

  // Closest hit with t in [0, ray.t_max]. Thread-safe.
  std::optional<RawHit> Intersect(const Ray& ray) const;
  // Whether anything lies on the ray with t in [0, ray.t_max]. Thread-safe.
  bool Occluded(const Ray& ray) const;

 private:
  struct Handles;  // RTCDevice and RTCScene, released in order
  std::unique_ptr<Handles> handles_;
};

}  // namespace farm
