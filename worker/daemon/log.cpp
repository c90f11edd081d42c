#include "daemon/log.h"

#include <cstdio>
#include <ctime>

#include "contract/go_text.h"
#include "daemon/task_log.h"

namespace farm {
namespace {

const char* LevelName(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug: return "DEBUG";
    case LogLevel::kInfo: return "INFO";
    case LogLevel::kWarn: return "WARN";
    case LogLevel::kError: return "ERROR";
  }
  return "INFO";
}

// slog's RFC 3339 with milliseconds, truncated as slog truncates: 2026-12-01T19:43:00.123Z.
std::string Timestamp(std::chrono::system_clock::time_point when) {
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(when.time_since_epoch()).count();
  const std::time_t seconds = static_cast<std::time_t>(ms / 1000 - (ms % 1000 < 0 ? 1 : 0));
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char buf[40];
  const std::size_t n = std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &utc);
  std::snprintf(buf + n, sizeof buf - n, ".%03dZ", static_cast<int>((ms % 1000 + 1000) % 1000));
  return buf;
}

}  // namespace

LogAttr::LogAttr(std::string_view key, std::string_view value) : key(key), text(contract::SlogText(value)) {}
LogAttr::LogAttr(std::string_view key, bool value) : key(key), text(value ? "true" : "false") {}
LogAttr::LogAttr(std::string_view key, double value) : key(key), text(contract::GoNumber(value)) {}

std::string FormatLogLine(std::chrono::system_clock::time_point when, LogLevel level, std::string_view msg,
                          std::span<const LogAttr> attrs) {
  std::string line = "time=";
  line.append(Timestamp(when)).append(" level=").append(LevelName(level));
  line.append(" msg=").append(contract::SlogText(msg));
  for (const LogAttr& a : attrs) line.append(" ").append(contract::SlogText(a.key)).append("=").append(a.text);
  return line;
}

void Log(LogLevel level, std::string_view msg, std::span<const LogAttr> attrs) {
  std::string line = FormatLogLine(std::chrono::system_clock::now(), level, msg, attrs);
  AddToTaskLogs(line);
  line += '\n';
  // One write per line: stdio locks the stream for the call.
  std::fwrite(line.data(), 1, line.size(), stderr);
}

}  // namespace farm
