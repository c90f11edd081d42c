#include "scene/indirect_settings.h"

#include <gtest/gtest.h>

#include "contract/failure.h"
#include "renderfarm/v1/scene.pb.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

TEST(IndirectSettings, UnsetFieldsTakeTheDocumentedDefaults) {
  const IndirectSettings s = IndirectSettings::FromProto(pb::Scene());
  EXPECT_EQ(s.mode, IndirectMode::kFinalGather);
  EXPECT_EQ(s.gather_rays, 64u);
  EXPECT_EQ(s.secondary_gather_rays, 8u);
  EXPECT_EQ(s.light_samples, 16u);
  EXPECT_NE(s.ToString().find("final_gather"), std::string::npos);
}

TEST(IndirectSettings, ReadsEveryField) {
  pb::Scene scene;
  scene.mutable_indirect()->set_mode(pb::INDIRECT_MODE_PHOTON_MAP);
  scene.mutable_indirect()->set_gather_rays(100);
  scene.mutable_indirect()->set_secondary_gather_rays(3);
  scene.mutable_sampling()->set_light_samples(2);
  const IndirectSettings s = IndirectSettings::FromProto(scene);
  EXPECT_EQ(s.mode, IndirectMode::kPhotonMap);
  EXPECT_EQ(s.gather_rays, 100u);
  EXPECT_EQ(s.secondary_gather_rays, 3u);
  EXPECT_EQ(s.light_samples, 2u);
}

TEST(IndirectSettings, AModeThisWorkerDoesNotKnowIsUnsupported) {
  pb::Scene scene;
  scene.mutable_indirect()->set_mode(static_cast<pb::IndirectMode>(9));
  try {
    IndirectSettings::FromProto(scene);
    FAIL() << "accepted";
  } catch (const UnsupportedError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("indirect.mode: ", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace farm
