#pragma once

// Adaptive sampling's allocation law: how a round's camera samples are shared out between
// pixels by their estimated error (docs/adaptive-sampling.md).
//
// A pixel whose camera samples have variance sigma^2 and which has taken N of them so far
// ends the round with squared error sigma^2 / (N + n) if it now draws n. The image's
// squared error, the mean of that over pixels, is least for a fixed total of n when every
// pixel's N + n is proportional to sigma (the Lagrange condition: sigma^2 / (N + n)^2 the
// same for all pixels): n = clamp(lambda * sigma - N, min, max), with lambda such that the
// counts add up to the budget. A pixel with 4x the variance (2x the sigma) and the same
// history thus gets 2x the samples, and one that has already taken more gets fewer.

#include <cstdint>
#include <span>
#include <vector>

namespace farm {

struct AllocationBudget {
  // Samples the round draws in all (clamped to [min, max] times the pixels).
  std::uint64_t total = 0;
  std::uint32_t min = 1;  // every pixel keeps drawing, so that its error estimate stays alive
  std::uint32_t max = 1;
};

// Each pixel's samples: integers in [min, max] that add up to the (clamped) total, from the
// continuous law above by largest remainders (ties to the lower pixel index). sigma and
// taken are per pixel (the same length; sigma >= 0, taken >= 0). A pure function of its
// arguments, in double arithmetic in pixel order: the same on every worker.
std::vector<std::uint32_t> AllocateSamples(std::span<const double> sigma, std::span<const double> taken,
                                           const AllocationBudget& budget);

}  // namespace farm
