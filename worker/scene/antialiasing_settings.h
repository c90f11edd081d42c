#pragma once

// renderfarm.v1.Antialiasing with its defaults applied (the default_value of each field's
// rule in scene.proto, read through worker/contract): which pixels the tile renderer
// supersamples, and with how many camera samples.

#include <cstdint>
#include <string>

namespace renderfarm::v1 {
class Antialiasing;
}

namespace farm {

enum class AntialiasingMode {
  kEdges,  // supersample pixels whose log-luminance gradient exceeds the threshold
  kNone,   // every pixel keeps samples_per_pixel
  kFull,   // every pixel gets edge_samples: the costly baseline
};

struct AntialiasingSettings {
  AntialiasingMode mode = AntialiasingMode::kEdges;
  uint32_t edge_samples = 0;
  // On the Sobel gradient of log-luminance, in log units per pixel (see render/edge_detect.h).
  double edge_threshold = 0;

  // Reads `aa`, which has passed contract::CheckRules; a field that is 0 takes its default.
  static AntialiasingSettings FromProto(const renderfarm::v1::Antialiasing& aa);
  std::string ToString() const;
};

}  // namespace farm
