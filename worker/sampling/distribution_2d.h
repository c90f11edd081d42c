#pragma once

// A piecewise-constant density over the unit square [0, 1)^2 on a grid of cells with given
// nonnegative weights (row-major, rows along v), sampled by inverting its marginal over rows
// and then the conditional within the chosen row: importance-samples an environment map.

#include <span>
#include <string>
#include <vector>

#include "math/vec3.h"
#include "sampling/distribution.h"

namespace farm {

class Distribution2D {
 public:
  Distribution2D() = default;
  // weights.size() == width * height, each finite and >= 0. If they sum to zero the
  // density is uniform.
  Distribution2D(std::span<const float> weights, int width, int height);

  struct Sample {
    Vec2 uv;          // in [0, 1)^2
    float pdf = 0;    // density per unit area of the square
  };
  Sample Draw(Vec2 u) const;
  float Pdf(Vec2 uv) const;

  int width() const { return width_; }
  int height() const { return height_; }
  // Sum of the weights given.
  double total() const { return rows_.total(); }

  std::string ToString() const;

 private:
  int width_ = 0, height_ = 0;
  DiscreteDistribution rows_;                  // marginal: a row by the sum of its weights
  std::vector<DiscreteDistribution> columns_;  // conditional: a cell within each row
};

}  // namespace farm
