#include "daemon/current_task.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

#include "photon/photon_tracer.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

TEST(HeartbeatRequest, WithoutATaskNamesOnlyTheWorker) {
  const pb::HeartbeatRequest request = MakeHeartbeatRequest("w-1", std::nullopt);
  EXPECT_EQ(request.worker_id(), "w-1");
  EXPECT_EQ(request.leases_size(), 0);
}

TEST(HeartbeatRequest, HeldLeaseCarriesTheProgressSoFar) {
  std::optional<CurrentTask> task;
  task.emplace("task-9", 3, std::stop_source());
  pb::HeartbeatRequest request = MakeHeartbeatRequest("w-1", task);
  ASSERT_EQ(request.leases_size(), 1);
  EXPECT_EQ(request.leases(0).task_id(), "task-9");
  EXPECT_EQ(request.leases(0).epoch(), 3u);
  EXPECT_EQ(request.leases(0).progress(), 0u);  // Nothing done yet.

  const Progress progress(task->progress);  // What RunTask hands the task's code.
  progress.Advance(40);
  progress.Advance(2);
  request = MakeHeartbeatRequest("w-1", task);
  ASSERT_EQ(request.leases_size(), 1);
  EXPECT_EQ(request.leases(0).progress(), 42u);
}

TEST(HeartbeatRequest, ALostLeaseIsNotReported) {
  std::optional<CurrentTask> task;
  task.emplace("task-9", 3, std::stop_source());
  Progress(task->progress).Advance(5);
  task->lost = "revoked by the coordinator";
  EXPECT_EQ(MakeHeartbeatRequest("w-1", task).leases_size(), 0);
}

// A lamp over a grey floor: every global path bounces, so tracing takes real time.
pb::Scene LampOverFloor() {
  pb::Scene s = MakeScene(4, 4, {0, -10, 5}, {0, 0, 0}, {0, 0, 1}, 40);
  AddLambert(s, "grey", Rgb(0.5f));
  AddEmissive(s, "lamp", Rgb(10));
  AddQuad(s, "grey", {-20, -20, 0}, {40, 0, 0}, {0, 40, 0});
  AddQuad(s, "lamp", {-1, -1, 4}, {0, 2, 0}, {2, 0, 0});  // Faces down.
  return s;
}

// The whole path as the worker runs it: the task's code advances the counter from TBB
// threads while heartbeats are built from it under the lock on another thread. Each
// heartbeat's progress is at least the last one's, and the last says every path is traced.
TEST(HeartbeatRequest, ProgressOfARunningPhotonTraceOnlyGrowsAndEndsAtThePathCount) {
  const Scene scene = Scene::Build(LampOverFloor(), NoBlobs());
  constexpr std::uint64_t kPaths = 200'000;
  std::mutex mu;
  std::optional<CurrentTask> task;
  Progress progress;
  {
    std::lock_guard lock(mu);
    task.emplace("emit-1", 1, std::stop_source());
    progress = Progress(task->progress);
  }
  std::atomic<bool> done{false};
  std::jthread worker([&] {
    TracePhotonShard(scene, {PhotonMapKind::kGlobal, 0, kPaths, kPaths}, {}, progress);
    done = true;
  });
  std::vector<std::uint64_t> reported;
  while (!done.load()) {
    std::lock_guard lock(mu);
    const pb::HeartbeatRequest request = MakeHeartbeatRequest("w-1", task);
    ASSERT_EQ(request.leases_size(), 1);
    const std::uint64_t now = request.leases(0).progress();
    if (reported.empty() || now != reported.back()) reported.push_back(now);
  }
  worker.join();
  EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
  std::lock_guard lock(mu);
  EXPECT_EQ(MakeHeartbeatRequest("w-1", task).leases(0).progress(), kPaths);
}

}  // namespace
}  // namespace farm
