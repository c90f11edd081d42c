#pragma once

// Where on the film camera samples fall: one scrambled (0,2)-sequence over the whole image,
// not an independent set in each pixel.
//
// The image is covered by a square of 2^k by 2^k pixels (2^k >= width and height). Sample j
// of pixel (x, y) is the point of the 2D Sobol sequence (sobol.h), scaled to that square,
// that falls in the pixel among the indices [j 4^k, (j + 1) 4^k): the Sobol sequence is a
// (0,2)-sequence in base 2, so each such block puts exactly one point in every pixel, and
// the index is found by solving a k-by-k linear system over GF(2) (as pbrt-v4's
// SobolSampler does). Consequences:
//
// - Samples 0..n-1 of every pixel together are the sequence's first n 4^k points: for n a
//   power of two, a (0, 2k + log2 n, 2)-net over the square. Each of its elementary
//   intervals (aligned rectangles of 1/n of a pixel's area, from 2^k pixels wide and
//   1 / (n 2^k) of a pixel tall to the reverse) holds exactly one sample: an aligned run of
//   pixels holds its exact share of samples in every band finer than a pixel, and the base
//   pass's one sample a pixel is stratified over the image. That is what a pixel filter
//   wider than a pixel integrates over (what it gains: docs/pixel-filters.md).
// - A pixel's own first n samples are still a (0, log2 n, 2)-net within the pixel, as the
//   padded per-pixel sampler's were, so the box filter loses nothing.
//
// The points are randomised per round by a nested uniform (Owen) scramble of each
// coordinate's bits below the pixel's, seeded by the round's seed and the pixel's column
// (for x) or row (for y): the same scramble for every point of a column or row, so the
// elementary intervals keep one point each, and each sample is uniform over its pixel
// (the estimate stays unbiased) and independent from round to round. The pixel bits are not
// scrambled: each pixel keeps its samples.
//
// A pure function of (image size, seed, pixel, sample index), like every random number of
// the renderer: tiles and workers draw the same samples.

#include <array>
#include <cstdint>
#include <string>

#include "math/vec3.h"

namespace farm {

class FilmSampler {
 public:
  // For an image of width x height pixels, each in [1, 2^16].
  FilmSampler(int width, int height);

  // Sample `sample` of pixel (x, y), as an offset from the pixel's corner in [0, 1)^2, in
  // the sample set keyed by seed (a round's).
  Vec2 Sample(int x, int y, std::uint32_t sample, std::uint64_t seed) const;

  // The index of that sample in the unscrambled sequence: (sample << 2k) plus the offset
  // within the block that lands in pixel (x, y).
  std::uint64_t SequenceIndex(int x, int y, std::uint32_t sample) const;

  // k: the square the sequence covers is 2^k pixels on a side.
  int resolution_bits() const { return bits_; }

  std::string ToString() const;

 private:
  // A sample's index in the sequence and its unscrambled 64-bit fractions.
  struct Point {
    std::uint64_t index, x_bits, y_bits;
  };
  Point Locate(int x, int y, std::uint32_t sample) const;

  int bits_ = 0;
  // Entry t: the index bits k..2k-1 (as a k-bit number) whose points' top k bits of y are
  // exactly bit t: the inverse of the k-by-k system that chooses a pixel's row. And what
  // those bits add to y's fraction.
  std::array<std::uint32_t, 16> row_solution_{};
  std::array<std::uint64_t, 16> row_solution_y_{};
};

// The 64-bit fixed-point fraction of the index-th point of Sobol dimension `dim` (0 or 1),
// unscrambled: sobol.h's SobolBits with 64 bits of index and of precision, so that a
// sequence over a 2^16-pixel square still has 32 bits below the pixel.
std::uint64_t SobolBits64(std::uint64_t index, int dim);

}  // namespace farm
