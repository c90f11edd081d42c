#include "scene/scene_data.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "scene/surface_geometry.h"

namespace farm {

std::string ToString(const SurfaceHit& hit) {
  return "SurfaceHit{p=" + ToString(hit.p) + ", n=" + ToString(hit.n) + ", t=" + std::to_string(hit.t) +
         ", shape=" + std::to_string(hit.shape) + ", part=" + std::to_string(hit.part) +
         ", primitive=" + std::to_string(hit.primitive) + ", material=" + std::to_string(hit.material) +
         ", ns=" + ToString(hit.ns) + (hit.has_uv ? ", uv=" + ToString(hit.uv) : std::string()) +
         ", dpdu=" + ToString(hit.dpdu) + ", dpdv=" + ToString(hit.dpdv) + "}";
}

std::optional<SurfaceHit> SceneData::Intersect(const Ray& ray) const {
  const std::optional<RawHit> raw = accelerator.Intersect(ray);
  if (!raw) return std::nullopt;
  return Refine(*raw, ray.At(raw->t));
}

std::optional<SceneData::FacingHit> SceneData::IntersectFacing(const Ray& ray) const {
  const std::optional<RawHit> raw = accelerator.Intersect(ray);
  if (!raw) return std::nullopt;
  struct Visitor {
    const RawHit& raw;
    Vec3 point;
    Vec3 operator()(const SphereShape& s) const { return SphereNormal(s, point); }
    Vec3 operator()(const QuadShape& q) const { return q.normal; }
    Vec3 operator()(const std::shared_ptr<const TriangleMesh>& m) const {
      return TriangleNormal(*m, nullptr, raw.primitive);
    }
    Vec3 operator()(const InstanceShape& instance) const {
      return TriangleNormal(*instance.mesh->parts[raw.part].triangles, &instance.placement, raw.primitive);
    }
  };
  return FacingHit{raw->t, std::visit(Visitor{*raw, ray.At(raw->t)}, shapes[raw->shape].geometry)};
}

SurfaceHit SceneData::Refine(const RawHit& raw, const Vec3& point) const {
  SurfaceHit hit;
  hit.t = raw.t;
  hit.shape = static_cast<int>(raw.shape);
  hit.part = raw.part;
  hit.primitive = raw.primitive;
  const ShapeRecord& shape = shapes[hit.shape];
  hit.material = shape.material;
  struct Visitor {
    const RawHit& raw;
    const Vec3& point;
    SurfaceHit& hit;
    void operator()(const SphereShape& s) const { DescribeSphereHit(s, point, hit); }
    void operator()(const QuadShape& q) const { DescribeQuadHit(q, point, hit); }
    void operator()(const std::shared_ptr<const TriangleMesh>& m) const {
      DescribeTriangleHit(*m, nullptr, raw.primitive, raw.barycentric, point, hit);
    }
    void operator()(const InstanceShape& instance) const {
      const SceneMesh::Part& part = instance.mesh->parts[raw.part];
      hit.material = part.material;
      DescribeTriangleHit(*part.triangles, &instance.placement, raw.primitive, raw.barycentric, point, hit);
    }
  };
  std::visit(Visitor{raw, point, hit}, shape.geometry);
  return hit;
}

CutoutHit SceneData::CutoutHitOf(const RawHit& raw, const Vec3& point) const {
  const ShapeRecord& shape = shapes[raw.shape];
  CutoutHit cut;
  cut.material = shape.material;
  const TriangleMesh* mesh = nullptr;
  if (const auto* m = std::get_if<std::shared_ptr<const TriangleMesh>>(&shape.geometry)) {
    mesh = m->get();
  } else if (const auto* instance = std::get_if<InstanceShape>(&shape.geometry)) {
    const SceneMesh::Part& part = instance->mesh->parts[raw.part];
    mesh = part.triangles.get();
    cut.material = part.material;
  }
  if (mesh) {
    cut.has_uv = TriangleTexcoords(*mesh, raw.primitive, raw.barycentric, cut.uv);
    return cut;
  }
  const SurfaceHit hit = Refine(raw, point);  // a sphere's or quad's: closed forms, cheap
  return {hit.material, hit.uv, hit.has_uv};
}

std::size_t SceneData::GeometryBytes() const {
  std::unordered_set<const TriangleMesh*> counted;
  std::size_t bytes = accelerator.memory_bytes();
  const auto count = [&](const std::shared_ptr<const TriangleMesh>& m) {
    if (counted.insert(m.get()).second) bytes += m->MemoryBytes();
  };
  for (const ShapeRecord& shape : shapes)
    if (const auto* m = std::get_if<std::shared_ptr<const TriangleMesh>>(&shape.geometry)) count(*m);
  for (const auto& mesh : meshes)
    for (const SceneMesh::Part& part : mesh->parts) count(part.triangles);
  return bytes;
}

bool SceneData::Visible(const Vec3& p0, const Vec3& n0, const Vec3& p1, const Vec3& n1) const {
  const Vec3 d = p1 - p0;
  return SegmentClear(OffsetRayOrigin(p0, n0, d, ray_epsilon), OffsetRayOrigin(p1, n1, -d, ray_epsilon));
}

bool SceneData::FrontsSeeEachOther(const Vec3& p0, const Vec3& n0, const Vec3& p1,
                                   const Vec3& n1) const {
  // Between two points of one convex surface (a ball) the segment runs beneath it. A surface
  // that turns by theta from n0 to n1 rises at most |p1 - p0| tan(theta / 2) / 2 above
  // their chord (a crease halfway); each end is lifted twice that along its normal, which
  // covers normals leaning up to 60 degrees from the chord's. Coplanar points get no lift,
  // so a wall standing between two points of a floor still blocks.
  const float c = std::clamp(Dot(n0, n1), -1.0f, 1.0f);
  const float lift = Length(p1 - p0) * std::sqrt((1 - c) / std::max(1 + c, 1.0f));
  return SegmentClear(OffsetRayOrigin(p0, n0, n0, ray_epsilon) + n0 * lift,
                      OffsetRayOrigin(p1, n1, n1, ray_epsilon) + n1 * lift);
}

int SceneData::AreaLightOf(const SurfaceHit& hit) const {
  const TargetSurface surface{hit.shape, hit.part};
  const auto before = [](const TargetSurface& a, const TargetSurface& b) {
    return a.shape != b.shape ? a.shape < b.shape : a.part < b.part;
  };
  const auto it = std::lower_bound(area_light_surfaces.begin(), area_light_surfaces.end(), surface, before);
  return it != area_light_surfaces.end() && *it == surface ? static_cast<int>(it - area_light_surfaces.begin()) : -1;
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
       ", " + photons.ToString();
  if (medium) s += ", medium=" + medium->ToString();
  s += "}";
  return s;
}

}  // namespace farm
