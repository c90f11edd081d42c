#pragma once

// The task the worker is working on, as the task thread and the heartbeat thread share it,
// and the heartbeat request made from it. Apart from worker.cpp so that what a heartbeat
// says can be tested without a coordinator. Internal to daemon/.

#include <cstdint>
#include <optional>
#include <stop_token>
#include <string>
#include <utility>

#include "renderfarm/v1/worker.pb.h"
#include "util/progress.h"

namespace farm {

// Guarded by the worker's mutex, but for `progress`, which the task's code advances from
// its own threads without taking it. Neither copyable nor movable (the counter is atomic):
// it is made in place in a std::optional, where it stays until the task is over, so a
// Progress handle on the counter stays valid for the whole task.
struct CurrentTask {
  CurrentTask(std::string task_id, std::uint64_t epoch, std::stop_source stop)
      : task_id(std::move(task_id)), epoch(epoch), stop(std::move(stop)) {}

  std::string task_id;
  std::uint64_t epoch = 0;
  std::stop_source stop;
  std::string lost;  // Why the lease was lost, if it was: the result must be dropped.
  ProgressCounter progress{0};
};

// What the next heartbeat tells the coordinator: the worker, and the lease it holds on the
// current task with the progress made so far (none once the lease is lost: it is not ours
// to extend). Call with the worker's mutex held.
renderfarm::v1::HeartbeatRequest MakeHeartbeatRequest(const std::string& worker_id,
                                                      const std::optional<CurrentTask>& task);

}  // namespace farm
