#pragma once

// A heterogeneous medium's density on a dense voxel grid (the machinery of issue 15's
// heterogeneous media; no scene field reads a grid yet, docs/media.md): nx x ny x nz
// values at the centres of the cells of an axis-aligned box, x fastest, trilinearly
// interpolated (clamped at the box's faces), 0 outside the box. The medium's sigma_t at p
// is density(p) times a scale per channel; transmittance and free flights through it are
// estimated by tracking against a majorant, the grid's largest value (Woodcock's delta
// tracking; ratio tracking for transmittance, Novak et al. 2014).

#include <functional>
#include <optional>
#include <stdexcept>
#include <vector>

#include "math/bounds.h"
#include "math/ray.h"

namespace farm {

class DenseGrid {
 public:
  // Throws std::invalid_argument unless values holds nx * ny * nz finite values >= 0 and
  // the box is not empty.
  DenseGrid(int nx, int ny, int nz, std::vector<float> values, const Bounds3& box);

  float Density(const Vec3& p) const;
  float max_density() const { return max_; }
  const Bounds3& box() const { return box_; }

 private:
  float At(int x, int y, int z) const { return values_[(std::size_t(z) * ny_ + y) * nx_ + x]; }

  int nx_, ny_, nz_;
  std::vector<float> values_;
  Bounds3 box_;
  float max_ = 0;
};

// Uniform random numbers in [0, 1), drawn in sequence by the trackers (the callers hash
// them from a sample's seed, so a flight is deterministic).
using UniformSource = std::function<float()>;

// Delta tracking along ray (unit direction) over [0, t_max] through density x sigma_scale:
// the distance of the first real collision, or nothing if the flight gets past t_max (with
// probability exactly the transmittance, whatever the majorant).
std::optional<float> DeltaTrack(const DenseGrid& grid, float sigma_scale, const Ray& ray, float t_max,
                                const UniformSource& u);

// Ratio tracking: an unbiased estimate of the transmittance over [0, t_max], the product
// of (1 - sigma(x) / majorant) over tentative collisions.
float RatioTrackTransmittance(const DenseGrid& grid, float sigma_scale, const Ray& ray, float t_max,
                              const UniformSource& u);

}  // namespace farm
