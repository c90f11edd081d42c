#include "scene/lights.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

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
  l.Corners(pick.index, p0, p1, p2);
  const Vec3 scaled_n = Cross(p1 - p0, p2 - p0);
  const float len = Length(scaled_n);
  if (!(len > 0)) return std::nullopt;
  return SurfacePoint{p0 * b.x + p1 * b.y + p2 * b.z, scaled_n / len};
}

}  // namespace

TriangleMeshLight TriangleMeshLight::Make(std::shared_ptr<const TriangleMesh> mesh, const Rgb& radiance,
                                          std::optional<Placement> placement) {
  TriangleMeshLight light;
  light.mesh = std::move(mesh);
  light.placement = std::move(placement);
  light.radiance = radiance;
  std::vector<float> areas(light.mesh->triangle_count());
  double total = 0;
  for (int i = 0; i < light.mesh->triangle_count(); ++i) {
    Vec3 p0, p1, p2;
    light.Corners(i, p0, p1, p2);
    total += areas[i] = 0.5f * Length(Cross(p1 - p0, p2 - p0));
  }
  light.triangles = DiscreteDistribution(areas);
  light.area = static_cast<float>(total);
  return light;
}

void TriangleMeshLight::Corners(int i, Vec3& p0, Vec3& p1, Vec3& p2) const {
  mesh->Corners(i, p0, p1, p2);
  if (!placement) return;
  p0 = placement->Point(p0);
  p1 = placement->Point(p1);
  p2 = placement->Point(p2);
  if (placement->mirrors) std::swap(p1, p2);  // counter-clockwise from the front again
}

float SpotCone::Falloff(const Vec3& w) const {
  const float c = Dot(w, axis);
  if (!(cos_inner > cos_outer)) return c >= cos_outer ? 1.0f : 0.0f;
  return Sqr(std::clamp((c - cos_outer) / (cos_inner - cos_outer), 0.0f, 1.0f));
}

float SpotCone::SolidAngle() const {
  // Constant inside the inner cone, the square of a ramp in cos between the cones.
  return 2 * kPi * ((1 - cos_inner) + std::max(0.0f, cos_inner - cos_outer) / 3);
}

Vec3 SpotCone::Sample(Vec2 u) const {
  // cos is drawn from the density in proportion to the falloff: a share of the mass is the
  // inner cap (uniform in cos), the rest the ramp, whose squared CDF inverts by a cube root.
  const float cap = 1 - cos_inner, ramp = std::max(0.0f, cos_inner - cos_outer) / 3;
  const float p_cap = cap / (cap + ramp);
  float c;
  if (u.x < p_cap) {
    c = 1 - cap * (u.x / p_cap);
  } else {
    const float v = std::min((u.x - p_cap) / (1 - p_cap), 1.0f);
    c = cos_outer + (cos_inner - cos_outer) * std::cbrt(v);
  }
  const float sin_theta = SafeSqrt(1 - c * c), phi = 2 * kPi * u.y;
  return Frame::FromZ(axis).FromLocal({sin_theta * std::cos(phi), sin_theta * std::sin(phi), c});
}

DistantDisc DistantDisc::Around(const BoundingSphere& scene) {
  // A margin so that the disc covers the sphere's silhouette despite rounding, and a floor
  // for a scene that is a single point.
  return {scene.center, scene.radius * 1.01f + 1e-4f * (1 + MaxComponent(Abs(scene.center)))};
}

float DistantDisc::Area() const { return kPi * radius * radius; }

SunLight SunLight::Make(const Vec3& direction, const Rgb& irradiance, double angular_diameter_degrees,
                        const BoundingSphere& scene) {
  SunLight sun{direction, irradiance, 0, Rgb(), DistantDisc::Around(scene)};
  const double alpha = Radians(angular_diameter_degrees) / 2;
  if (alpha > 0) {
    // 1 - cos alpha = 2 sin^2(alpha / 2), without cancellation.
    sun.one_minus_cos = static_cast<float>(2 * Sqr(std::sin(alpha / 2)));
    sun.radiance = irradiance / static_cast<float>(std::numbers::pi * Sqr(std::sin(alpha)));
  }
  return sun;
}

Light LightFromProto(const pb::Light& light, const BoundingSphere& scene) {
  // Directions are scaled first: a tiny non-zero direction (1e-200) is valid, its square
  // is not.
  const auto unit = [](const pb::Vec3& v) {
    const Vec3d d = Vec3dOf(v);
    return Vec3(Normalize(d / MaxComponent(Abs(d))));
  };
  switch (light.kind_case()) {
    case pb::Light::kPoint:
      return PointLight{Vec3(Vec3dOf(light.point().position())), RgbOf(light.point().intensity())};
    case pb::Light::kSpot: {
      const pb::SpotLight& s = light.spot();
      const SpotCone cone{unit(s.direction()), static_cast<float>(std::cos(Radians(s.inner_cone_degrees()))),
                          static_cast<float>(std::cos(Radians(s.outer_cone_degrees())))};
      return SpotLight{Vec3(Vec3dOf(s.position())), RgbOf(s.intensity()), cone};
    }
    case pb::Light::kSun:
      return SunLight::Make(unit(light.sun().direction()), RgbOf(light.sun().irradiance()),
                            light.sun().angular_diameter_degrees(), scene);
    case pb::Light::KIND_NOT_SET:
      break;
  }
  throw std::logic_error("LightFromProto: a light without a kind (CheckRules refuses it)");
}

std::optional<DistantDirection> SampleDistantDirection(const SunLight& sun, Vec2 u) {
  if (sun.one_minus_cos == 0) return DistantDirection{sun.direction, sun.irradiance};
  // Uniform over the cone about the direction of travel: the radiance over 1 / solid angle.
  const float d = u.x * sun.one_minus_cos;  // 1 - cos of the sample
  const float sin_theta = SafeSqrt(d * (2 - d)), phi = 2 * kPi * u.y;
  const Vec3 w = Frame::FromZ(sun.direction).FromLocal({sin_theta * std::cos(phi), sin_theta * std::sin(phi), 1 - d});
  return DistantDirection{Normalize(w), sun.radiance * (2 * kPi * sun.one_minus_cos)};
}

std::optional<DistantDirection> SampleDistantDirection(const EnvironmentLight& l, Vec2 u) {
  const std::optional<Environment::Sample> s = l.environment->SampleDirection(u);
  if (!s || !(s->pdf > 0)) return std::nullopt;
  const Rgb weight = s->radiance / s->pdf;
  if (!weight.IsFinite() || weight.IsBlack()) return std::nullopt;
  return DistantDirection{-s->w, weight};
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

    std::optional<LightSample> operator()(const PointLight& l) const { return FromPoint(l.position, l.intensity); }

    std::optional<LightSample> operator()(const SpotLight& l) const {
      std::optional<LightSample> s = FromPoint(l.position, l.intensity);
      if (!s) return std::nullopt;
      const float falloff = l.cone.Falloff(-s->wi);
      if (!(falloff > 0)) return std::nullopt;
      s->radiance *= falloff;
      return s;
    }

    std::optional<LightSample> operator()(const SunLight& l) const {
      // A point beyond all geometry along the way to the sun: ref lies within the scene's
      // sphere, which the disc's radius bounds.
      const float far = l.disc.Beyond();
      if (l.one_minus_cos == 0) return LightSample{l.irradiance, -l.direction, ref - l.direction * far, Vec3(), far, 1, true};
      const std::optional<DistantDirection> d = SampleDistantDirection(l, u);
      if (!d) return std::nullopt;
      const Vec3 wi = -d->w;
      return LightSample{l.radiance, wi, ref + wi * far, Vec3(), far, 1 / (2 * kPi * l.one_minus_cos), false};
    }

    std::optional<LightSample> operator()(const EnvironmentLight& l) const {
      const std::optional<Environment::Sample> s = l.environment->SampleDirection(u);
      if (!s || !(s->pdf > 0) || s->radiance.IsBlack()) return std::nullopt;
      const float far = l.disc.Beyond();
      return LightSample{s->radiance, s->w, ref + s->w * far, Vec3(), far, s->pdf, false};
    }

    // Light from a point with intensity I: I / d^2.
    std::optional<LightSample> FromPoint(const Vec3& position, const Rgb& intensity) const {
      const Vec3 d = position - ref;
      const float dist2 = LengthSquared(d);
      if (!(dist2 > 0)) return std::nullopt;
      const float dist = std::sqrt(dist2);
      const Rgb irradiance = intensity / dist2;
      if (!irradiance.IsFinite()) return std::nullopt;
      return LightSample{irradiance, d / dist, position, Vec3(), dist, 1, true};
    }
  };
  return std::visit(Visitor{ref, u}, light);
}

std::optional<LightSample> LightSampleAlong(const Light& light, const Vec3& ref, const Vec3& wi, const Vec3& p,
                                            const Vec3& n) {
  // As SampleLi places a distant light's point: beyond all geometry along wi.
  const auto distant = [&](const DistantDisc& disc, const Rgb& radiance, float pdf) -> std::optional<LightSample> {
    if (radiance.IsBlack() || !(pdf > 0) || !std::isfinite(pdf)) return std::nullopt;
    const float far = disc.Beyond();
    return LightSample{radiance, wi, ref + wi * far, Vec3(), far, pdf, false};
  };
  return std::visit(
      Overloaded{
          [&](const SphereLight& l) -> std::optional<LightSample> {
            if (!(Dot(n, wi) < 0)) return std::nullopt;  // from inside, the front faces away
            const float pdf = SphereFromPointPdf(l.sphere.center, l.sphere.radius, ref, wi);
            if (!(pdf > 0) || !std::isfinite(pdf)) return std::nullopt;
            return LightSample{l.radiance, wi, p, n, Distance(ref, p), pdf, false};
          },
          [&](const QuadLight& l) { return FromAreaSample({p, n}, l.quad.Area(), l.radiance, ref); },
          [&](const TriangleMeshLight& l) { return FromAreaSample({p, n}, l.area, l.radiance, ref); },
          [](const OneOf<PointLight, SpotLight> auto&) -> std::optional<LightSample> { return std::nullopt; },
          [&](const SunLight& l) -> std::optional<LightSample> {
            if (l.one_minus_cos == 0) return std::nullopt;
            // 1 - cos of the angle to the disc's centre as |a - b|^2 / 2: no cancellation.
            if (!(LengthSquared(wi + l.direction) / 2 <= l.one_minus_cos)) return std::nullopt;
            return distant(l.disc, l.radiance, 1 / (2 * kPi * l.one_minus_cos));
          },
          [&](const EnvironmentLight& l) {
            return distant(l.disc, l.environment->Radiance(wi), l.environment->Pdf(wi));
          },
      },
      light);
}

std::optional<LightOrigin> SampleLightOrigin(const Light& light, Vec2 u) {
  struct Visitor {
    Vec2 u;
    std::optional<LightOrigin> operator()(const SphereLight& l) const {
      const Vec3 n = SampleUniformSphere(u);
      return LightOrigin{l.sphere.center + n * l.sphere.radius, n, 1 / l.sphere.Area(), l.radiance, false,
                         std::nullopt};
    }
    std::optional<LightOrigin> operator()(const QuadLight& l) const {
      const SurfacePoint s = l.quad.SampleArea(u);
      return LightOrigin{s.p, s.n, 1 / l.quad.Area(), l.radiance, false, std::nullopt};
    }
    std::optional<LightOrigin> operator()(const TriangleMeshLight& l) const {
      const std::optional<SurfacePoint> s = SampleMeshPoint(l, u);
      if (!s || !(l.area > 0)) return std::nullopt;
      return LightOrigin{s->p, s->n, 1 / l.area, l.radiance, false, std::nullopt};
    }
    std::optional<LightOrigin> operator()(const PointLight& l) const {
      return LightOrigin{l.position, Vec3(), 1, l.intensity, true, std::nullopt};
    }
    std::optional<LightOrigin> operator()(const SpotLight& l) const {
      return LightOrigin{l.position, Vec3(), 1, l.intensity, true, l.cone};
    }
    std::optional<LightOrigin> operator()(const SunLight&) const { return std::nullopt; }
    std::optional<LightOrigin> operator()(const EnvironmentLight&) const { return std::nullopt; }
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
  // Light from infinitely far away crosses the disc for its sampled direction.
  const auto distant = [&](const std::optional<DistantDirection>& d, const DistantDisc& disc)
      -> std::optional<LightEmission> {
    if (!d) return std::nullopt;
    const Frame frame = Frame::FromZ(d->w);
    const Vec2 o = SampleUniformDiskConcentric(u_origin);
    const Vec3 p = disc.CenterFor(d->w) + (frame.x * o.x + frame.y * o.y) * disc.radius;
    return LightEmission{p, Vec3(), d->w, d->weight * disc.Area()};
  };
  return std::visit(
      Overloaded{
          [&](const SunLight& sun) { return distant(SampleDistantDirection(sun, u_direction), sun.disc); },
          [&](const EnvironmentLight& env) { return distant(SampleDistantDirection(env, u_direction), env.disc); },
          [&](const SpotLight& spot) -> std::optional<LightEmission> {
            return LightEmission{spot.position, Vec3(), spot.cone.Sample(u_direction),
                                 spot.intensity * spot.cone.SolidAngle()};
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
    Rgb operator()(const SpotLight& l) const { return l.intensity * l.cone.SolidAngle(); }
    Rgb operator()(const SunLight& l) const {
      // Radiance times the cone's solid angle (E for a delta sun), through the disc.
      const Rgb per_area = l.one_minus_cos == 0 ? l.irradiance : l.radiance * (2 * kPi * l.one_minus_cos);
      return per_area * l.disc.Area();
    }
    Rgb operator()(const EnvironmentLight& l) const { return l.environment->SphereIntegral() * l.disc.Area(); }
  };
  return std::visit(Visitor{}, light);
}

bool IsDeltaLight(const Light& light) {
  return std::visit(Overloaded{
                        [](const OneOf<PointLight, SpotLight> auto&) { return true; },
                        [](const SunLight& l) { return l.one_minus_cos == 0; },
                        [](const OneOf<SphereLight, QuadLight, TriangleMeshLight, EnvironmentLight> auto&) {
                          return false;
                        },
                    },
                    light);
}

std::string ToString(const DistantDisc& disc) {
  return "DistantDisc{center=" + ToString(disc.center) + ", radius=" + std::to_string(disc.radius) + "}";
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
      return "TriangleMeshLight{" + l.mesh->ToString() + (l.placement ? ", placed by " + ToString(l.placement->to_world) : "") +
             ", area=" + std::to_string(l.area) + ", radiance=" + ToString(l.radiance) + "}";
    }
    std::string operator()(const PointLight& l) const {
      return "PointLight{position=" + ToString(l.position) +
             ", intensity=" + ToString(l.intensity) + "}";
    }
    std::string operator()(const SpotLight& l) const {
      return "SpotLight{position=" + ToString(l.position) + ", intensity=" + ToString(l.intensity) +
             ", axis=" + ToString(l.cone.axis) + ", cos_inner=" + std::to_string(l.cone.cos_inner) +
             ", cos_outer=" + std::to_string(l.cone.cos_outer) + "}";
    }
    std::string operator()(const SunLight& l) const {
      return "SunLight{direction=" + ToString(l.direction) + ", irradiance=" + ToString(l.irradiance) +
             ", one_minus_cos=" + std::to_string(l.one_minus_cos) + ", " + ToString(l.disc) + "}";
    }
    std::string operator()(const EnvironmentLight& l) const {
      return "EnvironmentLight{" + l.environment->ToString() + ", " + ToString(l.disc) + "}";
    }
  };
  return std::visit(Visitor{}, light);
}

}  // namespace farm
