#include "daemon/worker.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <stop_token>
#include <thread>
#include <utility>

#include "contract/failure.h"
#include "contract/go_text.h"
#include "contract/rules.h"
#include "contract/tasks.h"
#include "daemon/blob_cache.h"
#include "daemon/blob_client.h"
#include "daemon/channel.h"
#include "daemon/current_task.h"
#include "daemon/log.h"
#include "daemon/peak_memory.h"
#include "daemon/retry.h"
#include "daemon/task_executor.h"
#include "daemon/task_log.h"
#include "daemon/task_log_upload.h"
#include "daemon/version.h"
#include "renderfarm/v1/worker.grpc.pb.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;
using std::chrono::seconds;

// How long one LeaseTask call waits for work (the contract allows up to 30 s).
constexpr seconds kLeaseWait{10};
// Deadline of short RPCs (everything but LeaseTask and blob transfers).
constexpr seconds kCallDeadline{30};
// How long shutdown keeps trying to release a lease or say goodbye.
constexpr seconds kGoodbyeGiveUp{5};
// The metadata that carries the registration's secret on every call about this worker
// (RegisterWorkerResponse.worker_secret in worker.proto; contract/rules.WorkerSecretMetadata
// in Go).
constexpr char kWorkerSecretMetadata[] = "farm-worker-secret";

// The pause before leasing again after a failure that does not blame the worker (a full
// disk or cache), doubling while they repeat: another worker takes the task meanwhile,
// and this one does not fail task after task the same way.
constexpr Millis kSpareFirstPause{5000};
constexpr Millis kSpareLongestPause{60000};

std::string HostName() {
  char name[256] = "";
  if (gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "unknown-host";
  return name;
}

Millis ToMillis(const google::protobuf::Duration& d, Millis fallback) {
  const auto ms = Millis(d.seconds() * 1000 + d.nanos() / 1'000'000);
  return ms.count() > 0 ? ms : fallback;
}

// An answer that no retry will change: this worker's token is missing, unknown or not a
// worker token.
bool IsAuthError(const grpc::Status& status) {
  return status.error_code() == grpc::StatusCode::UNAUTHENTICATED ||
         status.error_code() == grpc::StatusCode::PERMISSION_DENIED;
}

std::string AuthHint(const grpc::Status& status) {
  return IsAuthError(status) ? "give the coordinator's worker token with --token or $FARM_WORKER_TOKEN" : "";
}

void SetDeadline(grpc::ClientContext& ctx, std::chrono::system_clock::duration d) {
  ctx.set_deadline(std::chrono::system_clock::now() + d);
}

// A duration in seconds, to the millisecond.
double Seconds(std::chrono::steady_clock::duration d) {
  return static_cast<double>(std::chrono::duration_cast<std::chrono::milliseconds>(d).count()) / 1000;
}

// FailTaskRequest.error: the reason, cut to what the coordinator keeps.
std::string ReportedError(const std::string& error) {
  constexpr std::string_view kCutMark = "…";  // what Truncate appends
  return contract::Truncate(error, contract::RpcLimits().max_error_bytes() - kCutMark.size());
}

// What names a task in its lines, with the coordinator's field names.
std::vector<LogAttr> TaskAttrs(const pb::Task& task, const pb::Lease& lease, const std::string& worker) {
  return {{"job", task.job_id()},        {"task", lease.task_id()}, {"attempt", task.attempts()},
          {"epoch", lease.epoch()},       {"worker", worker},         {"spec", DescribeTask(task)}};
}

}  // namespace

class Worker::Impl {
 public:
  Impl(const WorkerOptions& options, unsigned cores)
      : coordinator_(JoinedAddresses(options)),
        hostname_(options.name.empty() ? HostName() : options.name),
        cores_(cores),
        cache_(options.cache_dir, options.cache_max_bytes),
        channel_(MakeCoordinatorChannel(options)),
        stub_(pb::WorkerService::NewStub(channel_)),
        blobs_(channel_, &cache_, options.download_range_bytes),
        executor_(blobs_, TextureSystemOptions{static_cast<std::size_t>(options.texture_cache_mib),
                                               options.cache_dir / "textures"}) {}

  int Run();

  void Drain() {
    if (!drain_.stop_requested()) Log(LogLevel::kInfo, "shutting down after the current task");
    drain_.request_stop();
  }

  void Abort() {
    if (!abort_.stop_requested()) Log(LogLevel::kWarn, "abandoning the current task and shutting down");
    drain_.request_stop();
    abort_.request_stop();  // Stops the current task through the callback in RunTask.
  }

 private:
  bool Register();
  void HeartbeatLoop(std::stop_token stop);
  void LoseLease(const std::string& reason);  // Needs mu_ held.
  grpc::Status LeaseOnce(pb::LeaseTaskResponse& leased);
  void RunTask(const pb::LeaseTaskResponse& leased);
  // Each returns what went wrong with the report, or "" once the coordinator has it.
  std::string ReportComplete(const pb::Lease& lease, const TaskResult& result, const std::optional<pb::Artifact>& log);
  std::string ReportFailure(const pb::Lease& lease, const std::string& error, pb::FailureKind kind,
                            const std::optional<pb::Artifact>& log);
  // Ends the task's log and uploads it as "task.log" (UploadTaskLog): nullopt if the
  // upload failed, which is logged and never fails the task.
  std::optional<pb::Artifact> UploadLog(std::optional<TaskLog>& log, const pb::Lease& lease) {
    return UploadTaskLog(log, lease.task_id(), [&](std::string_view bytes) { return blobs_.Upload(bytes, abort_.get_token()); });
  }
  // Sends the report that call makes (on a context given its deadline) until the
  // coordinator acknowledges it, as completions and failures are idempotent there, or the
  // worker aborts (the lease is then released). Returns "" once acknowledged, else what
  // became of it; lost says what a lost lease means for this report.
  template <typename Call>
  std::string Report(const pb::Lease& lease, const std::string& method, const std::string& lost, Call call);
  // Names lease in request, a report on it.
  template <typename Request>
  void NameLease(Request& request, const pb::Lease& lease) {
    request.set_worker_id(WorkerId());
    request.set_task_id(lease.task_id());
    request.set_epoch(lease.epoch());
  }
  void Release(const pb::Lease& lease);
  void Unregister();
  std::string WorkerId() {
    std::lock_guard lock(mu_);
    return worker_id_;
  }
  // Makes ctx carry the registration's secret, as every call about this worker must. The
  // id and the secret change together only in Register, on the thread that makes the
  // calls other than heartbeats (which read both at once).
  void Identify(grpc::ClientContext& ctx) {
    std::lock_guard lock(mu_);
    ctx.AddMetadata(kWorkerSecretMetadata, worker_secret_);
  }

  const std::string coordinator_;
  const std::string hostname_;
  const unsigned cores_;
  BlobCache cache_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<pb::WorkerService::Stub> stub_;
  BlobClient blobs_;
  TaskExecutor executor_;

  Backoff spare_pause_{kSpareFirstPause, kSpareLongestPause};
  bool pause_before_lease_ = false;  // The last task failed without blaming this worker.

  std::stop_source drain_;  // No more leasing.
  std::stop_source abort_;  // Abandon the current task too.
  std::atomic<bool> reregister_{false};

  std::mutex mu_;  // Guards what follows.
  std::string worker_id_;
  std::string worker_secret_;
  Millis heartbeat_interval_{5000};
  std::optional<CurrentTask> current_;  // Shared with the heartbeat thread.
};


bool Worker::Impl::Register() {
  pb::RegisterWorkerRequest request;
  request.set_hostname(hostname_);
  request.set_cores(cores_);
  request.set_version(kWorkerVersion);
  pb::RegisterWorkerResponse response;
  Log(LogLevel::kInfo, "registering", {{"coordinator", coordinator_}, {"hostname", hostname_}});
  // A worker may start before its coordinator: wait for it as long as it takes. Each
  // attempt fails fast (no wait_for_ready) so that a wrong or dead address is said at
  // once and then every few seconds, instead of after a call deadline of silence.
  const grpc::Status status = RetryTransient(
      "RegisterWorker with " + coordinator_, drain_.get_token(), seconds(0),
      [&] {
        grpc::ClientContext ctx;
        SetDeadline(ctx, kCallDeadline);
        std::stop_callback cancel(drain_.get_token(), [&ctx] { ctx.TryCancel(); });
        return stub_->RegisterWorker(&ctx, request, &response);
      },
      [&](const grpc::Status& failed, Millis delay) {
        Log(LogLevel::kWarn, "cannot reach coordinator at " + coordinator_ + ": " + failed.error_message() + "; retrying",
            {{"code", static_cast<int>(failed.error_code())}, {"retry_ms", delay.count()}});
      });
  if (!status.ok()) {
    if (!drain_.stop_requested()) {
      Log(LogLevel::kError, "coordinator refused registration",
          {{"coordinator", coordinator_}, {"err", status.error_message()}, {"hint", AuthHint(status)}});
    }
    return false;
  }
  std::lock_guard lock(mu_);
  worker_id_ = response.worker_id();
  worker_secret_ = response.worker_secret();
  heartbeat_interval_ = std::max(Millis(100), ToMillis(response.heartbeat_interval(), Millis(5000)));
  Log(LogLevel::kInfo, "registered",
      {{"coordinator", coordinator_},
       {"worker", worker_id_},
       {"hostname", hostname_},
       {"cores", cores_},
       {"heartbeat_ms", heartbeat_interval_.count()},
       {"lease_ms", ToMillis(response.lease_duration(), Millis(0)).count()}});
  return true;
}

void Worker::Impl::LoseLease(const std::string& reason) {
  if (!current_ || !current_->lost.empty()) return;
  current_->lost = reason;
  current_->stop.request_stop();
}

void Worker::Impl::HeartbeatLoop(std::stop_token stop) {
  bool heartbeat_failing = false;
  while (true) {
    Millis interval;
    pb::HeartbeatRequest request;
    std::string secret;
    {
      std::lock_guard lock(mu_);
      interval = heartbeat_interval_;
    }
    if (!SleepUnlessStopped(interval, stop)) return;
    {
      std::lock_guard lock(mu_);
      if (worker_id_.empty()) continue;
      request = MakeHeartbeatRequest(worker_id_, current_);
      secret = worker_secret_;
    }
    pb::HeartbeatResponse response;
    grpc::ClientContext ctx;
    ctx.AddMetadata(kWorkerSecretMetadata, secret);
    SetDeadline(ctx, std::max<std::chrono::system_clock::duration>(interval, seconds(5)));
    std::stop_callback cancel(stop, [&ctx] { ctx.TryCancel(); });
    const grpc::Status status = stub_->Heartbeat(&ctx, request, &response);
    std::lock_guard lock(mu_);
    if (status.ok()) {
      for (const pb::HeldLease& revoked : response.revoked()) {
        if (current_ && revoked.task_id() == current_->task_id &&
            revoked.epoch() == current_->epoch) {
          LoseLease("revoked by the coordinator");
        }
      }
    } else if (status.error_code() == grpc::StatusCode::NOT_FOUND) {
      // The coordinator forgot us (restarted without state, or we were presumed dead):
      // whatever we hold is no longer ours. Register again before the next lease.
      Log(LogLevel::kWarn, "coordinator does not know this worker; registering again", {{"worker", worker_id_}});
      LoseLease("the coordinator no longer knows this worker");
      reregister_ = true;
    } else if (!stop.stop_requested() && !heartbeat_failing) {
      // Once per outage, not every interval.
      Log(LogLevel::kWarn, "heartbeat failed; will keep trying", {{"worker", worker_id_}, {"err", status.error_message()}});
    }
    if (status.ok() && heartbeat_failing) Log(LogLevel::kInfo, "heartbeat works again", {{"worker", worker_id_}});
    heartbeat_failing = !status.ok();
  }
}

grpc::Status Worker::Impl::LeaseOnce(pb::LeaseTaskResponse& leased) {
  pb::LeaseTaskRequest request;
  request.set_worker_id(WorkerId());
  request.mutable_wait_timeout()->set_seconds(kLeaseWait.count());
  grpc::ClientContext ctx;
  Identify(ctx);
  SetDeadline(ctx, kLeaseWait + kCallDeadline);
  // While the coordinator is away, wait for the connection instead of failing at once:
  // the lease is asked for the moment it is back.
  ctx.set_wait_for_ready(true);
  // The first signal ends the long poll at once instead of up to kLeaseWait later.
  std::stop_callback cancel(drain_.get_token(), [&ctx] { ctx.TryCancel(); });
  return stub_->LeaseTask(&ctx, request, &leased);
}

int Worker::Impl::Run() {
  if (!Register()) return drain_.stop_requested() ? 0 : 1;
  int exit_code = 0;
  {
    std::jthread heartbeat([this](std::stop_token stop) { HeartbeatLoop(stop); });
    Backoff backoff;
    bool lease_failing = false;
    while (!drain_.stop_requested()) {
      if (reregister_.exchange(false) && !Register()) {
        exit_code = drain_.stop_requested() ? 0 : 1;
        break;
      }
      if (std::exchange(pause_before_lease_, false)) {
        const Millis pause = spare_pause_.Next();
        Log(LogLevel::kInfo, "pausing before the next lease", {{"ms", pause.count()}, {"why", "the last task ran out of a resource here"}});
        if (!SleepUnlessStopped(pause, drain_.get_token())) break;
      }
      pb::LeaseTaskResponse leased;
      const grpc::Status status = LeaseOnce(leased);
      if (status.ok() && leased.has_lease() && drain_.stop_requested()) {
        Release(leased.lease());  // Granted as we were told to stop: hand it straight back.
        break;
      }
      if (!status.ok()) {
        if (drain_.stop_requested()) break;
        if (status.error_code() == grpc::StatusCode::NOT_FOUND) {
          reregister_ = true;
        } else if (IsAuthError(status)) {
          Log(LogLevel::kError, "coordinator refused LeaseTask",
              {{"coordinator", coordinator_}, {"err", status.error_message()}, {"hint", AuthHint(status)}});
          exit_code = 1;
          break;
        } else {
          if (!lease_failing) {  // Once per outage, not every attempt.
            Log(LogLevel::kWarn, "LeaseTask failed; will keep trying",
                {{"err", status.error_message()}, {"code", static_cast<int>(status.error_code())}});
          }
          lease_failing = true;
          SleepUnlessStopped(backoff.Next(), drain_.get_token());
        }
        continue;
      }
      if (lease_failing) Log(LogLevel::kInfo, "LeaseTask works again");
      lease_failing = false;
      backoff.Reset();
      if (leased.has_lease()) RunTask(leased);
    }
  }  // Joins the heartbeat thread: no lease is held any more.
  Unregister();
  return exit_code;
}

void Worker::Impl::RunTask(const pb::LeaseTaskResponse& leased) {
  const pb::Lease& lease = leased.lease();
  const pb::Task& task = leased.task();
  const auto start = std::chrono::steady_clock::now();
  // Every line the worker logs from here to the report, uploaded with it (UploadLog).
  std::optional<TaskLog> task_log(std::in_place, contract::RpcLimits().max_task_log_bytes());
  Log(LogLevel::kInfo, "task started", TaskAttrs(task, lease, WorkerId()));
  const PeakMemory memory = PeakMemory::Start();
  std::stop_source task_stop;
  Progress progress;
  {
    std::lock_guard lock(mu_);
    current_.emplace(lease.task_id(), lease.epoch(), task_stop);
    // The counter stays put until current_.reset() below, after the task's code is done.
    progress = Progress(current_->progress);
  }
  std::stop_callback on_abort(abort_.get_token(), [task_stop]() mutable {
    task_stop.request_stop();
  });

  TaskResult result;
  std::optional<std::string> error;  // set when the task failed
  pb::FailureKind kind = pb::FAILURE_KIND_UNSPECIFIED;
  try {
    result = executor_.Execute(leased, task_stop.get_token(), progress);
  } catch (const TaskCancelled&) {
  } catch (const std::exception& e) {
    error = e.what();
    kind = FailureKindOf(e);
  } catch (...) {
    error = "an exception that is not a std::exception";
    kind = pb::FAILURE_KIND_TRANSIENT;
  }

  std::string lost;
  {
    std::lock_guard lock(mu_);
    lost = current_->lost;
  }
  // One line per task's outcome, with the coordinator's names for what identifies it, and
  // the peak resident memory of the worker while it ran.
  const auto log = [&](LogLevel level, std::string_view msg, const std::vector<LogAttr>& more) {
    std::vector<LogAttr> attrs = TaskAttrs(task, lease, WorkerId());
    attrs.emplace_back("seconds", Seconds(std::chrono::steady_clock::now() - start));
    if (const std::optional<std::uint64_t> peak = memory.Bytes()) {
      attrs.emplace_back("peak_memory_bytes", *peak);
      if (memory.since_start()) attrs.emplace_back("peak_memory_since", "process start");
    }
    attrs.insert(attrs.end(), more.begin(), more.end());
    // Only once textures are in use, so that other tasks' lines stay as they were.
    if (const std::uint64_t bytes = executor_.TextureCacheBytes(); bytes > 0) attrs.emplace_back("texture_cache_bytes", bytes);
    Log(level, msg, attrs);
  };
  if (!lost.empty()) {
    log(LogLevel::kWarn, "task dropped", {{"reason", "lease lost: " + lost}});
  } else if (task_stop.stop_requested()) {
    Release(lease);
    log(LogLevel::kInfo, "task released unfinished", {});
  } else if (error) {
    // Logged before the report, so that the task's log ends with it.
    const contract::FailureEntry treated = contract::FailureOf(kind);
    pause_before_lease_ = !treated.permanent && !treated.blames_worker;
    log(LogLevel::kWarn, "task failed", {{"error", *error}, {"kind", treated.label}});
    const std::optional<pb::Artifact> uploaded = UploadLog(task_log, lease);
    if (const std::string problem = ReportFailure(lease, *error, kind, uploaded); !problem.empty()) {
      Log(LogLevel::kWarn, "task failure not reported", {{"task", lease.task_id()}, {"report", problem}});
    }
  } else {
    spare_pause_.Reset();
    std::vector<LogAttr> more;
    // A render tile's sample counts, so that a tile with bad samples shows in the log too.
    if (result.samples) {
      more.emplace_back("samples", result.samples->samples());
      more.emplace_back("nonfinite_samples", result.samples->nonfinite());
      more.emplace_back("zero_samples", result.samples->zero());
    }
    log(LogLevel::kInfo, "task done", more);
    const std::optional<pb::Artifact> uploaded = UploadLog(task_log, lease);
    if (const std::string problem = ReportComplete(lease, result, uploaded); !problem.empty()) {
      Log(LogLevel::kWarn, "task result not reported", {{"task", lease.task_id()}, {"report", problem}});
    }
  }
  {
    std::lock_guard lock(mu_);
    current_.reset();
  }
}

template <typename Call>
std::string Worker::Impl::Report(const pb::Lease& lease, const std::string& method, const std::string& lost, Call call) {
  const grpc::Status status =
      RetryTransient(method + " " + lease.task_id(), abort_.get_token(), seconds(0), [&] {
        grpc::ClientContext ctx;
        SetDeadline(ctx, kCallDeadline);
        Identify(ctx);
        return call(ctx);
      });
  if (status.ok()) return "";
  if (status.error_code() == grpc::StatusCode::FAILED_PRECONDITION) {
    return lost + ", lease lost: " + status.error_message();
  }
  if (abort_.stop_requested()) {
    Release(lease);
    return "abandoned while reporting";
  }
  return "refused: " + status.error_message();
}

std::string Worker::Impl::ReportComplete(const pb::Lease& lease, const TaskResult& result,
                                         const std::optional<pb::Artifact>& log) {
  pb::CompleteTaskRequest request;
  NameLease(request, lease);
  for (const auto& a : result.outputs) *request.add_outputs() = a;
  if (log) *request.add_outputs() = *log;
  if (result.metrics) *request.mutable_metrics() = *result.metrics;
  if (result.samples) *request.mutable_samples() = *result.samples;
  return Report(lease, "CompleteTask", "result dropped", [&](grpc::ClientContext& ctx) {
    pb::CompleteTaskResponse response;
    return stub_->CompleteTask(&ctx, request, &response);
  });
}

std::string Worker::Impl::ReportFailure(const pb::Lease& lease, const std::string& error, pb::FailureKind kind,
                                        const std::optional<pb::Artifact>& log) {
  pb::FailTaskRequest request;
  NameLease(request, lease);
  request.set_error(ReportedError(error));
  request.set_kind(kind);
  if (log) *request.mutable_log() = *log;
  return Report(lease, "FailTask", "not reported", [&](grpc::ClientContext& ctx) {
    pb::FailTaskResponse response;
    return stub_->FailTask(&ctx, request, &response);
  });
}

void Worker::Impl::Release(const pb::Lease& lease) {
  pb::ReleaseTaskRequest request;
  NameLease(request, lease);
  const grpc::Status status =
      RetryTransient("ReleaseTask " + lease.task_id(), {}, kGoodbyeGiveUp, [&] {
        pb::ReleaseTaskResponse response;
        grpc::ClientContext ctx;
        SetDeadline(ctx, seconds(5));
        Identify(ctx);
        return stub_->ReleaseTask(&ctx, request, &response);
      });
  // If this fails the lease simply expires and the task is queued again.
  if (!status.ok() && status.error_code() != grpc::StatusCode::FAILED_PRECONDITION) {
    Log(LogLevel::kWarn, "cannot release task", {{"task", lease.task_id()}, {"err", status.error_message()}});
  }
}

void Worker::Impl::Unregister() {
  pb::UnregisterWorkerRequest request;
  request.set_worker_id(WorkerId());
  const grpc::Status status = RetryTransient("UnregisterWorker", {}, kGoodbyeGiveUp, [&] {
    pb::UnregisterWorkerResponse response;
    grpc::ClientContext ctx;
    SetDeadline(ctx, seconds(5));
    Identify(ctx);
    return stub_->UnregisterWorker(&ctx, request, &response);
  });
  if (status.ok()) {
    Log(LogLevel::kInfo, "unregistered", {{"worker", request.worker_id()}});
  } else {
    Log(LogLevel::kWarn, "cannot unregister", {{"worker", request.worker_id()}, {"err", status.error_message()}});
  }
}

Worker::Worker(const WorkerOptions& options, unsigned cores)
    : impl_(std::make_unique<Impl>(options, cores)) {}
Worker::~Worker() = default;
int Worker::Run() { return impl_->Run(); }
void Worker::Drain() { impl_->Drain(); }
void Worker::Abort() { impl_->Abort(); }

}  // namespace farm
