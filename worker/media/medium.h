#pragma once

// A participating medium as the renderer meets it (docs/media.md): homogeneous, whose
// transport is closed-form (homogeneous_medium.h), or a density grid placed in the scene,
// whose transport is tracked against majorants (dense_grid.h). The operations below are
// what light transport asks of the stretch [t0, t1] of a ray (unit direction, t a
// distance) in a medium; camera paths, volumetric paths and photon paths ask them through
// MediumSegment (scene/media_segments.h).
//
// A grid's transmittance is exact (its optical depth integrated piece by piece:
// dense_grid.h); delta tracking a free flight needs random numbers beyond the two a
// sample hands over: they are hashed from the query itself (the ray's origin and
// direction, the stretch, the sample's number), so that an answer is a pure function of
// what was asked, the same on every worker.

#include <memory>
#include <optional>
#include <string>
#include <variant>

#include "math/ray.h"
#include "math/rgb.h"
#include "math/transform.h"
#include "media/dense_grid.h"
#include "media/homogeneous_medium.h"

namespace farm {

// A heterogeneous medium: sigma_t(p) = density_scale x grid density at the grid-space
// point p maps to, the same in every channel; sigma_s = albedo x sigma_t.
struct GridMedium {
  std::shared_ptr<const DenseGrid> grid;
  Affine3d to_grid;  // scene space to the grid's own space (the inverse of its placement)
  float density_scale = 1;
  Rgb albedo;
  float g = 0;

  // A scene ray in the grid's space, its parameter t unchanged (its direction not unit).
  Ray ToGrid(const Ray& ray) const;
  float SigmaT(const Vec3& p) const;
};

struct Medium {
  std::variant<HomogeneousMedium, GridMedium> kind;

  float g() const;
  // Whether light can scatter in it: some sigma_s positive (a grid's albedo: its density
  // is not looked at).
  bool Scatters() const;
  std::string ToString() const;
};

// The transmittance over [t0, t1] of the ray, exactly: closed-form, or exp(-scale x the
// grid's optical depth). 1 for an empty stretch.
Rgb Transmittance(const Medium& medium, const Ray& ray, float t0, float t1);

// sigma_s at p.
Rgb ScatteringAt(const Medium& medium, const Vec3& p);

// A distance in [t0, t1] with its density: the free flight truncated to the stretch,
// channel-averaged (homogeneous), or exactly sigma_t T over the stretch (a grid's,
// dense_grid.h's SampleTruncatedFlight).
// Nothing where no distance can be drawn (vacuum, an empty stretch, empty bricks only).
std::optional<DistanceSample> SampleDistance(const Medium& medium, const Ray& ray, float t0, float t1, float u_channel,
                                             float u);

// The density with which SampleDistance draws t (its channel average for a homogeneous
// medium), 0 outside [t0, t1]: what another strategy's sample of t is weighed against.
float DistancePdf(const Medium& medium, const Ray& ray, float t0, float t1, float t);

// A free flight from t0 (what a photon does): either a collision at t, where the photon
// scatters carrying weight (sigma_s T / pdf: the albedo in a grid, where delta tracking
// draws collisions with density sigma_t T), or no collision before t1 (t unset), where it
// goes on carrying weight (T / the probability of getting through: 1 in a grid).
struct FreeFlight {
  std::optional<float> t;
  Rgb weight;
};
FreeFlight SampleFlight(const Medium& medium, const Ray& ray, float t0, float t1, float u_channel, float u);

}  // namespace farm
