#pragma once

// The running sums of progressive rounds, carried from one round's composite to the next
// as an OpenEXR file ("accumulation.exr" in the blob store).
//
// Format: a scanline OpenEXR, ZIP, every channel FLOAT and full resolution, data window =
// display window = the whole image, with
//   sum.<C>       for every channel C of the rendered image (sum.R, sum.direct.R, ...,
//                 sum.edge.Y): the sum over rounds of the round's value;
//   sumsq.R/G/B   the sum over rounds of the square of the round's beauty;
//   sumsq.bias    the sum over rounds of the bias layer's squares summed over R, G, B, when
//                 the image has the layer (image.h's BiasChannels): what the error estimate
//                 needs of the spread of its estimate of the bias (image/error_estimate.h),
//                 in one channel rather than three (4 bytes a pixel, not 12);
//   weight        the sum of the rounds' weights (> 0);
//   photonfarm.rounds  an int header attribute: how many rounds the sums hold (>= 1);
//   photonfarm.deviations, photonfarm.deviationSquares  double header attributes: the sum
//                 over rounds 2.. of D_r and of D_r^2, D_r being how far round r's beauty
//                 fell from the mean of the rounds before it, summed over pixels and R, G, B
//                 (Accumulation::deviations says how it is scaled): how much a whole round's
//                 error varies from round to round, pixels that share photons together.
// Each round's pixel is weighed by w, its samples allocated before the round over the
// scene's samples_per_pixel: 1 without adaptive sampling, so that weight = rounds. Sums
// are of w x and w x^2, except sum.samples.Y (the samples drawn), which is of x. The mean
// image is sum / weight; the spread between rounds, the variance of a round of weight 1,
// is (sumsq - sum^2 / weight) / (rounds - 1), and likewise the bias difference's. Floats keep 24 bits: the variance from them is good to about 1% while a
// round's noise is above ~0.3% of the pixel's value, and the image-wide estimate averages
// over pixels; a converged image's tiny spread is therefore under-resolved, not invented.
//
// The bytes are untrusted when read back: DecodeAccumulationExr checks all of the above.

#include <string>
#include <string_view>
#include <vector>

#include "image/image.h"

namespace farm {

inline constexpr char kRoundsAttribute[] = "photonfarm.rounds";
inline constexpr char kDeviationsAttribute[] = "photonfarm.deviations";
inline constexpr char kDeviationSquaresAttribute[] = "photonfarm.deviationSquares";

struct Accumulation {
  int rounds = 0;
  Image sums;     // whole image, the rendered image's channels (unprefixed names)
  Image squares;  // whole image, SquaredChannels of the sums' channels
  Image weights;  // whole image, channel W
  // Over rounds r = 2..rounds, the sum of D_r and of D_r^2: D_r = the sum over pixels and
  // R, G, B of (x - m)^2 w W / (W + w), x the round's value of weight w, m the mean of the
  // rounds before it of weight W, so that each D_r estimates the summed variance of a
  // round of weight 1 (image/error_estimate.h reads how much it varies).
  double deviations = 0, deviation_squares = 0;
};

// The squares channel of the bias layer: its three channels' squares summed.
inline constexpr char kBiasSquares[] = "bias";

// The channels whose squares an accumulation sums, for an image with these channels: R, G,
// B, then kBiasSquares if the image has the bias layer.
std::vector<std::string> SquaredChannels(const std::vector<std::string>& image_channels);

// The channel names of the file for an image with these channels: sum.<C>..., sumsq.<C>
// of SquaredChannels, weight.
std::vector<std::string> AccumulationChannels(const std::vector<std::string>& image_channels);

// Deterministic bytes. Throws ImageError if the two images do not cover the same whole
// image, squares is not SquaredChannels(sums' channels), weights is not W, or rounds < 1.
std::string EncodeAccumulationExr(const Accumulation& accumulation);

// Reads and validates an accumulation for an image of `size` with `image_channels` (the
// order of Accumulation::sums) that should hold `rounds` rounds. Throws ImageError naming
// what is wrong: unreadable bytes, the size, the channels, the round count, a non-finite
// or negative value.
Accumulation DecodeAccumulationExr(std::string_view bytes, ImageSize size,
                                   const std::vector<std::string>& image_channels, int rounds);

}  // namespace farm
