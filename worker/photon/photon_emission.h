#pragma once

// Where photons start: a light picked in proportion to power, then a point and a direction
// on it.
//
// Global photons leave each light as the light emits (lights.h SampleLe). Caustic photons
// are aimed at the specular geometry, as Jensen's projection maps do, so that the few paths
// that make caustics are not a small fraction of a large emission: from the sampled point of
// the light, a bounding sphere of a specular shape is chosen by the hierarchy of
// sampling/target_spheres.h (in proportion to the solid angle it subtends among a few, by
// estimates of it down a tree among many) and a direction sampled uniformly in its cone; the
// photon's power is divided by the density of the whole mixture of cones, summed over the
// cones that hold the direction, so the estimate stays unbiased for every path light ->
// specular (a spot's power along the direction is scaled by its falloff) and a photon costs
// O(log n) in the number of specular shapes. For light from infinitely far away (sun,
// environment), the direction is sampled as the light emits and the point on its disc within
// the shadows that the specular bounding spheres cast on the disc, each chosen by its area,
// with the mixture density by area. A light point inside a bounding sphere falls back to
// plain emission.

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

}  // namespace farm
