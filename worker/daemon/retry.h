#pragma once

// Retrying RPCs that failed for reasons that pass (the coordinator restarting, a network
// blip), with exponential backoff that a stop request cuts short.

#include <grpcpp/support/status.h>

#include <chrono>
#include <functional>
#include <random>
#include <stop_token>
#include <string_view>

namespace farm {

using Millis = std::chrono::milliseconds;

// UNAVAILABLE (no connection), DEADLINE_EXCEEDED (a call that took too long) and ABORTED
// (a conflict the server asks to retry) are worth another try; anything else is an answer.
bool IsTransient(grpc::StatusCode code);

// Sleeps for `duration`, or less if `stop` is requested. Returns false if it was.
bool SleepUnlessStopped(Millis duration, std::stop_token stop);

// Delays growing from `initial` by doubling up to `max`, each with +-25% jitter so that
// many workers do not retry in step.
class Backoff {
 public:
  explicit Backoff(Millis initial = Millis(200), Millis max = Millis(5000));
  Millis Next();
  void Reset() { next_ = initial_; }

 private:
  Millis initial_;
  Millis max_;
  Millis next_;
  std::minstd_rand rng_;
};

// Calls `attempt` until it returns a non-transient status (success included), `stop` is
// requested (returns CANCELLED), or `give_up_after` has passed since the first attempt
// (zero: never give up; returns the last transient status). Each attempt must create its
// own grpc::ClientContext. Retries are logged with `what` naming the call, or by
// `log_retry` (given the failed status and the delay before the next attempt) if set.
using RetryLogger = std::function<void(const grpc::Status&, Millis)>;
grpc::Status RetryTransient(std::string_view what, std::stop_token stop,
                            std::chrono::seconds give_up_after,
                            const std::function<grpc::Status()>& attempt,
                            const RetryLogger& log_retry = nullptr);

}  // namespace farm
