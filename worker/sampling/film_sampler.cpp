#include "sampling/film_sampler.h"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <utility>

#include "sampling/hash.h"
#include "sampling/sobol.h"

namespace farm {
namespace {

constexpr std::uint64_t ReverseBits64(std::uint64_t v) {
  v = (v << 32) | (v >> 32);
  v = ((v & 0x0000ffff0000ffffULL) << 16) | ((v & 0xffff0000ffff0000ULL) >> 16);
  v = ((v & 0x00ff00ff00ff00ffULL) << 8) | ((v & 0xff00ff00ff00ff00ULL) >> 8);
  v = ((v & 0x0f0f0f0f0f0f0f0fULL) << 4) | ((v & 0xf0f0f0f0f0f0f0f0ULL) >> 4);
  v = ((v & 0x3333333333333333ULL) << 2) | ((v & 0xccccccccccccccccULL) >> 2);
  v = ((v & 0x5555555555555555ULL) << 1) | ((v & 0xaaaaaaaaaaaaaaaaULL) >> 1);
  return v;
}

// Sobol dimension 1's direction numbers at 64 bits (sobol.cpp's kDimension1 are their top
// halves): v_i = v_{i-1} ^ (v_{i-1} >> 1) from 1/2.
constexpr std::array<std::uint64_t, 64> MakeDimension1() {
  std::array<std::uint64_t, 64> v{};
  v[0] = 1ULL << 63;
  for (int i = 1; i < 64; ++i) v[i] = v[i - 1] ^ (v[i - 1] >> 1);
  return v;
}

constexpr std::array<std::uint64_t, 64> kDimension1 = MakeDimension1();

// The top `bits` bits of a 64-bit fraction (0 for none).
constexpr std::uint64_t Top(std::uint64_t fraction, int bits) { return bits == 0 ? 0 : fraction >> (64 - bits); }

// The 32 bits of a 64-bit fraction below its top `bits`: the position within a pixel.
constexpr std::uint32_t BelowTop(std::uint64_t fraction, int bits) {
  return static_cast<std::uint32_t>((fraction << bits) >> 32);
}

int BitsFor(int width, int height) {
  if (width < 1 || height < 1 || width > (1 << 16) || height > (1 << 16))
    throw std::invalid_argument("FilmSampler: the image must be 1 to 65536 pixels a side, got " +
                                std::to_string(width) + "x" + std::to_string(height));
  return std::bit_width(static_cast<unsigned>(std::max(width, height) - 1));
}

}  // namespace

std::uint64_t SobolBits64(std::uint64_t index, int dim) {
  if (dim == 0) return ReverseBits64(index);
  std::uint64_t v = 0;
  for (; index != 0; index &= index - 1) v ^= kDimension1[std::countr_zero(index)];
  return v;
}

FilmSampler::FilmSampler(int width, int height) : bits_(BitsFor(width, height)) {
  const int k = bits_;
  // Index bit k + t moves y's top k bits by column[t]. Gauss-Jordan elimination over GF(2)
  // on rows (column value, the combination of index bits that gives it) turns the columns
  // into the unit vectors, recording for each which index bits produce it. The columns are
  // independent because the 2D Sobol sequence is a (0,2)-sequence.
  std::array<std::pair<std::uint32_t, std::uint32_t>, 16> rows{};
  for (int t = 0; t < k; ++t) rows[t] = {static_cast<std::uint32_t>(Top(kDimension1[k + t], k)), 1u << t};
  for (int bit = 0; bit < k; ++bit) {
    int pivot = bit;
    while (pivot < k && !((rows[pivot].first >> bit) & 1)) ++pivot;
    if (pivot == k) throw std::logic_error("FilmSampler: the Sobol row system is singular");
    std::swap(rows[bit], rows[pivot]);
    for (int r = 0; r < k; ++r)
      if (r != bit && ((rows[r].first >> bit) & 1)) {
        rows[r].first ^= rows[bit].first;
        rows[r].second ^= rows[bit].second;
      }
  }
  for (int t = 0; t < k; ++t) {
    row_solution_[t] = rows[t].second;
    row_solution_y_[t] = SobolBits64(static_cast<std::uint64_t>(rows[t].second) << k, 1);
  }
}

FilmSampler::Point FilmSampler::Locate(int x, int y, std::uint32_t sample) const {
  const int k = bits_;
  // x's top k bits are the index's low k bits reversed (dimension 0 is the bit reversal).
  const std::uint64_t low = k == 0 ? 0 : ReverseBits64(static_cast<std::uint64_t>(x)) >> (64 - k);
  const std::uint64_t high = static_cast<std::uint64_t>(sample) << (2 * k);
  // The middle k bits must move y's top bits from those of low + high to the row y; y's
  // bits are linear in the index's, so the middle's add to those of low + high.
  std::uint64_t y_bits = SobolBits64(low | high, 1);
  const std::uint64_t wanted = static_cast<std::uint64_t>(y) ^ Top(y_bits, k);
  std::uint64_t middle = 0;
  for (int t = 0; t < k; ++t)
    if ((wanted >> t) & 1) {
      middle ^= row_solution_[t];
      y_bits ^= row_solution_y_[t];
    }
  const std::uint64_t index = high | (middle << k) | low;
  return {index, ReverseBits64(index), y_bits};
}

std::uint64_t FilmSampler::SequenceIndex(int x, int y, std::uint32_t sample) const {
  return Locate(x, y, sample).index;
}

Vec2 FilmSampler::Sample(int x, int y, std::uint32_t sample, std::uint64_t seed) const {
  const Point point = Locate(x, y, sample);
  // One scramble per column for x and per row for y: nested in the pixel bits above, so
  // points sharing a column (row) keep their stratification in x (y) across pixels.
  // The tag keeps these seeds apart from PixelSampler's Hash(seed, pixel, dimension).
  constexpr std::uint64_t kFilmTag = 0x66696c6d;  // "film"
  const auto scramble = [seed](std::uint32_t bits, int axis, int line) {
    return FractionToFloat(OwenScramble(bits, static_cast<std::uint32_t>(Hash(kFilmTag, seed, axis, line))));
  };
  return {scramble(BelowTop(point.x_bits, bits_), 0, x), scramble(BelowTop(point.y_bits, bits_), 1, y)};
}

std::string FilmSampler::ToString() const {
  return "FilmSampler{square=2^" + std::to_string(bits_) + "}";
}

}  // namespace farm
