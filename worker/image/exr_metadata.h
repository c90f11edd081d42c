#pragma once

// What the final EXR carries besides its pixels: OpenEXR's standard attributes where they
// exist (chromaticities, always Rec. 709 with a D65 white, the contract's linear RGB;
// worldToCamera and worldToNDC), and attributes of our own for the rest.

#include <array>
#include <optional>
#include <string>

namespace farm {

struct ExrMetadata {
  // 4x4, row-major, applied to row vectors, as OpenEXR's M44f (scene/camera.h).
  std::optional<std::array<double, 16>> world_to_camera;  // worldToCamera
  std::optional<std::array<double, 16>> world_to_ndc;     // worldToNDC
  std::optional<double> render_seconds;                   // renderTime (double, seconds)
  std::optional<int> samples_per_pixel;                   // samplesPerPixel (int)
  std::optional<int> rounds;                              // rounds (int)
  std::string software;                                   // software (string), if not empty
};

}  // namespace farm
