#pragma once

// renderfarm.v1.Antialiasing with its defaults applied (scene.proto documents them): which
// pixels the tile renderer supersamples, and with how many camera samples.

#include <cstdint>
#include <string>

namespace renderfarm::v1 {
class Antialiasing;
}

namespace farm {

inline constexpr uint32_t kDefaultEdgeSamples = 12;
inline constexpr double kDefaultEdgeThreshold = 0.1;
// The coordinator's bound (docs/limits.md), checked again here: scenes are untrusted.
inline constexpr uint32_t kMaxEdgeSamples = 1024;

enum class AntialiasingMode {
  kEdges,  // supersample pixels whose log-luminance gradient exceeds the threshold
  kNone,   // every pixel keeps samples_per_pixel
  kFull,   // every pixel gets edge_samples: the costly baseline
};

struct AntialiasingSettings {
  AntialiasingMode mode = AntialiasingMode::kEdges;
  uint32_t edge_samples = kDefaultEdgeSamples;
  // On the Sobel gradient of log-luminance, in log units per pixel (see render/edge_detect.h).
  double edge_threshold = kDefaultEdgeThreshold;

  // Throws SceneError naming the field ("antialiasing.edge_samples") for values out of range.
  static AntialiasingSettings FromProto(const renderfarm::v1::Antialiasing& aa);
  std::string ToString() const;
};

}  // namespace farm
