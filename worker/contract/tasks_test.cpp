#include "contract/tasks.h"

#include <gtest/gtest.h>

namespace farm::contract {
namespace {

TEST(Phases, FollowTheDeclarationOrderOfThePhaseEnum) {
  const std::vector<PhaseEntry>& table = Phases();
  ASSERT_EQ(table.size(), 6u);
  const pb::Phase order[] = {pb::PHASE_EMIT,   pb::PHASE_BUILD,  pb::PHASE_PRECOMPUTE,
                             pb::PHASE_MERGE,  pb::PHASE_RENDER, pb::PHASE_COMPOSITE};
  for (std::size_t i = 0; i < table.size(); ++i) {
    EXPECT_EQ(table[i].phase, order[i]) << i;
    EXPECT_EQ(table[i].rank, static_cast<int>(i) + 1);
  }
  EXPECT_EQ(FindPhase(pb::PHASE_RENDER)->label, "Render tiles");
  EXPECT_EQ(FindPhase(pb::PHASE_BUILD)->executor, pb::EXECUTOR_COORDINATOR);
  EXPECT_EQ(FindPhase(pb::PHASE_COMPOSITE)->executor, pb::EXECUTOR_WORKER);
  EXPECT_EQ(FindPhase(pb::PHASE_RENDER)->outputs,
            (std::vector<pb::ArtifactKind>{pb::ARTIFACT_KIND_TILE_EXR, pb::ARTIFACT_KIND_TILE_PNG}));
  EXPECT_EQ(FindPhase(static_cast<pb::Phase>(99)), nullptr);
  EXPECT_EQ(PhaseLabel(static_cast<pb::Phase>(99)), "phase 99");
}

TEST(Phases, ATasksPhaseIsItsSpecsTaskPhase) {
  pb::Task task;
  EXPECT_EQ(PhaseOf(task), pb::PHASE_UNSPECIFIED);
  task.mutable_render_tile();
  EXPECT_EQ(PhaseOf(task), pb::PHASE_RENDER);
  task.mutable_merge_irradiance();
  EXPECT_EQ(PhaseOf(task), pb::PHASE_MERGE);
  task.mutable_emit_photons();
  EXPECT_EQ(PhaseOf(task), pb::PHASE_EMIT);
}

TEST(Artifacts, NamesComeFromArtifactInfo) {
  EXPECT_EQ(ArtifactName(pb::ARTIFACT_KIND_TILE_EXR), "tile.exr");
  EXPECT_EQ(ArtifactName(pb::ARTIFACT_KIND_PHOTON_SHARD), "photons.shard");
  EXPECT_EQ(ArtifactName(pb::ARTIFACT_KIND_ACCUMULATION_EXR), "accumulation.exr");
  EXPECT_TRUE(ArtifactOf(pb::ARTIFACT_KIND_ACCUMULATION_EXR).previous_round);
  EXPECT_FALSE(ArtifactOf(pb::ARTIFACT_KIND_IMAGE_EXR).previous_round);
  EXPECT_THROW(ArtifactOf(pb::ARTIFACT_KIND_UNSPECIFIED), std::logic_error);
}

TEST(Failures, PermanenceAndLabelsComeFromFailureInfo) {
  EXPECT_TRUE(FailureOf(pb::FAILURE_KIND_BAD_INPUT).permanent);
  EXPECT_TRUE(FailureOf(pb::FAILURE_KIND_UNSUPPORTED).permanent);
  EXPECT_FALSE(FailureOf(pb::FAILURE_KIND_RESOURCE_EXHAUSTED).permanent);
  EXPECT_FALSE(FailureOf(pb::FAILURE_KIND_TRANSIENT).permanent);
  EXPECT_EQ(FailureOf(pb::FAILURE_KIND_BAD_INPUT).label, "bad input");
  EXPECT_EQ(FailureOf(static_cast<pb::FailureKind>(42)).label, "transient failure");
}

TEST(Failures, OnlyTransientFailuresBlameTheWorker) {
  EXPECT_TRUE(FailureOf(pb::FAILURE_KIND_TRANSIENT).blames_worker);
  EXPECT_TRUE(FailureOf(pb::FAILURE_KIND_UNSPECIFIED).blames_worker);
  EXPECT_TRUE(FailureOf(static_cast<pb::FailureKind>(42)).blames_worker);
  EXPECT_FALSE(FailureOf(pb::FAILURE_KIND_RESOURCE_EXHAUSTED).blames_worker);
  EXPECT_FALSE(FailureOf(pb::FAILURE_KIND_BAD_INPUT).blames_worker);
  EXPECT_TRUE(FailureOf(pb::FAILURE_KIND_LOST_INPUT).permanent);
  EXPECT_FALSE(FailureOf(pb::FAILURE_KIND_LOST_INPUT).blames_worker);
}

}  // namespace
}  // namespace farm::contract
