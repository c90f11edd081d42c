#include "scene/accelerator.h"

#include <embree3/rtcore.h>

#include <cstring>
#include <limits>
#include <string>

#include "scene/scene.h"

namespace farm {

struct Accelerator::Handles {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  ~Handles() {
    if (scene) rtcReleaseScene(scene);
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

RTCGeometry MakeGeometry(RTCDevice device, const ShapeGeometry& shape) {
  struct Visitor {
    RTCDevice device;
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
    RTCGeometry operator()(const std::shared_ptr<const TriangleMesh>& m) const {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      Vec3* v = NewBuffer<Vec3>(g, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, m->positions.size());
      uint32_t* i = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
          g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), m->triangle_count()));
      if (v && i) {
        std::memcpy(v, m->positions.data(), m->positions.size() * sizeof(Vec3));
        std::memcpy(i, m->indices.data(), m->indices.size() * sizeof(uint32_t));
      }
      return g;
    }
  };
  static_assert(sizeof(Vec3) == 3 * sizeof(float));
  return std::visit(Visitor{device}, shape);
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

}  // namespace

Accelerator::Accelerator() = default;
Accelerator::Accelerator(Accelerator&&) noexcept = default;
Accelerator& Accelerator::operator=(Accelerator&&) noexcept = default;
Accelerator::~Accelerator() = default;

Accelerator Accelerator::Build(std::span<const ShapeGeometry> shapes) {
  Accelerator accel;
  accel.handles_ = std::make_unique<Handles>();
  Handles& h = *accel.handles_;
  h.device = rtcNewDevice(nullptr);
  if (!h.device) throw SceneError("scene: cannot create an Embree device");
  h.scene = rtcNewScene(h.device);
  // Robust traversal: no leaks through shared triangle edges; we trade a little speed for
  // watertight meshes, which photons will need.
  rtcSetSceneFlags(h.scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(h.scene, RTC_BUILD_QUALITY_HIGH);
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    RTCGeometry g = MakeGeometry(h.device, shapes[i]);
    ThrowOnDeviceError(h.device, "shapes[" + std::to_string(i) + "]");
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(h.scene, g, static_cast<unsigned>(i));
    rtcReleaseGeometry(g);  // the scene holds it now
    ThrowOnDeviceError(h.device, "shapes[" + std::to_string(i) + "]");
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
  return RawHit{rh.ray.tfar, rh.hit.geomID, rh.hit.primID};
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

}  // namespace farm
