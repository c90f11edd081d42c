#pragma once

// An environment map's file (OpenEXR, Radiance HDR, PNG or JPEG, told apart by its first
// bytes) decoded into linear RGB through OpenImageIO, from memory.

#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "scene/environment.h"

namespace farm {

// How stored values become linear: kByFormat follows the contract's rule for a colour
// (8- and 16-bit integer files hold sRGB, float files linear values).
enum class EnvironmentEncoding { kByFormat, kSrgb, kLinear };

class EnvironmentImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws EnvironmentImageError saying what is wrong: not an image of a known kind, larger
// than max_pixels, unreadable, or with a pixel that is not finite (negative values count as 0). One channel is grey; a second (alpha) or fourth channel
// is ignored.
EnvironmentImage DecodeEnvironmentImage(std::string_view bytes, EnvironmentEncoding encoding,
                                        std::uint64_t max_pixels);

}  // namespace farm
