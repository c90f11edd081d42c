#pragma once

// The Embree 3 device and BVH over a scene's shapes. Geometry IDs equal shape indices, so a
// hit names the shape directly. A mesh of Scene.meshes is built once, as an Embree scene
// of its own whose geometry IDs are its part indices, and each instance shape places it
// with an Embree instance (RTC_GEOMETRY_TYPE_INSTANCE): its triangles and BVH are never
// copied. Embree headers stay out of this header: every render file includes it.
//
// Geometry may have a hit filter (alpha-tested cut-outs): Embree then asks it about every
// candidate hit, of closest-hit and occlusion queries alike, and a hit it rejects is not
// there. Geometry without one costs nothing.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "math/ray.h"
#include "scene/shapes.h"

namespace farm {

// What Embree reports of a hit.
struct RawHit {
  float t = 0;
  uint32_t shape = 0;      // geometry ID = index into the scene's shapes
  uint32_t part = 0;       // for an instance, the part of its mesh; else 0
  uint32_t primitive = 0;  // triangle index within a mesh or part; 0 for spheres and quads
  Vec2 barycentric;        // Embree's u, v: the triangle's point (1-u-v) p0 + u p1 + v p2
};

// Whether to ignore a candidate hit; `point` is where it lies in world space (for an
// instance, its mesh's point placed). Called by Embree during traversal, from any thread.
using HitFilter = std::function<bool(const RawHit& hit, const Vec3& point)>;

struct AcceleratorInput {
  std::span<const ShapeGeometry> shapes;
  // Every mesh the instances among `shapes` place (others are built too).
  std::span<const std::shared_ptr<const SceneMesh>> meshes;
  // Which geometry's hits go through `filter`: shapes by index (instances excepted) and
  // the parts of meshes (by mesh, then part). Either may be empty (none).
  std::vector<bool> filtered_shapes;
  std::vector<std::vector<bool>> filtered_parts;
  HitFilter filter;
};

class Accelerator {
 public:
  Accelerator();  // empty: every ray misses
  // Throws SceneError if Embree refuses the geometry.
  static Accelerator Build(const AcceleratorInput& input);

  Accelerator(Accelerator&&) noexcept;
  Accelerator& operator=(Accelerator&&) noexcept;
  ~Accelerator();

  // Closest hit with t in [0, ray.t_max]. Thread-safe.
  std::optional<RawHit> Intersect(const Ray& ray) const;
  // Whether anything lies on the ray with t in [0, ray.t_max]. Thread-safe.
  bool Occluded(const Ray& ray) const;

  // The bytes Embree holds now (geometry buffers and BVHs), by its memory monitor.
  std::size_t memory_bytes() const;

 private:
  struct Handles;  // RTCDevice and RTCScenes, released in order
  std::unique_ptr<Handles> handles_;
};

}  // namespace farm
