#pragma once

#include <functional>
#include <vector>

#include "math/rgb.h"
#include "math/vec3.h"
#include "photonmap/photon_map.h"

namespace farm {

enum class PhotonFilter { kBox, kCone, kGaussian };

struct RadianceEstimateSettings {
  int neighbours = 100;
  float max_radius = 1.0f;
  PhotonFilter filter = PhotonFilter::kBox;
  float cone_k = 1.1f;
};

// Reflected radiance at p (surface normal n) from the k nearest photons: sum over photons of
// bsdf(wi) * power * filter weight, over the disc area, normalised so that a uniform photon
// density gives the exact irradiance whatever the filter. Photons on surfaces facing away
// from n are ignored (they leak through thin walls). scratch is reused between calls.
Rgb EstimateRadiance(const PhotonMap& map, const Vec3& p, const Vec3& n,
                     const RadianceEstimateSettings& settings,
                     const std::function<Rgb(const Vec3& wi)>& bsdf,
                     std::vector<PhotonNeighbour>& scratch);

}  // namespace farm
