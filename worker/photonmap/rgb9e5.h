#pragma once

// Shared-exponent RGB (OpenGL EXT_texture_shared_exponent) as the snapshot stores photon
// power relative to its map's power scale (docs/photon-snapshot.md). 4 bytes instead of 12;
// 1/512 precision of a photon's brightest component. The encoder follows the spec's
// binary64 recipe step for step, so it reproduces the Go builder's bits exactly.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "math/rgb.h"

namespace farm {

inline Rgb DecodeRgb9e5(std::uint32_t v) {
  float step = std::ldexp(1.0f, int(v >> 27) - 24);
  return {float(v & 0x1ffu) * step, float((v >> 9) & 0x1ffu) * step,
          float((v >> 18) & 0x1ffu) * step};
}

// Components in [0, 1].
inline std::uint32_t EncodeRgb9e5(double r, double g, double b) {
  double maxc = std::max({r, g, b});
  int e = -16;
  if (maxc > 0) {
    int ex;
    std::frexp(maxc, &ex);  // maxc = f * 2^ex, f in [0.5, 1): floor(log2 maxc) = ex - 1
    e = std::max(e, ex - 1);
  }
  e += 16;
  double d = std::ldexp(1.0, e - 24);
  if (std::floor(maxc / d + 0.5) == 512) {
    ++e;
    d *= 2;
  }
  auto m = [d](double c) { return static_cast<std::uint32_t>(std::floor(c / d + 0.5)); };
  return m(r) | (m(g) << 9) | (m(b) << 18) | (std::uint32_t(e) << 27);
}

}  // namespace farm
