#include "scene/antialiasing_settings.h"

#include <cmath>

#include "renderfarm/v1/scene.pb.h"
#include "scene/scene.h"

namespace farm {

namespace pb = renderfarm::v1;

AntialiasingSettings AntialiasingSettings::FromProto(const pb::Antialiasing& aa) {
  AntialiasingSettings s;
  switch (aa.mode()) {
    case pb::ANTIALIASING_MODE_UNSPECIFIED:
    case pb::ANTIALIASING_MODE_EDGES: s.mode = AntialiasingMode::kEdges; break;
    case pb::ANTIALIASING_MODE_NONE: s.mode = AntialiasingMode::kNone; break;
    case pb::ANTIALIASING_MODE_FULL: s.mode = AntialiasingMode::kFull; break;
    default:
      throw SceneError("antialiasing.mode: unknown value " + std::to_string(aa.mode()));
  }
  if (aa.edge_samples() > kMaxEdgeSamples)
    throw SceneError("antialiasing.edge_samples: at most " + std::to_string(kMaxEdgeSamples) +
                     ", got " + std::to_string(aa.edge_samples()));
  s.edge_samples = aa.edge_samples() == 0 ? kDefaultEdgeSamples : aa.edge_samples();
  if (!std::isfinite(aa.edge_threshold()) || aa.edge_threshold() < 0)
    throw SceneError("antialiasing.edge_threshold: must be finite and >= 0 (0 selects " +
                     std::to_string(kDefaultEdgeThreshold) + ")");
  s.edge_threshold = aa.edge_threshold() == 0 ? kDefaultEdgeThreshold : aa.edge_threshold();
  return s;
}

std::string AntialiasingSettings::ToString() const {
  const char* name = mode == AntialiasingMode::kEdges  ? "edges"
                     : mode == AntialiasingMode::kNone ? "none"
                                                       : "full";
  return std::string("Antialiasing{mode=") + name + ", edge_samples=" +
         std::to_string(edge_samples) + ", edge_threshold=" + std::to_string(edge_threshold) + "}";
}

}  // namespace farm
