#pragma once

// Where photons start: a light picked in proportion to power, then a point and a direction
// on it.
//
// Global photons leave each light as the light emits (lights.h SampleLe). Caustic photons
// are aimed at the specular geometry, as Jensen's projection maps do, so that the few paths
// that make caustics are not a small fraction of a large emission. From the sampled point
// of the light, a bounding sphere of a specular shape is chosen by a table fixed per light
// (scene/caustic_targets.h: the solid angle each sphere subtends from the nearest point of
// the light's bounds, in an alias table) and a direction sampled uniformly in its cone; the
// photon's power is divided by the density of the whole mixture of cones, which sums only
// the cones that hold the direction (the spheres its ray passes through, found through the
// targets' hierarchy), so the estimate stays unbiased for every path light -> specular (a
// spot's power along the direction is scaled by its falloff) and the cost per photon grows
// with the logarithm of the number of specular shapes, not with it. For light from
// infinitely far away (sun, environment), the direction is sampled as the light emits and
// the point on its disc within the shadows that the specular bounding spheres cast on the
// disc (a shadow chosen by its area), with the mixture density by area over the shadows
// that hold the point (the spheres the line through it crosses). A light point inside a
// bounding sphere falls back to plain emission.

#include <optional>

#include "math/ray.h"
#include "math/rgb.h"
#include "photon/photon_random.h"
#include "scene/scene_data.h"

namespace farm {

struct PhotonRay {
  Ray ray;
  Rgb power;  // flux of this one path, before dividing by the number of paths
};

// Nothing if the sample carries no light (the path still counts as emitted).
std::optional<PhotonRay> EmitPhoton(const SceneData& scene, PhotonMapKind kind,
                                    PhotonRandom& random);

// The density per unit solid angle of the directions in which light `light` (an index into
// scene.lights, a light with an origin) aims caustic photons from o, outside every target
// sphere, at the unit direction w: the sum over the spheres k of the light's table's
// Pmf(k) times the cone density SphereFromPointPdf of k at w.
float CausticAimPdf(const SceneData& scene, int light, const Vec3& o, const Vec3& w);

}  // namespace farm
