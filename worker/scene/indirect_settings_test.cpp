#include "scene/indirect_settings.h"

#include <gtest/gtest.h>

#include "renderfarm/v1/scene.pb.h"
#include "scene/scene.h"

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

TEST(IndirectSettings, RefusesValuesOutOfRangeNamingTheField) {
  struct Case {
    void (*set)(pb::Scene&);
    const char* field;
  } cases[] = {
      {[](pb::Scene& s) { s.mutable_indirect()->set_gather_rays(4097); }, "indirect.gather_rays"},
      {[](pb::Scene& s) { s.mutable_indirect()->set_secondary_gather_rays(1u << 31); },
       "indirect.secondary_gather_rays"},
      {[](pb::Scene& s) { s.mutable_sampling()->set_light_samples(5000); }, "sampling.light_samples"},
      {[](pb::Scene& s) { s.mutable_indirect()->set_mode(static_cast<pb::IndirectMode>(9)); },
       "indirect.mode"},
  };
  for (const Case& c : cases) {
    pb::Scene scene;
    c.set(scene);
    try {
      IndirectSettings::FromProto(scene);
      ADD_FAILURE() << c.field << " accepted";
    } catch (const SceneError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(c.field, 0), 0u) << e.what();
    }
  }
}

}  // namespace
}  // namespace farm
