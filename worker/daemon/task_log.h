#pragma once

// A task's own log: while a TaskLog lives, every line the worker logs (Log in log.h, from
// any thread) is kept for it as well as written to stderr, so that the worker can upload
// the lines of one task with its result ("task.log": worker.cpp). Tied to the task's scope:
// it starts collecting when made and stops when destroyed.
//
// Bounded: Text() is at most max_bytes. The first lines are kept up to about half of it,
// the last lines in the rest, and between them one line says how many were left out:
//
//   ... 1234 lines left out ...
//
// A line longer than its half is cut at a UTF-8 boundary and ends in "...".

#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <string_view>

namespace farm {

class TaskLog {
 public:
  // max_bytes must leave room for the marker line: at least kMinBytes.
  explicit TaskLog(std::size_t max_bytes);
  ~TaskLog();
  TaskLog(const TaskLog&) = delete;
  TaskLog& operator=(const TaskLog&) = delete;

  static constexpr std::size_t kMinBytes = 256;

  // Keeps one line (without its newline). Log calls it for every live TaskLog.
  void Add(std::string_view line);
  // The lines kept, each ending in a newline, with the marker where lines were left out.
  std::string Text() const;
  // Lines left out between the first and the last.
  std::uint64_t LeftOut() const;

 private:
  const std::size_t head_max_;
  const std::size_t tail_max_;
  mutable std::mutex mu_;  // guards what follows
  std::string head_;
  bool head_closed_ = false;
  std::deque<std::string> tail_;
  std::size_t tail_bytes_ = 0;
  std::uint64_t left_out_ = 0;
};

// The marker line for n lines left out, with its newline.
std::string LeftOutLine(std::uint64_t n);

// Adds line to every live TaskLog (Log calls it for each line it writes).
void AddToTaskLogs(std::string_view line);

}  // namespace farm
