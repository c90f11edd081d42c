#pragma once

// Integer hashing: the only source of randomness in the renderer. Every random number is a
// pure function of integers (seed, pixel, sample index, dimension; later photon index), so
// an image does not depend on threads, tiles or workers.

#include <cstdint>

namespace farm {

// A 64-bit finaliser with full avalanche (every input bit flips each output bit with
// probability ~1/2); the constants are from Pelle Evensen's rrmxmx/"Moremur" analysis of
// MurmurHash3's fmix64, the variant pbrt-v4 also uses.
constexpr uint64_t MixBits(uint64_t v) {
  v ^= v >> 31;
  v *= 0x7fb5d329728ea185ULL;
  v ^= v >> 27;
  v *= 0x81dadef4bc2dd44dULL;
  v ^= v >> 33;
  return v;
}

// Hash of a sequence of integers. Each value is mixed in turn, so Hash(a, b) != Hash(b, a)
// and small or zero arguments still give well-spread results.
template <typename... Ts>
constexpr uint64_t Hash(Ts... values) {
  uint64_t h = 0x9e3779b97f4a7c15ULL;  // 2^64 / golden ratio: a nonzero start
  ((h = MixBits(h ^ MixBits(static_cast<uint64_t>(values) + 0x632be59bd9b4e019ULL))), ...);
  return h;
}

}  // namespace farm
