#pragma once

// A heterogeneous medium's density on a dense voxel grid (a farm grid file's,
// docs/grid-format.md): nx x ny x nz values at the centres of the cells of an axis-aligned
// box, x fastest, trilinearly interpolated (clamped at the box's faces), 0 outside the box.
// The medium's sigma_t at p is density(p) times a scale; transmittance and free flights
// through it are estimated by tracking against a majorant (Woodcock's delta tracking;
// residual ratio tracking for transmittance, Novak et al. 2014). Each brick of 8 x 8 x 8
// cells has a majorant and a minorant, the largest and smallest density its interpolation
// reads (counting the cells beyond its faces), walked brick by brick along the ray: in
// sparse smoke most bricks are empty and cost one step, a thin wisp beside a dense core is
// not tracked at the core's rate, and the minorant's share of a brick's transmittance is
// taken in closed form (a uniform brick costs no tracking and adds no noise).
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

// Residual ratio tracking: an unbiased estimate of the transmittance over [t_min, t_max].
// In each brick, exp(-minorant x length) in closed form times the product of (1 - (sigma(x)
// - minorant) / (majorant - minorant)) over tentative collisions against the residual
// majorant (plain ratio tracking against a tight majorant would answer 0 or 1: the
// variance of a coin toss).
float RatioTrackTransmittance(const DenseGrid& grid, float sigma_scale, const Ray& ray, float t_min, float t_max,
                              const UniformSource& u);

// A distance in [t_min, t_max] drawn from the majorants' free-flight density truncated to
// the stretch, m(t) exp(-integral of m) / (1 - exp(-the whole stretch's)), m the bricks'
// majorants times sigma_scale, with its pdf: every sample lands where the grid may hold
// something, and weighed by a tracked transmittance it estimates integrals over the
// stretch. Nothing where every brick on the way is empty.
std::optional<DistanceSample> SampleMajorantDistance(const DenseGrid& grid, float sigma_scale, const Ray& ray,
                                                     float t_min, float t_max, float u);

}  // namespace farm
