#include "daemon/signals.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <stop_token>
#include <system_error>

namespace farm {
namespace {

// The pipe the handler writes to. Plain ints: all a signal handler may touch.
int g_pipe[2] = {-1, -1};

extern "C" void OnTerminationSignal(int signo) {
  const int saved_errno = errno;
  const unsigned char byte = static_cast<unsigned char>(signo);
  // Non-blocking: if the pipe were ever full, dropping a signal beats hanging in a handler.
  [[maybe_unused]] const ssize_t n = write(g_pipe[1], &byte, 1);
  errno = saved_errno;
}

void SetHandler(void (*handler)(int)) {
  struct sigaction action {};
  action.sa_handler = handler;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // Other threads' system calls carry on undisturbed.
  for (int signo : {SIGINT, SIGTERM}) {
    if (sigaction(signo, &action, nullptr) != 0) {
      throw std::system_error(errno, std::generic_category(), "sigaction");
    }
  }
}

}  // namespace

SignalWatcher::SignalWatcher(std::function<void(int, int)> on_signal) {
  if (pipe2(g_pipe, O_CLOEXEC | O_NONBLOCK) != 0) {
    throw std::system_error(errno, std::generic_category(), "signal pipe");
  }
  SetHandler(OnTerminationSignal);
  thread_ = std::jthread([on_signal = std::move(on_signal)](std::stop_token stop) {
    int count = 0;
    while (!stop.stop_requested()) {
      pollfd fd{g_pipe[0], POLLIN, 0};
      // Wakes up now and then to notice that the watcher is being destroyed.
      if (poll(&fd, 1, 200) <= 0) continue;
      unsigned char signo = 0;
      while (read(g_pipe[0], &signo, 1) == 1) on_signal(++count, signo);
    }
  });
}

SignalWatcher::~SignalWatcher() {
  SetHandler(SIG_DFL);
  thread_.request_stop();
  thread_.join();
  close(g_pipe[0]);
  close(g_pipe[1]);
  g_pipe[0] = g_pipe[1] = -1;
}

}  // namespace farm
