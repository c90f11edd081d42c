#include "scene/lights.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "contract/failure.h"
#include "math/frame.h"
#include "math/math.h"
#include "renderfarm/v1/scene.pb.h"
#include "sampling/warps.h"
#include "scene/proto_values.h"
#include "util/overloaded.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

// Completes a sample of a point chosen by area (density 1/area) into a solid-angle sample.
std::optional<LightSample> FromAreaSample(const SurfacePoint& s, float area, const Rgb& radiance,
                                          const Vec3& ref) {
  const Vec3 d = s.p - ref;
  const float dist2 = LengthSquared(d);
  if (!(dist2 > 0) || !(area > 0)) return std::nullopt;
  const float dist = std::sqrt(dist2);
  const Vec3 wi = d / dist;
  const float cos_light = -Dot(s.n, wi);  // > 0 when the front faces ref
  if (!(cos_light > 0)) return std::nullopt;
  const float pdf = dist2 / (cos_light * area);
  if (!std::isfinite(pdf)) return std::nullopt;
  return LightSample{radiance, wi, s.p, s.n, dist, pdf, false};
}

// A point of a mesh uniform by total area, with its front normal; nothing for slivers.
std::optional<SurfacePoint> SampleMeshPoint(const TriangleMeshLight& l, Vec2 u) {
  if (l.triangles.empty()) return std::nullopt;
  // One number picks the triangle, its remainder and u.y place the point.
  const auto pick = l.triangles.Sample(u.x);
  const Vec3 b = SampleUniformTriangle({pick.u_remapped, u.y});
  Vec3 p0, p1, p2;
  l.mesh->Corners(pick.index, p0, p1, p2);
  const Vec3 scaled_n = l.mesh->ScaledNormal(pick.index);
  const float len = Length(scaled_n);
  if (!(len > 0)) return std::nullopt;
  return SurfacePoint{p0 * b.x + p1 * b.y + p2 * b.z, scaled_n / len};
}

}  // namespace

TriangleMeshLight TriangleMeshLight::Make(std::shared_ptr<const TriangleMesh> mesh,
                                          const Rgb& radiance) {
  std::vector<float> areas(mesh->triangle_count());
  double total = 0;
  for (int i = 0; i < mesh->triangle_count(); ++i) total += areas[i] = mesh->TriangleArea(i);
  TriangleMeshLight light;
  light.triangles = DiscreteDistribution(areas);
  light.area = static_cast<float>(total);
  light.radiance = radiance;
  light.mesh = std::move(mesh);
  return light;
}

SunLight SunLight::Make(const Vec3& direction, const Rgb& irradiance, const BoundingSphere& scene) {
  // A margin so that the disc covers the sphere's silhouette despite rounding, and a floor
  // for a scene that is a single point.
  const float radius = scene.radius * 1.01f + 1e-4f * (1 + MaxComponent(Abs(scene.center)));
  return {direction, irradiance, scene.center - direction * (radius * 1.05f), radius};
}

Light LightFromProto(const pb::Light& light, const BoundingSphere& scene) {
  switch (light.kind_case()) {
    case pb::Light::kPoint:
      return PointLight{Vec3(Vec3dOf(light.point().position())), RgbOf(light.point().intensity())};
    case pb::Light::kSun: {
      // Scaled first: a tiny non-zero direction (1e-200) is valid, its square is not.
      const Vec3d d = Vec3dOf(light.sun().direction());
      return SunLight::Make(Vec3(Normalize(d / MaxComponent(Abs(d)))), RgbOf(light.sun().irradiance()),
                            scene);
    }
    case pb::Light::kSpot:  // placeholder until the light helper's spot light lands
      throw UnsupportedError("spot lights are not rendered by this worker yet");
    case pb::Light::KIND_NOT_SET:
      break;
  }
  throw std::logic_error("LightFromProto: a light without a kind (CheckRules refuses it)");
}

std::optional<LightSample> SampleLi(const Light& light, const Vec3& ref, Vec2 u) {
  struct Visitor {
    const Vec3& ref;
    Vec2 u;

    std::optional<LightSample> operator()(const SphereLight& l) const {
      const SphereSample s = SampleSphereFromPoint(l.sphere.center, l.sphere.radius, ref, u);
      if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return std::nullopt;
      const Vec3 d = s.p - ref;
      const float dist = Length(d);
      if (!(dist > 0)) return std::nullopt;
      const Vec3 wi = d / dist;
      // The cone sample always sees the outside; from inside, the front faces away.
      if (!(Dot(s.n, wi) < 0)) return std::nullopt;
      return LightSample{l.radiance, wi, s.p, s.n, dist, s.pdf, false};
    }

    std::optional<LightSample> operator()(const QuadLight& l) const {
      return FromAreaSample(l.quad.SampleArea(u), l.quad.Area(), l.radiance, ref);
    }

    std::optional<LightSample> operator()(const TriangleMeshLight& l) const {
      const std::optional<SurfacePoint> s = SampleMeshPoint(l, u);
      if (!s) return std::nullopt;
      // Density by area over the whole mesh: pmf(triangle) / area(triangle) = 1 / total area.
      return FromAreaSample(*s, l.area, l.radiance, ref);
    }

    std::optional<LightSample> operator()(const PointLight& l) const {
      const Vec3 d = l.position - ref;
      const float dist2 = LengthSquared(d);
      if (!(dist2 > 0)) return std::nullopt;
      const float dist = std::sqrt(dist2);
      const Rgb irradiance = l.intensity / dist2;
      if (!irradiance.IsFinite()) return std::nullopt;
      return LightSample{irradiance, d / dist, l.position, Vec3(), dist, 1, true};
    }

    std::optional<LightSample> operator()(const SunLight& l) const {
      // A point beyond all geometry along the way to the sun: ref lies within the scene's
      // sphere, which the disc's radius bounds, so two disc radii always get out.
      const Vec3 wi = -l.direction;
      const float far = 2.5f * l.disc_radius;
      return LightSample{l.irradiance, wi, ref + wi * far, Vec3(), far, 1, true};
    }
  };
  return std::visit(Visitor{ref, u}, light);
}

std::optional<LightOrigin> SampleLightOrigin(const Light& light, Vec2 u) {
  struct Visitor {
    Vec2 u;
    std::optional<LightOrigin> operator()(const SphereLight& l) const {
      const Vec3 n = SampleUniformSphere(u);
      return LightOrigin{l.sphere.center + n * l.sphere.radius, n, 1 / l.sphere.Area(),
                         l.radiance, false};
    }
    std::optional<LightOrigin> operator()(const QuadLight& l) const {
      const SurfacePoint s = l.quad.SampleArea(u);
      return LightOrigin{s.p, s.n, 1 / l.quad.Area(), l.radiance, false};
    }
    std::optional<LightOrigin> operator()(const TriangleMeshLight& l) const {
      const std::optional<SurfacePoint> s = SampleMeshPoint(l, u);
      if (!s || !(l.area > 0)) return std::nullopt;
      return LightOrigin{s->p, s->n, 1 / l.area, l.radiance, false};
    }
    std::optional<LightOrigin> operator()(const PointLight& l) const {
      return LightOrigin{l.position, Vec3(), 1, l.intensity, true};
    }
    std::optional<LightOrigin> operator()(const SunLight&) const { return std::nullopt; }
  };
  return std::visit(Visitor{u}, light);
}

std::optional<LightEmission> SampleLe(const Light& light, Vec2 u_origin, Vec2 u_direction) {
  // Every light but the sun emits from a point of its own (SampleLightOrigin).
  const auto from_origin = [&]() -> std::optional<LightEmission> {
    const std::optional<LightOrigin> o = SampleLightOrigin(light, u_origin);
    if (!o || !(o->pdf_area > 0)) return std::nullopt;
    if (o->is_point)  // uniform over the sphere: I / (1 / 4 pi)
      return LightEmission{o->p, Vec3(), SampleUniformSphere(u_direction), o->emission * (4 * kPi)};
    // Cosine-weighted about the front: L cos / (pdf_area * cos / pi) = pi L / pdf_area.
    const Vec3 local = SampleCosineHemisphere(u_direction);
    if (!(local.z > 0)) return std::nullopt;
    const Vec3 w = Frame::FromZ(o->n).FromLocal(local);
    return LightEmission{o->p, o->n, w, o->emission * (kPi / o->pdf_area)};
  };
  return std::visit(
      Overloaded{
          [&](const SunLight& sun) -> std::optional<LightEmission> {
            const Frame frame = Frame::FromZ(sun.direction);
            const Vec2 d = SampleUniformDiskConcentric(u_origin);
            const Vec3 p = sun.disc_center + (frame.x * d.x + frame.y * d.y) * sun.disc_radius;
            return LightEmission{p, Vec3(), sun.direction, Power(light)};
          },
          [&](const OneOf<SphereLight, QuadLight, TriangleMeshLight, PointLight> auto&) {
            return from_origin();
          },
      },
      light);
}

Rgb Power(const Light& light) {
  struct Visitor {
    Rgb operator()(const SphereLight& l) const { return l.radiance * (kPi * l.sphere.Area()); }
    Rgb operator()(const QuadLight& l) const { return l.radiance * (kPi * l.quad.Area()); }
    Rgb operator()(const TriangleMeshLight& l) const { return l.radiance * (kPi * l.area); }
    Rgb operator()(const PointLight& l) const { return l.intensity * (4 * kPi); }
    Rgb operator()(const SunLight& l) const {
      return l.irradiance * (kPi * l.disc_radius * l.disc_radius);
    }
  };
  return std::visit(Visitor{}, light);
}

bool IsDeltaLight(const Light& light) {
  return std::visit(Overloaded{
                        [](const OneOf<PointLight, SunLight> auto&) { return true; },
                        [](const OneOf<SphereLight, QuadLight, TriangleMeshLight> auto&) { return false; },
                    },
                    light);
}

std::string ToString(const Light& light) {
  struct Visitor {
    std::string operator()(const SphereLight& l) const {
      return "SphereLight{" + l.sphere.ToString() + ", radiance=" + ToString(l.radiance) + "}";
    }
    std::string operator()(const QuadLight& l) const {
      return "QuadLight{" + l.quad.ToString() + ", radiance=" + ToString(l.radiance) + "}";
    }
    std::string operator()(const TriangleMeshLight& l) const {
      return "TriangleMeshLight{" + l.mesh->ToString() + ", area=" + std::to_string(l.area) +
             ", radiance=" + ToString(l.radiance) + "}";
    }
    std::string operator()(const PointLight& l) const {
      return "PointLight{position=" + ToString(l.position) +
             ", intensity=" + ToString(l.intensity) + "}";
    }
    std::string operator()(const SunLight& l) const {
      return "SunLight{direction=" + ToString(l.direction) +
             ", irradiance=" + ToString(l.irradiance) + ", disc_center=" +
             ToString(l.disc_center) + ", disc_radius=" + std::to_string(l.disc_radius) + "}";
    }
  };
  return std::visit(Visitor{}, light);
}

}  // namespace farm
