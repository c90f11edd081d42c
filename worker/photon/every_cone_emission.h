#pragma once

// The caustic emission of main before issue 17 (7f376ca), kept as the reference that
// photon_emission_test.cpp compares EmitPhoton's caustics with:
// spheres chosen by the solid angle each subtends from the emission point itself, the
// density summed over every cone (for the sun, every shadow on its disc), a pass over every
// specular shape per photon. Same random numbers as EmitPhoton. Handles what those scenes
// hold: area and point lights (no spot falloff) and the sun, no environment, no light
// point inside a target (none emits then). Its photons own no target (PhotonRay::target
// -1): the tracer keeps them whatever they hit first. Header-only, never in the worker.

#include <cmath>
#include <optional>
#include <variant>
#include <vector>

#include "math/frame.h"
#include "math/math.h"
#include "photon/photon_emission.h"
#include "photon/photon_random.h"
#include "sampling/distribution.h"
#include "sampling/warps.h"
#include "scene/scene_data.h"

namespace farm::testing {

// Whether p is inside or on some specular target's sphere, by a pass over all of them.
inline bool InsideSomeTarget(const SceneData& scene, const Vec3& p) {
  for (int k = 0; k < scene.specular_targets.size(); ++k) {
    const BoundingSphere& t = scene.specular_targets[k];
    if (LengthSquared(t.center - p) <= t.radius * t.radius) return true;
  }
  return false;
}

inline std::optional<PhotonRay> EmitByEveryCone(const SceneData& scene, PhotonRandom& random) {
  const float u_light = random.Get1D();
  const Vec2 u_origin = random.Get2D();
  const float u_target = random.Get1D();
  const Vec2 u_direction = random.Get2D();
  const auto pick = scene.light_power.Sample(u_light);
  const Light& light = scene.lights[pick.index];
  std::vector<BoundingSphere> targets;
  for (int k = 0; k < scene.specular_targets.size(); ++k) targets.push_back(scene.specular_targets[k]);
  std::vector<float> weights;
  std::optional<PhotonRay> photon;
  if (const auto* sun = std::get_if<SunLight>(&light)) {
    const std::optional<DistantDirection> d = SampleDistantDirection(*sun, u_direction);
    const Vec3 disc_center = sun->disc.CenterFor(d->w);
    auto project = [&](const Vec3& c) { return c - d->w * Dot(c - disc_center, d->w); };
    for (const BoundingSphere& t : targets) weights.push_back(t.radius * t.radius);
    const DiscreteDistribution choose(weights);
    const BoundingSphere& t = targets[choose.Sample(u_target).index];
    const Frame frame = Frame::FromZ(d->w);
    const Vec2 q = SampleUniformDiskConcentric(u_origin);
    const Vec3 p = project(t.center) + (frame.x * q.x + frame.y * q.y) * t.radius;
    float pdf_area = 0;
    for (std::size_t k = 0; k < targets.size(); ++k)
      if (LengthSquared(p - project(targets[k].center)) <= Sqr(targets[k].radius))
        pdf_area += choose.Pmf(static_cast<int>(k)) / (kPi * Sqr(targets[k].radius));
    photon = PhotonRay{Ray{p, d->w}, d->weight / pdf_area};
  } else {
    const std::optional<LightOrigin> o = SampleLightOrigin(light, u_origin);
    if (InsideSomeTarget(scene, o->p)) return std::nullopt;  // none in these scenes
    for (const BoundingSphere& t : targets) {
      const float sin2 = Sqr(t.radius) / LengthSquared(t.center - o->p);
      weights.push_back(2 * kPi * (sin2 < 1e-3f ? sin2 / 2 : 1 - std::sqrt(1 - sin2)));
    }
    const DiscreteDistribution choose(weights);
    const BoundingSphere& t = targets[choose.Sample(u_target).index];
    const Vec3 w = Normalize(SampleSphereFromPoint(t.center, t.radius, o->p, u_direction).p - o->p);
    float pdf = 0;
    for (std::size_t k = 0; k < targets.size(); ++k)
      pdf += choose.Pmf(static_cast<int>(k)) * SphereFromPointPdf(targets[k].center, targets[k].radius, o->p, w);
    const float cos_light = o->is_point ? 1 : Dot(o->n, w);
    if (!(pdf > 0) || !(cos_light > 0)) return std::nullopt;
    const Vec3 start = o->is_point ? o->p : OffsetRayOrigin(o->p, o->n, w, scene.ray_epsilon);
    photon = PhotonRay{Ray{start, w}, o->emission * (cos_light / (o->pdf_area * pdf))};
  }
  photon->power = photon->power / pick.pmf;
  return photon;
}

}  // namespace farm::testing
