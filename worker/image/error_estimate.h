#pragma once

// How far a progressive job's image, the mean of its rounds, is estimated to be from the
// converged image, without a reference: noise and bias, with an interval
// (docs/error-estimate.md says why each part is what it is and how it was validated).
//
// The mean image's squared error at a pixel and channel has two parts:
//
//   noise  the variance of the mean. Rounds draw fresh photons and camera samples, so they
//          are independent: the spread between them, s^2 (RoundSpread), estimates the
//          variance of a round of weight 1, and s^2 / W that of the mean (W the rounds'
//          summed weight: the rounds without adaptive sampling).
//   bias   the mean of the rounds' biases. A photon estimate blurs the light over its
//          kernel, a bias whose leading term grows with the kernel's area (for a disc of
//          radius r, (r^2 / 8) times the Laplacian of the irradiance); every round renders
//          beside the beauty a companion whose photon estimates take twice the neighbours
//          over twice the area, from the same photons, camera samples and gather rays
//          (the tile's bias layer, BiasChannels: companion - beauty). By Richardson's
//          argument, twice the area has twice the bias, so their difference D is the
//          beauty's bias, and it is nearly free of the beauty's noise (what the two share
//          cancels). The mean of D over the rounds, B, estimates the mean image's bias;
//          B^2 overstates its square by B's own variance, s_D^2 / W (the spread of D
//          between rounds), which is taken off.
//
// The estimate of the image's mean squared error is the average over pixels and R, G, B of
// s^2 / W plus, if positive, that of B^2 - s_D^2 / W; its square root is the RMSE estimate.
//
// The interval. The image's actual squared error is a sum of squared errors that vary from
// one render to the next, and the estimate is itself a sum of spreads over R - 1 degrees
// of freedom each. Both are modelled as scaled chi-squares: their effective degrees of
// freedom (Satterthwaite) come from the estimated squared error summed over 2x2-pixel
// blocks, nu = (sum of blocks)^2 / (sum of squared blocks), and (R - 1) nu for the
// estimate (pixels of a block, which share photons, are taken as fully correlated, the
// cautious choice). When a few pixels hold most of the error (a light's jagged rim) nu is
// small and the interval wide. The log of actual / estimate is then the difference of two
// log chi-squares, whose mean and variance are digamma and trigamma values; the interval
// is its normal 95% range about the estimate.

#include "image/accumulation_exr.h"

namespace farm {

// The variance of a round of weight 1 from an accumulation's sums of one channel at one
// pixel: (squares - sum^2 / weight) / (rounds - 1), at least 0 (the float sums can round a
// tiny spread below it). rounds >= 2.
double RoundSpread(double sum, double squares, double weight, int rounds);

struct ErrorEstimate {
  // The estimated RMSE of the mean image's beauty (R, G, B over every pixel):
  // sqrt(noise^2 + bias^2).
  double rmse = 0;
  double noise = 0;  // the part from the spread between rounds
  double bias = 0;   // the part from the bias layer (0 when the image has none)
  // A 95% interval for the image's RMSE.
  double low = 0, high = 0;

  friend bool operator==(const ErrorEstimate&, const ErrorEstimate&) = default;
};

// The estimate of an accumulation of at least two rounds; the bias part needs the
// accumulation's bias layer (SquaredChannels). Deterministic: double sums in pixel order.
// Throws ImageError for fewer than two rounds.
ErrorEstimate EstimateError(const Accumulation& accumulation);

}  // namespace farm
