#pragma once

// How a linear image becomes the PNG preview's display values (docs/output.md): the
// exposure, 2^stops, multiplies the linear colour; then a tone map brings it into [0, 1],
// which the sRGB transfer function encodes (srgb_preview.h). The EXR stays linear.
//
//   clamp   values past 1 are clipped, per channel (the preview as it always was)
//   filmic  Khronos PBR Neutral (KhronosGroup/ToneMapping, 2024): colours below 0.76 pass
//           nearly unchanged (a small toe lifts blacks by at most 0.04), brighter ones are
//           compressed towards 1 with their hue kept and desaturated as they approach
//           white, so highlights roll off instead of clipping.

#include <array>

namespace farm {

enum class ToneMap { kClamp, kFilmic };

struct PreviewSettings {
  double exposure_stops = 0;
  ToneMap tone_map = ToneMap::kClamp;
};

// Exposure then the tone map of one straight (not premultiplied) linear RGB colour; the
// result lies in [0, 1] per channel. NaN and negative values count as 0.
std::array<float, 3> ToneMapColor(const PreviewSettings& settings, std::array<float, 3> rgb);

}  // namespace farm
