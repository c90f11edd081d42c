#include "scene/antialiasing_settings.h"

#include <gtest/gtest.h>

#include "contract/failure.h"
#include "renderfarm/v1/scene.pb.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

TEST(AntialiasingSettings, UnsetFieldsTakeTheDocumentedDefaults) {
  const AntialiasingSettings s = AntialiasingSettings::FromProto(pb::Antialiasing());
  EXPECT_EQ(s.mode, AntialiasingMode::kEdges) << s.ToString();
  EXPECT_EQ(s.edge_samples, 32u);
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

TEST(AntialiasingSettings, AModeThisWorkerDoesNotKnowIsUnsupported) {
  pb::Antialiasing aa;
  aa.set_mode(static_cast<pb::AntialiasingMode>(42));
  EXPECT_THROW(AntialiasingSettings::FromProto(aa), UnsupportedError);
}

}  // namespace
}  // namespace farm
