#pragma once

// Termination signals without async-signal-safety hazards (the self-pipe trick): the
// SIGINT/SIGTERM handler only writes the signal number to a pipe, which is async-signal-safe
// whichever thread it runs on; a watcher thread reads the pipe and may then lock mutexes,
// log and call into gRPC like any other code. (Blocking the signals and sigwait-ing is not
// enough here: libraries start threads before main() that would not inherit the mask.)

#include <functional>
#include <thread>

namespace farm {

class SignalWatcher {
 public:
  // Installs the SIGINT and SIGTERM handlers and calls on_signal(n, signo) on the watcher
  // thread for the n-th signal received (n = 1, 2, ...). One watcher per process. The
  // destructor stops the thread and restores the default handlers. Throws
  // std::system_error if the pipe or the handlers cannot be set up.
  explicit SignalWatcher(std::function<void(int count, int signo)> on_signal);
  ~SignalWatcher();

  SignalWatcher(const SignalWatcher&) = delete;
  SignalWatcher& operator=(const SignalWatcher&) = delete;

 private:
  std::jthread thread_;
};

}  // namespace farm
