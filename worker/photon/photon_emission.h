#pragma once

// Where photons start: a light picked in proportion to power, then a point and a direction
// on it.
//
// Global photons leave each light as the light emits (lights.h SampleLe). Caustic photons
// are aimed at the specular geometry, as Jensen's projection maps do, so that the few paths
// that make caustics are not a small fraction of a large emission: from the sampled point of
// the light, the bounding sphere of a specular surface is picked (sampling/target_spheres.h)
// and a direction sampled uniformly in its cone: from the light's table (SceneData::
// caustic_aim: the solid angles seen from one point of the light, one read a photon), or,
// for lights beyond the tables' budget, down a tree by the solid angle estimated from the
// photon's own point (O(log n) in their number). For light from infinitely far away (sun,
// environment), the direction is sampled as the light emits and the point on its disc within
// the shadow one bounding sphere casts on the disc, picked by its area. A light point inside
// a bounding sphere falls back to plain emission.
//
// The photon is aimed at target i, and its path counts only if the first surface it hits is
// target i's (the photon tracer ends it otherwise): every caustic path L S+ D has exactly
// one target able to own it, the one around its first specular surface, whose sampling
// reaches it with a positive density (its surface lies in the sphere, so its direction in
// the cone and its point in the shadow). The power divided by that one strategy's density
// (the pick's probability times the cone's or the disc's) is then unbiased, with no sum
// over the other targets: paths aimed at one sphere that hit another's surface first (one
// behind the other) are the price, instead of a sum over every cone that cost O(n).

#include <optional>

#include "math/ray.h"
#include "math/rgb.h"
#include "photon/photon_random.h"
#include "scene/scene_data.h"

namespace farm {

struct PhotonRay {
  Ray ray;
  Rgb power;  // flux of this one path, before dividing by the number of paths
  // The specular target it was aimed at (an index of SceneData::specular_targets): the path
  // counts only if it hits that target's surface first. -1: emitted as the light emits.
  int target = -1;
};

// Nothing if the sample carries no light (the path still counts as emitted).
std::optional<PhotonRay> EmitPhoton(const SceneData& scene, PhotonMapKind kind,
                                    PhotonRandom& random);

}  // namespace farm
