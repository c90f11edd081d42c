#pragma once

// Light transport through media along camera paths (docs/media.md): where a ray travels
// in a medium, what it reaches is attenuated by the medium's transmittance (closed-form,
// or ratio-tracked through a grid), and light from every light scattered once towards the
// ray along the way (single scattering) is added:
//
//   L_ss = integral over t of T(t0, t) sigma_s p(wo, wi) L_light(x(t), wi) T_shadow dt,
//
// estimated by picking a light in proportion to power and a distance along the segment:
// equiangularly towards point and spot lights and towards the point drawn on a quad or mesh
// light (media/equiangular.h: it cancels their 1 / d^2, which is what makes halos clean and
// keeps rays that pass close to an emitter from blowing up), by the truncated free-flight
// density for spheres and distant lights (a grid's: its majorants', MediumSegment::
// SampleDistance). Shadow rays from media and from surfaces are attenuated by the transmittance
// of the medium they cross.

#include <array>
#include <functional>
#include <vector>
#include <optional>

#include "math/bounds.h"
#include "math/ray.h"
#include "math/rgb.h"
#include "photonmap/photon_map.h"
#include "photonmap/radiance_estimate.h"
#include "scene/media_segments.h"
#include "scene/lights.h"

namespace farm {


// The light a light sample reaches x with, times the transmittance of the way; zero where
// something blocks it.
using ShadowTransmittance = std::function<Rgb(const Vec3& x, const LightSample& sample)>;

// The random numbers of one single-scattering sample.
struct InScatterDimensions {
  Vec2 light;  // the point on the light (SampleLi)
  float channel = 0;  // which channel's free-flight density (spheres and distant lights)
  float distance = 0;
};

// One sample of the single-scattered radiance arriving at the ray's origin from `light`
// (picked with probability pick_pmf) along the segment; ray.direction unit.
Rgb InScatter(const MediumSegment& segment, const Ray& ray, const Light& light, float pick_pmf,
              const InScatterDimensions& u, const ShadowTransmittance& shadow);

// One sample of the radiance scattered towards the ray's origin along the segment by light
// that bounced or scattered before (multiple scattering), from the volume photon map
// (Jensen and Christensen 1998): at a distance drawn from the truncated free-flight
// density, the in-scattered radiance times sigma_s is the photons' power weighed by the
// phase function over the volume of the sphere holding the k nearest,
//
//   sigma_s L_i(x, wo) = sum_p p(wo, wi_p) Phi_p / (4/3 pi r^3),
//
// the farthest of the k setting r and not summed (then the estimate of a uniform density
// is unbiased, as on surfaces: radiance_estimate.h); fewer than k within max_radius: all
// counted, r = max_radius. The sphere's volume is that part of it the point sees, and its
// photons those in that part (probe rays: SeenBall), so no light is lost where it hangs
// over a wall nor borrowed from beyond one. In a grid, where sigma_s varies within the
// sphere, the photons' density is that of sigma_s L_i: the sum is divided by the integral
// of sigma_t over the seen part instead of its volume (an estimate of albedo x L_i) and
// multiplied by sigma_t at the point, so that scattering is not smeared past the smoke's
// edges (a halo where sigma_s is 0) nor averaged away in its wisps. The
// settings' filter does not apply. ray.direction unit; u_probe turns the probes.
Rgb VolumeInScatter(const SceneData& scene, const MediumSegment& segment, const Ray& ray, const PhotonMap& volume,
                    const RadianceEstimateSettings& estimate, float u_channel, float u_distance, Vec2 u_probe,
                    std::vector<PhotonNeighbour>& scratch);

// The part of the ball of radius r around x that x sees (no surface between), as
// kVolumeProbes probe rays find it: a spherical Fibonacci set of directions turned by u
// (its azimuth and its lattice's offset), each with the distance it sees, up to r.
// fraction is the mean of (depth / r)^3, the seen share of the ball's volume (exact for a
// wall in the ball when the probes are many; 1 in open space); Sees tells whether a point
// at `offset` from x lies in the seen part, by the probe nearest its direction, so that
// the photons beyond a wall (in the bright room behind a ceiling) are not counted.
inline constexpr int kVolumeProbes = 24;
struct SeenBall {
  std::array<Vec3, kVolumeProbes> directions;
  std::array<float, kVolumeProbes> depths;
  float fraction = 1;

  static SeenBall Probe(const SceneData& scene, const Vec3& x, float r, Vec2 u);
  bool Sees(const Vec3& offset) const;
  // The integral of f over the seen part of the ball around x: along each probe, two
  // Gauss-Legendre points over its depth (exact for f uniform: the s^2 of the volume
  // element is integrated exactly), each probe standing for 4 pi / kVolumeProbes of the
  // directions.
  double Integral(const Vec3& x, const std::function<float(const Vec3&)>& f) const;
};

}  // namespace farm
