#pragma once

// The first two dimensions of the Sobol sequence, Owen-scrambled.
//
// Two dimensions are all we ever draw from one sequence: the pixel sampler (pixel_sampler.h)
// pads further dimensions pair by pair with independently scrambled and shuffled copies of
// this 2D set, as pbrt-v4's PaddedSobolSampler does. The 2D Sobol set is a (0,2)-sequence in
// base 2: any 2^k consecutive points aligned at a multiple of 2^k put exactly one point in
// each elementary interval of area 2^-k. Owen scrambling keeps that property and makes the
// points random (uniform marginals), so estimates are unbiased.

#include <cstdint>

namespace farm {

// Bits of the index-th point of Sobol dimension `dim` (0 or 1) as a 32-bit fixed-point
// fraction, unscrambled.
uint32_t SobolBits(uint32_t index, int dim);

// A nested uniform scramble of a 32-bit fraction, in the hash form of Laine and Karras
// (2011) as refined by Burley (2020) and used by pbrt-v4 (FastOwenScrambler): each output
// bit is flipped by a function of the bits above it and the seed only, which is what Owen
// scrambling requires for the elementary intervals to keep one point each.
uint32_t OwenScramble(uint32_t v, uint32_t seed);

// 32-bit fraction to a float in [0, 1).
float FractionToFloat(uint32_t v);

// The index-th point of dimension `dim`, scrambled with `seed`, in [0, 1).
inline float SobolSample(uint32_t index, int dim, uint32_t seed) {
  return FractionToFloat(OwenScramble(SobolBits(index, dim), seed));
}

// The element at position i of a pseudorandom permutation of {0, ..., n-1} chosen by seed,
// computed without storing the permutation (Kensler, "Correlated Multi-Jittered Sampling",
// 2013). Used to shuffle sample indices independently per dimension pair.
uint32_t PermutationElement(uint32_t i, uint32_t n, uint32_t seed);

}  // namespace farm
