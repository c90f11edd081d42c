#pragma once

// A heterogeneous medium's density on a dense voxel grid (a farm grid file's,
// docs/grid-format.md): nx x ny x nz values at the centres of the cells of an axis-aligned
// box, x fastest, trilinearly interpolated (clamped at the box's faces), 0 outside the box.
// The medium's sigma_t at p is density(p) times a scale. Each brick of 8 x 8 x 8 cells has
// a majorant and a minorant, the largest and smallest density its interpolation reads
// (counting the cells beyond its faces), walked brick by brick along a ray: in sparse smoke
// most bricks are empty and cost one step. Free flights are delta-tracked against the
// bricks' majorants (Woodcock), so a thin wisp beside a dense core is not tracked at the
// core's rate; optical depth (transmittance) is integrated exactly.
//
// Rays need not have a unit direction: a ray moved into the grid's own space by an affine
// map keeps its parameter t, and every t here is the caller's (a distance in the scene).

#include <functional>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "math/bounds.h"
#include "math/ray.h"
#include "media/homogeneous_medium.h"

namespace farm {

class DenseGrid {
 public:
  static constexpr int kBrick = 8;  // cells along each side of a brick

  // Throws std::invalid_argument unless values holds nx * ny * nz finite values >= 0 and
  // the box is not empty.
  DenseGrid(int nx, int ny, int nz, std::vector<float> values, const Bounds3& box);

  float Density(const Vec3& p) const;
  float max_density() const { return max_; }
  const Bounds3& box() const { return box_; }
  int nx() const { return nx_; }
  int ny() const { return ny_; }
  int nz() const { return nz_; }

  // A stretch [t0, t1] of a ray inside one brick, with the brick's bounds on the density.
  struct Span {
    float t0 = 0, t1 = 0;
    float minorant = 0, majorant = 0;
  };

  // The pieces of a span (of a brick of this grid) along which the density is one cubic in
  // t (between planes of cell centres; a uniform brick is one piece), in order: visit(a, b,
  // the integral of the density over [a, b]) returns false to stop.
  using PieceVisit = std::function<bool(float a, float b, double depth)>;
  void Pieces(const Ray& ray, const Span& span, const PieceVisit& visit) const;
  // The integral of the density over [a, b] within one piece (Simpson's rule: exact there).
  double DepthBetween(const Ray& ray, float a, float b) const;

  // The bricks a ray crosses within [t_min, t_max], in order along the ray (3D DDA).
  class Walk {
   public:
    Walk(const DenseGrid& grid, const Ray& ray, float t_min, float t_max);
    // The next span, or false past the last.
    bool Next(Span& span);

   private:
    const DenseGrid& grid_;
    int index_[3] = {0, 0, 0}, step_[3] = {0, 0, 0};
    float next_[3] = {0, 0, 0}, delta_[3] = {0, 0, 0};
    float t_ = 0, t_end_ = 0;
    bool done_ = true;
  };

 private:
  float At(int x, int y, int z) const { return values_[(std::size_t(z) * ny_ + y) * nx_ + x]; }
  std::size_t Brick(int bx, int by, int bz) const { return (std::size_t(bz) * bricks_[1] + by) * bricks_[0] + bx; }

  int nx_, ny_, nz_;
  std::vector<float> values_;
  Bounds3 box_;
  float max_ = 0;
  int bricks_[3] = {1, 1, 1};
  std::vector<float> brick_min_, brick_max_;
};

// The part of [t_min, t_max] of the ray inside the box (slabs), or nothing.
std::optional<std::pair<float, float>> ClipToBox(const Bounds3& box, const Ray& ray, float t_min, float t_max);

// Uniform random numbers in [0, 1), drawn in sequence by the trackers (the callers hash
// them from a sample's numbers, so a flight is deterministic).
using UniformSource = std::function<float()>;

// Delta tracking along ray over [t_min, t_max] through density x sigma_scale: the t of the
// first real collision, or nothing if the flight gets past t_max (with probability exactly
// the transmittance, whatever the majorants).
std::optional<float> DeltaTrack(const DenseGrid& grid, float sigma_scale, const Ray& ray, float t_min, float t_max,
                                const UniformSource& u);

// The integral of the density along the ray over [t_min, t_max], exactly (to rounding):
// between two planes of cell centres the trilinear density along a line is a cubic in t,
// which Simpson's rule integrates exactly, so each piece costs three lookups (two shared
// with its neighbours); empty bricks are skipped and uniform ones taken in closed form.
// Transmittance is then exp(-sigma_scale x depth), with no noise: ratio tracking (Novak et
// al. 2014) against these majorants answers 0 or 1 through a uniform brick (the variance
// of a coin toss: +57% in a point light's halo), and its residual variant stays noisy in
// turbulent smoke whose bricks' minorants are 0.
double OpticalDepth(const DenseGrid& grid, const Ray& ray, float t_min, float t_max);

// Free flight truncated to [t_min, t_max]: a distance drawn from the density sigma_t(t)
// T(t) / (1 - T(t_max)), sigma_t = sigma_scale x the density, found by inverting the exact
// optical depth, with its pdf. An estimate T sigma_s / pdf is then the albedo times (1 -
// T(t_max)) wherever it lands: what the homogeneous medium's truncated flight gives, so
// single scattering and the volume estimate add no noise of their own through smoke, only
// the light's. Nothing where the stretch holds no density.
std::optional<DistanceSample> SampleTruncatedFlight(const DenseGrid& grid, float sigma_scale, const Ray& ray,
                                                    float t_min, float t_max, float u);

// The density with which SampleTruncatedFlight draws t: sigma_t(t) T(t) / (1 - T(t_max)),
// T from t_min, the depth to t and over the whole stretch integrated exactly in one walk;
// 0 outside [t_min, t_max] or where the stretch holds no density. What multiple importance
// sampling weighs another strategy's distance against (render/media_transport.h).
float TruncatedFlightPdf(const DenseGrid& grid, float sigma_scale, const Ray& ray, float t_min, float t_max, float t);

}  // namespace farm
