#pragma once

// The worker's log: one event a line on stderr, key=value in the shape of the
// coordinator's log (Go's log/slog TextHandler), with the coordinator's field names, so one
// grep finds a task on both sides:
//
//   time=2026-12-01T19:43:00.123Z level=INFO msg="task done" job=J task=J.7 attempt=1 worker=W ...
//
// time is UTC with milliseconds; level is DEBUG, INFO, WARN or ERROR; values that need it
// are quoted and escaped as slog quotes them (contract/go_text.h). Field names: job, task,
// attempt, epoch, worker, coordinator, error (why a task failed, as the coordinator's
// "task failed" line has it), err (why a call failed), kind (a failure's kind), seconds.

#include <chrono>
#include <concepts>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>

namespace farm {

enum class LogLevel { kDebug, kInfo, kWarn, kError };

// One key=value pair; numbers are written as Go writes them.
struct LogAttr {
  LogAttr(std::string_view key, std::string_view value);
  LogAttr(std::string_view key, const std::string& value) : LogAttr(key, std::string_view(value)) {}
  LogAttr(std::string_view key, const char* value) : LogAttr(key, std::string_view(value)) {}
  LogAttr(std::string_view key, bool value);
  LogAttr(std::string_view key, double value);
  template <std::integral T>
    requires(!std::same_as<T, bool>)
  LogAttr(std::string_view key, T value) : key(key), text(std::to_string(value)) {}

  std::string_view key;
  std::string text;  // the value as written, quoted if it needs it
};

// The line (without its newline) for one event at `when`.
std::string FormatLogLine(std::chrono::system_clock::time_point when, LogLevel level, std::string_view msg,
                          std::span<const LogAttr> attrs);

// Writes the event at the current time to stderr, and keeps it in every live TaskLog
// (task_log.h). Lines from different threads never interleave.
void Log(LogLevel level, std::string_view msg, std::span<const LogAttr> attrs);
inline void Log(LogLevel level, std::string_view msg, std::initializer_list<LogAttr> attrs = {}) {
  Log(level, msg, std::span<const LogAttr>(attrs.begin(), attrs.size()));
}

}  // namespace farm
