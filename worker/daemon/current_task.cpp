#include "daemon/current_task.h"

namespace farm {

renderfarm::v1::HeartbeatRequest MakeHeartbeatRequest(const std::string& worker_id,
                                                      const std::optional<CurrentTask>& task) {
  renderfarm::v1::HeartbeatRequest request;
  request.set_worker_id(worker_id);
  if (task && task->lost.empty()) {
    renderfarm::v1::HeldLease* held = request.add_leases();
    held->set_task_id(task->task_id);
    held->set_epoch(task->epoch);
    // Relaxed, as it is advanced: the coordinator only needs a value that never goes back.
    held->set_progress(task->progress.load(std::memory_order_relaxed));
  }
  return request;
}

}  // namespace farm
