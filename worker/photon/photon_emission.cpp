#include "photon/photon_emission.h"

#include <cmath>

#include "math/frame.h"
#include "math/math.h"
#include "sampling/warps.h"
#include "util/overloaded.h"

namespace farm {
namespace {

Ray RayFrom(const Vec3& p, const Vec3& n, const Vec3& w, float epsilon) {
  const bool on_surface = LengthSquared(n) > 0;
  return Ray{on_surface ? OffsetRayOrigin(p, n, w, epsilon) : p, w};
}

// Light from infinitely far away, travelling along d.w: the point on the disc for d.w is
// sampled within the shadows the targets cast on it, a disc of each target's radius about
// the projection of its centre, chosen by the light's table (by area).
std::optional<PhotonRay> AimAtTargetsAlong(const SceneData& scene, int light, const std::optional<DistantDirection>& d,
                                           const DistantDisc& disc, float u_target, Vec2 u_disc) {
  if (!d) return std::nullopt;
  const CausticTargets& targets = scene.caustic_targets;
  const AliasTable& table = targets.ForLight(light);
  if (!(table.total() > 0)) return std::nullopt;
  const Frame frame = Frame::FromZ(d->w);
  const Vec3 disc_center = disc.CenterFor(d->w);
  auto project = [&](const Vec3& c) { return c - d->w * Dot(c - disc_center, d->w); };
  const BoundingSphere& chosen = targets.sphere(table.Sample(u_target));
  const Vec2 o = SampleUniformDiskConcentric(u_disc);
  const Vec3 p = project(chosen.center) + (frame.x * o.x + frame.y * o.y) * chosen.radius;
  // The shadows that hold p are those of the spheres the line through p along w crosses.
  float pdf_area = 0;
  targets.ForEachNearLine(p, d->w, [&](int k) {
    const BoundingSphere& t = targets.sphere(k);
    if (LengthSquared(p - project(t.center)) <= t.radius * t.radius)
      pdf_area += table.Pmf(k) / (kPi * t.radius * t.radius);
  });
  if (!(pdf_area > 0)) return std::nullopt;
  return PhotonRay{Ray{p, d->w}, d->weight / pdf_area};
}

// From a point of a light with an origin of its own (every kind but the sun).
std::optional<PhotonRay> AimAtTargetsFromOrigin(const SceneData& scene, int light_index, Vec2 u_origin,
                                                float u_target, Vec2 u_direction) {
  const Light& light = scene.lights[light_index];
  const std::optional<LightOrigin> o = SampleLightOrigin(light, u_origin);
  if (!o || !(o->pdf_area > 0)) return std::nullopt;
  const CausticTargets& targets = scene.caustic_targets;
  if (targets.MayContainPointsOf(light_index) && targets.AnyContains(o->p)) {
    // Inside a target's sphere every direction may reach it: emit as the light does.
    const std::optional<LightEmission> e = SampleLe(light, u_origin, u_direction);
    if (!e) return std::nullopt;
    return PhotonRay{RayFrom(e->p, e->n, e->w, scene.ray_epsilon), e->power};
  }
  const AliasTable& table = targets.ForLight(light_index);
  if (!(table.total() > 0)) return std::nullopt;
  const BoundingSphere& chosen = targets.sphere(table.Sample(u_target));
  const SphereSample s = SampleSphereFromPoint(chosen.center, chosen.radius, o->p, u_direction);
  const Vec3 d = s.p - o->p;
  if (!(LengthSquared(d) > 0)) return std::nullopt;
  const Vec3 w = Normalize(d);
  const float pdf_direction = CausticAimPdf(scene, light_index, o->p, w);
  if (!(pdf_direction > 0)) return std::nullopt;
  Rgb power;
  if (o->is_point) {
    power = o->emission * (o->cone ? o->cone->Falloff(w) : 1.0f) / pdf_direction;
  } else {
    const float cos_light = Dot(o->n, w);
    if (!(cos_light > 0)) return std::nullopt;  // aimed through the back of the light
    power = o->emission * (cos_light / (o->pdf_area * pdf_direction));
  }
  if (!power.IsFinite()) return std::nullopt;
  return PhotonRay{RayFrom(o->p, o->n, w, scene.ray_epsilon), power};
}

std::optional<PhotonRay> AimAtTargets(const SceneData& scene, int light_index, Vec2 u_origin, float u_target,
                                      Vec2 u_direction) {
  const Light& light = scene.lights[light_index];
  return std::visit(
      Overloaded{
          [&](const SunLight& sun) {
            return AimAtTargetsAlong(scene, light_index, SampleDistantDirection(sun, u_direction), sun.disc, u_target,
                                     u_origin);
          },
          [&](const EnvironmentLight& env) {
            return AimAtTargetsAlong(scene, light_index, SampleDistantDirection(env, u_direction), env.disc, u_target,
                                     u_origin);
          },
          [&](const OneOf<SphereLight, QuadLight, TriangleMeshLight, PointLight, SpotLight> auto&) {
            return AimAtTargetsFromOrigin(scene, light_index, u_origin, u_target, u_direction);
          },
      },
      light);
}

}  // namespace

float CausticAimPdf(const SceneData& scene, int light, const Vec3& o, const Vec3& w) {
  const CausticTargets& targets = scene.caustic_targets;
  if (targets.empty()) return 0;
  const AliasTable& table = targets.ForLight(light);
  float pdf = 0;
  targets.ForEachNearRay(o, w, [&](int k) {
    const BoundingSphere& t = targets.sphere(k);
    pdf += table.Pmf(k) * SphereFromPointPdf(t.center, t.radius, o, w);
  });
  return pdf;
}

std::optional<PhotonRay> EmitPhoton(const SceneData& scene, PhotonMapKind kind,
                                    PhotonRandom& random) {
  // A fixed number of draws whatever happens, so later draws of a path never shift.
  const float u_light = random.Get1D();
  const Vec2 u_origin = random.Get2D();
  const float u_target = random.Get1D();
  const Vec2 u_direction = random.Get2D();
  if (scene.lights.empty() || !(scene.light_power.total() > 0)) return std::nullopt;
  const auto pick = scene.light_power.Sample(u_light);
  if (!(pick.pmf > 0)) return std::nullopt;
  const Light& light = scene.lights[pick.index];

  std::optional<PhotonRay> photon;
  if (kind == PhotonMapKind::kCaustic) {
    if (scene.caustic_targets.empty()) return std::nullopt;
    photon = AimAtTargets(scene, pick.index, u_origin, u_target, u_direction);
  } else if (const std::optional<LightEmission> e = SampleLe(light, u_origin, u_direction)) {
    photon = PhotonRay{RayFrom(e->p, e->n, e->w, scene.ray_epsilon), e->power};
  }
  if (!photon) return std::nullopt;
  photon->power = photon->power / pick.pmf;
  if (!photon->power.IsFinite() || photon->power.IsBlack()) return std::nullopt;
  return photon;
}

}  // namespace farm
