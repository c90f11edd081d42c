#include "scene/scene_data.h"

#include <cmath>

namespace farm {

std::string ToString(const SurfaceHit& hit) {
  return "SurfaceHit{p=" + ToString(hit.p) + ", n=" + ToString(hit.n) +
         ", t=" + std::to_string(hit.t) + ", shape=" + std::to_string(hit.shape) +
         ", primitive=" + std::to_string(hit.primitive) + "}";
}

std::optional<SurfaceHit> SceneData::Intersect(const Ray& ray) const {
  const std::optional<RawHit> raw = accelerator.Intersect(ray);
  if (!raw) return std::nullopt;
  SurfaceHit hit;
  hit.t = raw->t;
  hit.shape = static_cast<int>(raw->shape);
  hit.primitive = raw->primitive;
  const Vec3 p = ray.At(raw->t);

  // Recompute the normal from our own copy of the geometry (independent of Embree's Ng
  // conventions) and move p back onto the surface: o + t d carries the rounding error of the
  // whole ray length, the projection only that of the primitive's coordinates.
  struct Visitor {
    const Vec3& p;
    uint32_t primitive;
    SurfaceHit& hit;
    void operator()(const SphereShape& s) const {
      const Vec3 d = p - s.center;
      const float len = Length(d);
      hit.n = len > 0 ? d / len : Vec3(0, 0, 1);
      hit.p = s.center + hit.n * s.radius;
    }
    void operator()(const QuadShape& q) const {
      hit.n = q.normal;
      hit.p = p - q.normal * Dot(p - q.origin, q.normal);
    }
    void operator()(const std::shared_ptr<const TriangleMesh>& m) const {
      const Vec3 scaled = m->ScaledNormal(static_cast<int>(primitive));
      const float len = Length(scaled);
      if (!(len > 0)) {  // degenerate sliver: keep Embree's point, any unit normal
        hit.n = Vec3(0, 0, 1);
        hit.p = p;
        return;
      }
      hit.n = scaled / len;
      const Vec3 p0 = m->positions[m->indices[std::size_t(primitive) * 3]];
      hit.p = p - hit.n * Dot(p - p0, hit.n);
    }
  };
  std::visit(Visitor{p, raw->primitive, hit}, shapes[hit.shape].geometry);
  hit.ns = hit.n;
  hit.material = shapes[hit.shape].material;
  return hit;
}

bool SceneData::Visible(const Vec3& p0, const Vec3& n0, const Vec3& p1, const Vec3& n1) const {
  const Vec3 d = p1 - p0;
  return SegmentClear(OffsetRayOrigin(p0, n0, d, ray_epsilon), OffsetRayOrigin(p1, n1, -d, ray_epsilon));
}

bool SceneData::FrontsSeeEachOther(const Vec3& p0, const Vec3& n0, const Vec3& p1,
                                   const Vec3& n1) const {
  return SegmentClear(OffsetRayOrigin(p0, n0, n0, ray_epsilon), OffsetRayOrigin(p1, n1, n1, ray_epsilon));
}

bool SceneData::SegmentClear(const Vec3& o0, const Vec3& o1) const {
  const Vec3 segment = o1 - o0;
  const float length = Length(segment);
  if (!(length > 0)) return true;
  return !accelerator.Occluded(Ray{o0, segment / length, length});
}

std::string SceneData::ToString() const {
  std::string s = "SceneData{" + std::to_string(width) + "x" + std::to_string(height) +
                  ", tile=" + std::to_string(tile_size) + ", spp=" +
                  std::to_string(samples_per_pixel) + ", seed=" + std::to_string(seed) + ", " +
                  camera.ToString() + ", materials=[";
  for (std::size_t i = 0; i < materials.size(); ++i)
    s += (i ? ", " : "") + material_names[i] + ": " + farm::ToString(materials[i]);
  s += "], shapes=[";
  for (std::size_t i = 0; i < shapes.size(); ++i)
    s += (i ? ", " : "") + shapes[i].label + ": " + farm::ToString(shapes[i].geometry);
  s += "], lights=[";
  for (std::size_t i = 0; i < lights.size(); ++i) s += (i ? ", " : "") + farm::ToString(lights[i]);
  s += "], " + bounds.ToString() + ", specular_targets=" + std::to_string(specular_targets.size()) +
       ", " + photons.ToString() + "}";
  return s;
}

}  // namespace farm
