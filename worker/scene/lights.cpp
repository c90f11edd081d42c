#include "scene/lights.h"

#include <cmath>
#include <vector>

#include "math/math.h"
#include "sampling/warps.h"

namespace farm {
namespace {

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
  return LightSample{radiance, wi, s.p, s.n, dist, pdf};
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
      return LightSample{l.radiance, wi, s.p, s.n, dist, s.pdf};
    }

    std::optional<LightSample> operator()(const QuadLight& l) const {
      return FromAreaSample(l.quad.SampleArea(u), l.quad.Area(), l.radiance, ref);
    }

    std::optional<LightSample> operator()(const TriangleMeshLight& l) const {
      if (l.triangles.empty()) return std::nullopt;
      // One number picks the triangle, its remainder and u.y place the point.
      const auto pick = l.triangles.Sample(u.x);
      const Vec3 b = SampleUniformTriangle({pick.u_remapped, u.y});
      Vec3 p0, p1, p2;
      l.mesh->Corners(pick.index, p0, p1, p2);
      const Vec3 scaled_n = l.mesh->ScaledNormal(pick.index);
      const float len = Length(scaled_n);
      if (!(len > 0)) return std::nullopt;
      const SurfacePoint s{p0 * b.x + p1 * b.y + p2 * b.z, scaled_n / len};
      // Density by area over the whole mesh: pmf(triangle) / area(triangle) = 1 / total area.
      return FromAreaSample(s, l.area, l.radiance, ref);
    }
  };
  return std::visit(Visitor{ref, u}, light);
}

Rgb Power(const Light& light) {
  struct Visitor {
    Rgb operator()(const SphereLight& l) const { return l.radiance * (kPi * l.sphere.Area()); }
    Rgb operator()(const QuadLight& l) const { return l.radiance * (kPi * l.quad.Area()); }
    Rgb operator()(const TriangleMeshLight& l) const { return l.radiance * (kPi * l.area); }
  };
  return std::visit(Visitor{}, light);
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
  };
  return std::visit(Visitor{}, light);
}

}  // namespace farm
