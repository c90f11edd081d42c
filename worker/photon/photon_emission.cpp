#include "photon/photon_emission.h"

#include <cmath>
#include <vector>

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
// sampled within the shadows the targets cast on it.
std::optional<PhotonRay> AimAtTargetsAlong(const SceneData& scene, const std::optional<DistantDirection>& d,
                                           const DistantDisc& disc, float u_target, Vec2 u_disc) {
  if (!d) return std::nullopt;
  const TargetSpheres& targets = scene.specular_targets;
  const Frame frame = Frame::FromZ(d->w);
  const Vec3 disc_center = disc.CenterFor(d->w);
  // Each target's shadow on the disc's plane: a disc of its radius around the projection of
  // its centre, chosen in proportion to area.
  const TargetSpheres::Pick pick = targets.PickByCrossSection(u_target);
  const BoundingSphere& target = targets[pick.index];
  const double pdf_area = pick.probability / (kPi * double(target.radius) * target.radius);
  if (!(pdf_area > 0)) return std::nullopt;
  const Vec3 center = target.center - d->w * Dot(target.center - disc_center, d->w);
  const Vec2 o = SampleUniformDiskConcentric(u_disc);
  const Vec3 p = center + (frame.x * o.x + frame.y * o.y) * target.radius;
  return PhotonRay{Ray{p, d->w}, d->weight / static_cast<float>(pdf_area), pick.index};
}

// From a point of a light with an origin of its own (every kind but the sun).
std::optional<PhotonRay> AimAtTargetsFromOrigin(const SceneData& scene, const Light& light, const AliasTable& aim,
                                                Vec2 u_origin, float u_target, Vec2 u_direction) {
  const std::optional<LightOrigin> o = SampleLightOrigin(light, u_origin);
  if (!o || !(o->pdf_area > 0)) return std::nullopt;
  const TargetSpheres& targets = scene.specular_targets;
  if (targets.AnyContains(o->p)) {
    // Inside a target's sphere every direction may reach it: emit as the light does.
    const std::optional<LightEmission> e = SampleLe(light, u_origin, u_direction);
    if (!e) return std::nullopt;
    return PhotonRay{RayFrom(e->p, e->n, e->w, scene.ray_epsilon), e->power};
  }
  // The light's table when it has one (one read), else the tree's descent from o.
  std::optional<TargetSpheres::Pick> pick;
  if (aim.size() > 0) {
    const AliasTable::Choice c = aim.Sample(u_target);
    pick = TargetSpheres::Pick{c.index, c.pmf};
  } else {
    pick = targets.PickFrom(o->p, u_target);
  }
  if (!pick) return std::nullopt;
  const BoundingSphere& target = targets[pick->index];
  const SphereSample s = SampleSphereFromPoint(target.center, target.radius, o->p, u_direction);
  const Vec3 d = s.p - o->p;
  if (!(LengthSquared(d) > 0)) return std::nullopt;
  const Vec3 w = Normalize(d);
  const float pdf_direction = static_cast<float>(pick->probability * s.pdf);
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
  return PhotonRay{RayFrom(o->p, o->n, w, scene.ray_epsilon), power, pick->index};
}

std::optional<PhotonRay> AimAtTargets(const SceneData& scene, int light_index, Vec2 u_origin, float u_target,
                                      Vec2 u_direction) {
  const Light& light = scene.lights[light_index];
  return std::visit(
      Overloaded{
          [&](const SunLight& sun) {
            return AimAtTargetsAlong(scene, SampleDistantDirection(sun, u_direction), sun.disc, u_target, u_origin);
          },
          [&](const EnvironmentLight& env) {
            return AimAtTargetsAlong(scene, SampleDistantDirection(env, u_direction), env.disc, u_target, u_origin);
          },
          [&](const OneOf<SphereLight, QuadLight, TriangleMeshLight, PointLight, SpotLight> auto&) {
            return AimAtTargetsFromOrigin(scene, light, scene.caustic_aim[light_index], u_origin, u_target,
                                          u_direction);
          },
      },
      light);
}

}  // namespace

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
    if (scene.specular_targets.empty()) return std::nullopt;
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
