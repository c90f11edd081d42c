#pragma once

// How many camera samples each pixel draws in a round under adaptive sampling: what one
// round's composite decides for the next ("samples.map" in the blob store), which the
// next round's tiles draw and its composite weighs the round's pixels by.
//
// Format: a scanline OpenEXR, ZIP, data window = display window = the whole image, one
// full-resolution UINT channel "N", the pixel's samples (>= 1). The bytes are untrusted
// when read back: DecodeSampleMap checks the size, the channel and every count.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "image/image.h"

namespace farm {

struct SampleMap {
  ImageSize size;
  std::vector<std::uint32_t> counts;  // row-major, size.width * size.height

  std::uint32_t at(int x, int y) const { return counts[std::size_t(y) * std::size_t(size.width) + std::size_t(x)]; }
};

// Deterministic bytes. Throws ImageError if counts does not fit size.
std::string EncodeSampleMap(const SampleMap& map);

// Reads a map for an image of `size` whose counts are in [1, max_samples]. Throws
// ImageError naming what is wrong.
SampleMap DecodeSampleMap(std::string_view bytes, ImageSize size, std::uint32_t max_samples);

}  // namespace farm
