#pragma once

#include <cstdint>
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

// The fewest neighbours a progressive round's estimate keeps (ForRound): the estimate
// needs two (the farthest only sets the radius), and a few more keep one round's noise
// bounded.
inline constexpr int kMinRoundNeighbours = 8;

// A round's settings of an estimate: progressive photon mapping shrinks its radius by
// radius_scale (RoundSettings), and since every round traces as many photons as the
// first, k shrinks by the same area, radius_scale^2 (at least kMinRoundNeighbours; never
// more than k): the k-nearest radius, which binds long before max_radius does, shrinks
// too, and with it the estimate's bias (a blur of the irradiance over the disc, and light
// lost where the disc hangs over an edge), while the image's mean over the rounds keeps
// converging (Hachisuka et al. 2008; Knaus and Zwicker 2011). radius_scale must be in
// (0, 1].
RadianceEstimateSettings ForRound(RadianceEstimateSettings settings, double radius_scale);

// The companion of an estimate, whose difference from it is the error estimate's measure of
// its bias (the bias layer, image/error_estimate.h): twice the neighbours and a bound
// sqrt(2) times the radius, so that the disc's area doubles whether k or the bound sets it.
// A kernel estimate's leading bias grows with the kernel's area (a disc of radius r blurs
// the irradiance by (r^2 / 8) times its Laplacian), so the companion's bias is twice the
// estimate's and their difference the estimate's own, from the same photons.
RadianceEstimateSettings Companion(RadianceEstimateSettings settings);

// Reflected radiance at p (surface normal n) from the k nearest photons: sum over photons of
// bsdf(wi) * power * filter weight, over the disc area, normalised so that a uniform photon
// density gives the exact irradiance whatever the filter. Photons on surfaces facing away
// from n are ignored (they leak through thin walls). When k are found, the disc is that of
// the farthest, which sets the radius and is not summed: with it the estimate would be
// k / (k - 1) too bright on average (of m Poisson points, (m - 1) / (pi r_m^2) is the
// unbiased density); with fewer, the whole max_radius disc was searched and each counts.
// scratch is reused between calls.
Rgb EstimateRadiance(const PhotonMap& map, const Vec3& p, const Vec3& n,
                     const RadianceEstimateSettings& settings,
                     const std::function<Rgb(const Vec3& wi)>& bsdf,
                     std::vector<PhotonNeighbour>& scratch);

// An estimate with the radius of its disc (0 when it found no photon), for a caller that
// corrects the area it divided by (photon/surface_estimate.h).
struct DiscEstimate {
  Rgb radiance;
  float radius = 0;
};
DiscEstimate EstimateRadianceOverDisc(const PhotonMap& map, const Vec3& p, const Vec3& n,
                                      const RadianceEstimateSettings& settings,
                                      const std::function<Rgb(const Vec3& wi)>& bsdf,
                                      std::vector<PhotonNeighbour>& scratch);

}  // namespace farm
