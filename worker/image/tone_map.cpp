#include "image/tone_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace farm {
namespace {

// Khronos PBR Neutral: the toe subtracts an offset that is quadratic in the smallest
// channel below 0.08 (and 0.04 above), then a peak above start is compressed on a
// hyperbola that meets the identity with slope 1 at start and tends to 1, the colour
// scaled with it and mixed towards white by how much the peak was compressed.
std::array<float, 3> PbrNeutral(std::array<float, 3> c) {
  constexpr float kStart = 0.8f - 0.04f, kDesaturation = 0.15f;
  const float x = std::min({c[0], c[1], c[2]});
  const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
  for (float& v : c) v -= offset;
  const float peak = std::max({c[0], c[1], c[2]});
  if (peak < kStart) return c;
  const float d = 1 - kStart;
  const float new_peak = 1 - d * d / (peak + d - kStart);
  const float g = 1 - 1 / (kDesaturation * (peak - new_peak) + 1);
  for (float& v : c) v = v * (new_peak / peak) * (1 - g) + new_peak * g;
  return c;
}

}  // namespace

std::array<float, 3> ToneMapColor(const PreviewSettings& settings, std::array<float, 3> rgb) {
  const float scale = static_cast<float>(std::exp2(settings.exposure_stops));
  // NaN -> 0; infinity -> the largest float, which the filmic curve takes to 1.
  for (float& v : rgb) v = v > 0 ? std::min(v * scale, std::numeric_limits<float>::max()) : 0.0f;
  if (settings.tone_map == ToneMap::kFilmic) rgb = PbrNeutral(rgb);
  for (float& v : rgb) v = std::clamp(v, 0.0f, 1.0f);
  return rgb;
}

}  // namespace farm
