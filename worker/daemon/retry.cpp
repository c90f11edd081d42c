#include "daemon/retry.h"

#include <condition_variable>
#include <mutex>
#include <string>

#include "daemon/log.h"

namespace farm {

bool IsTransient(grpc::StatusCode code) {
  return code == grpc::StatusCode::UNAVAILABLE || code == grpc::StatusCode::DEADLINE_EXCEEDED ||
         code == grpc::StatusCode::ABORTED;
}

bool SleepUnlessStopped(Millis duration, std::stop_token stop) {
  std::mutex mu;
  std::condition_variable_any cv;
  std::unique_lock lock(mu);
  // Waits on nothing but the stop request and the clock.
  return !cv.wait_for(lock, stop, duration, [] { return false; }) && !stop.stop_requested();
}

Backoff::Backoff(Millis initial, Millis max)
    : initial_(initial), max_(max), next_(initial), rng_(std::random_device{}()) {}

Millis Backoff::Next() {
  const Millis base = next_;
  next_ = std::min(max_, next_ * 2);
  std::uniform_real_distribution<double> jitter(0.75, 1.25);
  return Millis(static_cast<Millis::rep>(static_cast<double>(base.count()) * jitter(rng_)));
}

grpc::Status RetryTransient(std::string_view what, std::stop_token stop,
                            std::chrono::seconds give_up_after,
                            const std::function<grpc::Status()>& attempt,
                            const RetryLogger& log_retry) {
  const auto start = std::chrono::steady_clock::now();
  Backoff backoff;
  while (true) {
    if (stop.stop_requested()) return grpc::Status(grpc::StatusCode::CANCELLED, "stopped");
    grpc::Status status = attempt();
    if (status.ok() || !IsTransient(status.error_code())) return status;
    if (stop.stop_requested()) return grpc::Status(grpc::StatusCode::CANCELLED, "stopped");
    const Millis delay = backoff.Next();
    if (give_up_after.count() > 0 &&
        std::chrono::steady_clock::now() + delay - start > give_up_after) {
      return status;
    }
    if (log_retry) {
      log_retry(status, delay);
    } else {
      Log(LogLevel::kWarn, "retrying",
          {{"call", what}, {"err", status.error_message()}, {"code", static_cast<int>(status.error_code())},
           {"retry_ms", delay.count()}});
    }
    if (!SleepUnlessStopped(delay, stop)) {
      return grpc::Status(grpc::StatusCode::CANCELLED, "stopped");
    }
  }
}

}  // namespace farm
