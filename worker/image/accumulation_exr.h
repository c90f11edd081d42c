#pragma once

// The running sums of progressive rounds, carried from one round's composite to the next
// as an OpenEXR file ("accumulation.exr" in the blob store).
//
// Format: a scanline OpenEXR, ZIP, every channel FLOAT and full resolution, data window =
// display window = the whole image, with
//   sum.<C>       for every channel C of the rendered image (sum.R, sum.direct.R, ...,
//                 sum.edge.Y): the sum over rounds of the round's value;
//   sumsq.R/G/B   the sum over rounds of the square of the round's beauty;
//   weight        the sum of the rounds' weights (> 0);
//   photonfarm.rounds  an int header attribute: how many rounds the sums hold (>= 1).
// Each round's pixel is weighed by w, its samples allocated before the round over the
// scene's samples_per_pixel: 1 without adaptive sampling, so that weight = rounds. Sums
// are of w x and w x^2, except sum.samples.Y (the samples drawn), which is of x. The mean
// image is sum / weight; the spread between rounds, the variance of a round of weight 1,
// is (sumsq - sum^2 / weight) / (rounds - 1). Floats keep 24 bits: the variance from them is good to about 1% while a
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

struct Accumulation {
  int rounds = 0;
  Image sums;     // whole image, the rendered image's channels (unprefixed names)
  Image squares;  // whole image, channels R, G, B
  Image weights;  // whole image, channel W
};

// The channel names of the file for an image with these channels: sum.<C>..., sumsq.R/G/B,
// weight.
std::vector<std::string> AccumulationChannels(const std::vector<std::string>& image_channels);

// Deterministic bytes. Throws ImageError if the two images do not cover the same whole
// image, squares is not R, G, B, weights is not W, or rounds < 1.
std::string EncodeAccumulationExr(const Accumulation& accumulation);

// Reads and validates an accumulation for an image of `size` with `image_channels` (the
// order of Accumulation::sums) that should hold `rounds` rounds. Throws ImageError naming
// what is wrong: unreadable bytes, the size, the channels, the round count, a non-finite
// or negative value.
Accumulation DecodeAccumulationExr(std::string_view bytes, ImageSize size,
                                   const std::vector<std::string>& image_channels, int rounds);

}  // namespace farm
