#include "scene/antialiasing_settings.h"

#include "contract/failure.h"
#include "contract/rules.h"
#include "renderfarm/v1/scene.pb.h"

namespace farm {

namespace pb = renderfarm::v1;
using contract::OrDefault;

AntialiasingSettings AntialiasingSettings::FromProto(const pb::Antialiasing& aa) {
  AntialiasingSettings s;
  const pb::AntialiasingMode mode = OrDefault<pb::Antialiasing>(aa.mode(), "mode");
  switch (mode) {
    case pb::ANTIALIASING_MODE_EDGES: s.mode = AntialiasingMode::kEdges; break;
    case pb::ANTIALIASING_MODE_NONE: s.mode = AntialiasingMode::kNone; break;
    case pb::ANTIALIASING_MODE_FULL: s.mode = AntialiasingMode::kFull; break;
    default:  // a mode the contract declares and this worker does not know
      throw UnsupportedError("antialiasing.mode: " + pb::AntialiasingMode_Name(mode) +
                             " is not supported by this worker");
  }
  s.edge_samples = OrDefault<pb::Antialiasing>(aa.edge_samples(), "edge_samples");
  s.edge_threshold = OrDefault<pb::Antialiasing>(aa.edge_threshold(), "edge_threshold");
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
