#include "scene/accelerator.h"

#include <embree3/rtcore.h>

#include <array>
#include <cstring>
#include <deque>
#include <limits>
#include <string>
#include <unordered_map>

#include "scene/scene.h"

namespace farm {
namespace {

// What a filtered geometry's filter needs to know of its hits.
struct FilterTarget {
  const HitFilter* filter = nullptr;
  bool instanced = false;  // a part of a mesh: the shape is the instance Embree names
  uint32_t shape = 0;      // else the shape
  uint32_t part = 0;
  // The placements of the instances, by shape index (row-major 3x4), for instanced hits.
  const std::vector<std::array<float, 12>>* placements = nullptr;
};

}  // namespace

struct Accelerator::Handles {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<RTCScene> meshes;
  HitFilter filter;
  std::vector<std::array<float, 12>> placements;
  std::deque<FilterTarget> targets;  // stable addresses: Embree holds pointers to them
  std::atomic<std::int64_t> bytes{0};

  ~Handles() {
    if (scene) rtcReleaseScene(scene);  // first: its instances hold the mesh scenes
    for (RTCScene mesh : meshes) rtcReleaseScene(mesh);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

void ThrowOnDeviceError(RTCDevice device, const std::string& what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE)
    throw SceneError(what + ": Embree error " + std::to_string(static_cast<int>(error)));
}

template <typename T>
T* NewBuffer(RTCGeometry geometry, RTCBufferType type, RTCFormat format, std::size_t count) {
  return static_cast<T*>(rtcSetNewGeometryBuffer(geometry, type, 0, format, sizeof(T), count));
}

bool CountBytes(void* counter, ssize_t bytes, bool /*post*/) {
  static_cast<std::atomic<std::int64_t>*>(counter)->fetch_add(bytes, std::memory_order_relaxed);
  return true;
}

std::array<float, 12> RowsOf(const Placement& p) {
  std::array<float, 12> rows{};
  const double t[3] = {p.to_world.t.x, p.to_world.t.y, p.to_world.t.z};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) rows[4 * i + j] = static_cast<float>(p.to_world.m[i][j]);
    rows[4 * i + 3] = static_cast<float>(t[i]);
  }
  return rows;
}

Vec3 Apply(const std::array<float, 12>& m, const Vec3& p) {
  return {m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
          m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]};
}

// Embree's filter callback (closest-hit and occlusion queries alike): rejects the hits the
// scene's filter says to ignore. For an instanced part the ray and hit are in the mesh's
// space (Embree's rule); the point is placed into the world for the filter.
void FilterHits(const RTCFilterFunctionNArguments* args) {
  const auto& target = *static_cast<const FilterTarget*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    RawHit raw;
    raw.t = RTCRayN_tfar(args->ray, args->N, i);
    raw.primitive = RTCHitN_primID(args->hit, args->N, i);
    raw.barycentric = {RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i)};
    const Vec3 origin(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                      RTCRayN_org_z(args->ray, args->N, i));
    const Vec3 direction(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                         RTCRayN_dir_z(args->ray, args->N, i));
    Vec3 point = origin + direction * raw.t;
    if (target.instanced) {
      raw.shape = RTCHitN_instID(args->hit, args->N, i, 0);
      raw.part = target.part;
      point = Apply((*target.placements)[raw.shape], point);
    } else {
      raw.shape = target.shape;
    }
    if ((*target.filter)(raw, point)) args->valid[i] = 0;
  }
}

void SetFilter(RTCGeometry g, FilterTarget& target) {
  rtcSetGeometryUserData(g, &target);
  rtcSetGeometryIntersectFilterFunction(g, FilterHits);
  rtcSetGeometryOccludedFilterFunction(g, FilterHits);
}

RTCGeometry TriangleGeometry(RTCDevice device, const TriangleMesh& m) {
  static_assert(sizeof(Vec3) == 3 * sizeof(float));
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  Vec3* v = NewBuffer<Vec3>(g, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, m.positions.size());
  uint32_t* i = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(uint32_t), m.triangle_count()));
  if (v && i) {
    std::memcpy(v, m.positions.data(), m.positions.size() * sizeof(Vec3));
    std::memcpy(i, m.indices.data(), m.indices.size() * sizeof(uint32_t));
  }
  return g;
}

RTCScene NewScene(RTCDevice device) {
  RTCScene scene = rtcNewScene(device);
  // Robust traversal: no leaks through shared triangle edges; we trade a little speed for
  // watertight meshes, which photons need.
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  return scene;
}

// Attaches g to scene as geometry `id` and lets the scene hold it.
void Attach(RTCDevice device, RTCScene scene, RTCGeometry g, unsigned id, const std::string& what) {
  ThrowOnDeviceError(device, what);
  rtcCommitGeometry(g);
  rtcAttachGeometryByID(scene, g, id);
  rtcReleaseGeometry(g);
  ThrowOnDeviceError(device, what);
}

RTCGeometry MakeGeometry(RTCDevice device, const ShapeGeometry& shape,
                         const std::unordered_map<const SceneMesh*, RTCScene>& meshes) {
  struct Visitor {
    RTCDevice device;
    const std::unordered_map<const SceneMesh*, RTCScene>& meshes;
    RTCGeometry operator()(const SphereShape& s) const {
      // Analytic: Embree intersects the sphere exactly, no tessellation.
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
      struct Point { float x, y, z, r; };
      Point* p = NewBuffer<Point>(g, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT4, 1);
      if (p) *p = {s.center.x, s.center.y, s.center.z, s.radius};
      return g;
    }
    RTCGeometry operator()(const QuadShape& q) const {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_QUAD);
      Vec3* v = NewBuffer<Vec3>(g, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, 4);
      struct Quad { uint32_t v0, v1, v2, v3; };
      Quad* i = NewBuffer<Quad>(g, RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT4, 1);
      if (v && i) {
        v[0] = q.origin;
        v[1] = q.origin + q.edge_u;
        v[2] = q.origin + q.edge_u + q.edge_v;
        v[3] = q.origin + q.edge_v;
        *i = {0, 1, 2, 3};
      }
      return g;
    }
    RTCGeometry operator()(const std::shared_ptr<const TriangleMesh>& m) const { return TriangleGeometry(device, *m); }
    RTCGeometry operator()(const InstanceShape& instance) const {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(g, meshes.at(instance.mesh.get()));
      const std::array<float, 12> rows = RowsOf(instance.placement);
      rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, rows.data());
      return g;
    }
  };
  return std::visit(Visitor{device, meshes}, shape);
}

RTCRay ToEmbree(const Ray& ray) {
  RTCRay r{};
  r.org_x = ray.origin.x;
  r.org_y = ray.origin.y;
  r.org_z = ray.origin.z;
  r.dir_x = ray.direction.x;
  r.dir_y = ray.direction.y;
  r.dir_z = ray.direction.z;
  r.tnear = 0;
  r.tfar = ray.t_max;
  r.mask = std::numeric_limits<unsigned>::max();
  r.flags = 0;
  r.time = 0;
  return r;
}

bool Filtered(const std::vector<bool>& flags, std::size_t i) { return i < flags.size() && flags[i]; }

}  // namespace

Accelerator::Accelerator() = default;
Accelerator::Accelerator(Accelerator&&) noexcept = default;
Accelerator& Accelerator::operator=(Accelerator&&) noexcept = default;
Accelerator::~Accelerator() = default;

Accelerator Accelerator::Build(const AcceleratorInput& input) {
  Accelerator accel;
  accel.handles_ = std::make_unique<Handles>();
  Handles& h = *accel.handles_;
  h.device = rtcNewDevice(nullptr);
  if (!h.device) throw SceneError("scene: cannot create an Embree device");
  rtcSetDeviceMemoryMonitorFunction(h.device, CountBytes, &h.bytes);
  h.filter = input.filter;
  const auto target = [&h](bool instanced, uint32_t shape, uint32_t part) -> FilterTarget& {
    return h.targets.emplace_back(FilterTarget{&h.filter, instanced, shape, part, &h.placements});
  };

  std::unordered_map<const SceneMesh*, RTCScene> mesh_scenes;
  for (std::size_t m = 0; m < input.meshes.size(); ++m) {
    const SceneMesh& mesh = *input.meshes[m];
    RTCScene scene = h.meshes.emplace_back(NewScene(h.device));
    mesh_scenes.emplace(&mesh, scene);
    const std::vector<bool> none;
    const std::vector<bool>& filtered = m < input.filtered_parts.size() ? input.filtered_parts[m] : none;
    for (std::size_t p = 0; p < mesh.parts.size(); ++p) {
      const std::string what = "meshes[" + std::to_string(m) + "].parts[" + std::to_string(p) + "]";
      RTCGeometry g = TriangleGeometry(h.device, *mesh.parts[p].triangles);
      if (Filtered(filtered, p)) SetFilter(g, target(true, 0, static_cast<uint32_t>(p)));
      Attach(h.device, scene, g, static_cast<unsigned>(p), what);
    }
    rtcCommitScene(scene);
    ThrowOnDeviceError(h.device, "meshes[" + std::to_string(m) + "]");
  }

  h.scene = NewScene(h.device);
  h.placements.resize(input.shapes.size());
  for (std::size_t i = 0; i < input.shapes.size(); ++i) {
    const ShapeGeometry& shape = input.shapes[i];
    const std::string what = "shapes[" + std::to_string(i) + "]";
    RTCGeometry g = MakeGeometry(h.device, shape, mesh_scenes);
    if (const auto* instance = std::get_if<InstanceShape>(&shape)) {
      h.placements[i] = RowsOf(instance->placement);
    } else if (Filtered(input.filtered_shapes, i)) {
      SetFilter(g, target(false, static_cast<uint32_t>(i), 0));
    }
    Attach(h.device, h.scene, g, static_cast<unsigned>(i), what);
  }
  rtcCommitScene(h.scene);
  ThrowOnDeviceError(h.device, "shapes");
  return accel;
}

std::optional<RawHit> Accelerator::Intersect(const Ray& ray) const {
  if (!handles_) return std::nullopt;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray = ToEmbree(ray);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(handles_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  const bool instanced = rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID;
  return RawHit{rh.ray.tfar, instanced ? rh.hit.instID[0] : rh.hit.geomID, instanced ? rh.hit.geomID : 0,
                rh.hit.primID, {rh.hit.u, rh.hit.v}};
}

bool Accelerator::Occluded(const Ray& ray) const {
  if (!handles_) return false;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r = ToEmbree(ray);
  rtcOccluded1(handles_->scene, &context, &r);
  // Embree marks an occluded ray by setting tfar to -inf.
  return r.tfar < 0;
}

std::size_t Accelerator::memory_bytes() const {
  return handles_ ? static_cast<std::size_t>(std::max<std::int64_t>(0, handles_->bytes.load())) : 0;
}

}  // namespace farm
