#include "scene/antialiasing_settings.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "renderfarm/v1/scene.pb.h"
#include "scene/scene.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

TEST(AntialiasingSettings, UnsetFieldsTakeTheDocumentedDefaults) {
  const AntialiasingSettings s = AntialiasingSettings::FromProto(pb::Antialiasing());
  EXPECT_EQ(s.mode, AntialiasingMode::kEdges) << s.ToString();
  EXPECT_EQ(s.edge_samples, 12u);
  EXPECT_EQ(s.edge_threshold, 0.1);
}

TEST(AntialiasingSettings, SetFieldsAreKept) {
  pb::Antialiasing aa;
  aa.set_mode(pb::ANTIALIASING_MODE_FULL);
  aa.set_edge_samples(64);
  aa.set_edge_threshold(0.5);
  const AntialiasingSettings s = AntialiasingSettings::FromProto(aa);
  EXPECT_EQ(s.mode, AntialiasingMode::kFull);
  EXPECT_EQ(s.edge_samples, 64u);
  EXPECT_EQ(s.edge_threshold, 0.5);
  aa.set_mode(pb::ANTIALIASING_MODE_NONE);
  EXPECT_EQ(AntialiasingSettings::FromProto(aa).mode, AntialiasingMode::kNone);
}

void ExpectRefused(const pb::Antialiasing& aa, const std::string& field) {
  try {
    AntialiasingSettings::FromProto(aa);
    ADD_FAILURE() << "accepted " << aa.ShortDebugString();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(AntialiasingSettings, OutOfRangeValuesAreRefusedNamingTheField) {
  pb::Antialiasing aa;
  aa.set_edge_samples(kMaxEdgeSamples + 1);
  ExpectRefused(aa, "antialiasing.edge_samples");
  aa = {};
  aa.set_edge_threshold(-0.1);
  ExpectRefused(aa, "antialiasing.edge_threshold");
  aa.set_edge_threshold(std::numeric_limits<double>::quiet_NaN());
  ExpectRefused(aa, "antialiasing.edge_threshold");
  aa = {};
  aa.set_mode(static_cast<pb::AntialiasingMode>(42));
  ExpectRefused(aa, "antialiasing.mode");
}

}  // namespace
}  // namespace farm
