#include "sampling/sobol.h"

#include <array>
#include <bit>

#include "math/math.h"

namespace farm {
namespace {

constexpr uint32_t ReverseBits32(uint32_t v) {
  v = (v << 16) | (v >> 16);
  v = ((v & 0x00ff00ffu) << 8) | ((v & 0xff00ff00u) >> 8);
  v = ((v & 0x0f0f0f0fu) << 4) | ((v & 0xf0f0f0f0u) >> 4);
  v = ((v & 0x33333333u) << 2) | ((v & 0xccccccccu) >> 2);
  v = ((v & 0x55555555u) << 1) | ((v & 0xaaaaaaaau) >> 1);
  return v;
}

// Direction numbers of Sobol dimension 1 (primitive polynomial x + 1, m_1 = 1): column i of
// the generator matrix is v_i = v_{i-1} ^ (v_{i-1} >> 1), starting from 1/2. Dimension 0
// is the van der Corput sequence, whose matrix is the bit reversal.
constexpr std::array<uint32_t, 32> MakeDimension1() {
  std::array<uint32_t, 32> v{};
  v[0] = 0x80000000u;
  for (int i = 1; i < 32; ++i) v[i] = v[i - 1] ^ (v[i - 1] >> 1);
  return v;
}

constexpr std::array<uint32_t, 32> kDimension1 = MakeDimension1();

}  // namespace

uint32_t SobolBits(uint32_t index, int dim) {
  if (dim == 0) return ReverseBits32(index);
  uint32_t v = 0;
  for (int i = 0; index != 0; index >>= 1, ++i)
    if (index & 1) v ^= kDimension1[i];
  return v;
}

uint32_t OwenScramble(uint32_t v, uint32_t seed) {
  // In bit-reversed order, "bits above" become "bits below", and multiplication by an even
  // constant, addition and multiplication by an odd constant only carry upwards.
  v = ReverseBits32(v);
  v ^= v * 0x3d20adeau;
  v += seed;
  v *= (seed >> 16) | 1u;
  v ^= v * 0x05526c56u;
  v ^= v * 0x53a22864u;
  return ReverseBits32(v);
}

float FractionToFloat(uint32_t v) {
  // Rounding to float can carry 0xffffffff up to 1.0; clamp to keep the interval half-open.
  const float f = static_cast<float>(v) * 0x1p-32f;
  return f < kOneMinusEpsilon ? f : kOneMinusEpsilon;
}

uint32_t PermutationElement(uint32_t i, uint32_t n, uint32_t seed) {
  // A bijection on [0, 2^k) with 2^k >= n; values >= n are walked on ("cycle walking")
  // until they land inside [0, n), which keeps it a permutation of [0, n).
  uint32_t w = n - 1;
  w |= w >> 1;
  w |= w >> 2;
  w |= w >> 4;
  w |= w >> 8;
  w |= w >> 16;
  const uint32_t p = seed;
  do {
    i ^= p;
    i *= 0xe170893du;
    i ^= p >> 16;
    i ^= (i & w) >> 4;
    i ^= p >> 8;
    i *= 0x0929eb3fu;
    i ^= p >> 23;
    i ^= (i & w) >> 1;
    i *= 1 | p >> 27;
    i *= 0x6935fa69u;
    i ^= (i & w) >> 11;
    i *= 0x74dcb303u;
    i ^= (i & w) >> 2;
    i *= 0x9e501cc3u;
    i ^= (i & w) >> 2;
    i *= 0xc860a3dfu;
    i &= w;
    i ^= i >> 5;
  } while (i >= n);
  return (i + p) % n;
}

}  // namespace farm
