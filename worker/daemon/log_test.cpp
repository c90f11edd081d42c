#include "daemon/log.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>

namespace farm {
namespace {

// 2026-12-01T19:43:00.123456789Z.
std::chrono::system_clock::time_point When() {
  return std::chrono::system_clock::time_point(
      std::chrono::duration_cast<std::chrono::system_clock::duration>(std::chrono::nanoseconds(1796154180123456789)));
}

std::string Line(std::chrono::system_clock::time_point when, LogLevel level, std::string_view msg,
                 std::initializer_list<LogAttr> attrs) {
  return FormatLogLine(when, level, msg, std::span<const LogAttr>(attrs.begin(), attrs.size()));
}

// The expectations are what Go's log/slog TextHandler writes for the same event.
TEST(Log, LinesHaveTheShapeOfTheCoordinatorsSlogLines) {
  EXPECT_EQ(Line(When(), LogLevel::kWarn, "task failed",
                          {{"job", "J"}, {"attempt", 3}, {"err", "shapes[2].sphere.radius: must be > 0, got -1"},
                           {"f", 0.25}, {"ok", true}}),
            "time=2026-12-01T19:43:00.123Z level=WARN msg=\"task failed\" job=J attempt=3 "
            "err=\"shapes[2].sphere.radius: must be > 0, got -1\" f=0.25 ok=true");
  EXPECT_EQ(Line(When(), LogLevel::kError, "x", {}), "time=2026-12-01T19:43:00.123Z level=ERROR msg=x");
  EXPECT_EQ(Line(When(), LogLevel::kInfo, "registered", {{"epoch", std::uint64_t{18446744073709551615u}}}),
            "time=2026-12-01T19:43:00.123Z level=INFO msg=registered epoch=18446744073709551615");
}

TEST(Log, KeysAndValuesAreQuotedOnlyWhenSlogWouldQuoteThem) {
  // Each case of contract::SlogText's table applies; one of each kind here.
  EXPECT_EQ(Line(When(), LogLevel::kInfo, "m", {{"addr", "127.0.0.1:50051"}, {"v", ""}, {"a key", "tab\there"}}),
            "time=2026-12-01T19:43:00.123Z level=INFO msg=m addr=127.0.0.1:50051 v=\"\" \"a key\"=\"tab\\there\"");
}

TEST(Log, TimeIsUtcTruncatedToMilliseconds) {
  const auto epoch = std::chrono::system_clock::time_point();
  EXPECT_EQ(Line(epoch + std::chrono::microseconds(999'999), LogLevel::kDebug, "m", {}),
            "time=1970-01-01T00:00:00.999Z level=DEBUG msg=m");
}

}  // namespace
}  // namespace farm
