#include "daemon/task_log.h"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "daemon/log.h"

namespace farm {
namespace {

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  for (std::size_t nl; (nl = text.find('\n', start)) != std::string::npos; start = nl + 1) {
    lines.push_back(text.substr(start, nl - start));
  }
  EXPECT_EQ(start, text.size()) << "the text does not end in a newline";
  return lines;
}

TEST(TaskLog, KeepsWhatIsLoggedWhileItLivesAndNothingElse) {
  Log(LogLevel::kInfo, "before the task");
  std::optional<TaskLog> log(std::in_place, 64 * 1024);
  Log(LogLevel::kInfo, "task started", {{"job", "J"}, {"task", "J.7"}});
  std::thread([] { Log(LogLevel::kWarn, "heartbeat failed; will keep trying", {{"worker", "W"}}); }).join();
  const std::string text = log->Text();
  log.reset();
  Log(LogLevel::kInfo, "after the task");
  const std::vector<std::string> lines = Lines(text);
  ASSERT_EQ(lines.size(), 2u) << text;
  EXPECT_NE(lines[0].find(" level=INFO msg=\"task started\" job=J task=J.7"), std::string::npos) << lines[0];
  EXPECT_TRUE(lines[0].starts_with("time=")) << lines[0];
  EXPECT_NE(lines[1].find("msg=\"heartbeat failed; will keep trying\" worker=W"), std::string::npos) << lines[1];
}

TEST(TaskLog, EveryLiveLogGetsTheLine) {
  TaskLog a(1024);
  {
    TaskLog b(1024);
    b.Add("both");
    AddToTaskLogs("both again");
  }
  AddToTaskLogs("only a");
  EXPECT_EQ(a.Text(), "both again\nonly a\n");
}

// Past the limit: the first lines up to half, the last in the rest, the count between.
TEST(TaskLog, KeepsTheFirstAndLastLinesWithinTheLimitAndCountsTheRest) {
  struct Case {
    std::size_t max_bytes;
    int lines;
  };
  for (const Case c : {Case{256, 100}, Case{1024, 5000}, Case{64 * 1024, 100000}}) {
    TaskLog log(c.max_bytes);
    for (int i = 0; i < c.lines; ++i) log.Add("line " + std::to_string(i));
    const std::string text = log.Text();
    EXPECT_LE(text.size(), c.max_bytes);
    const std::vector<std::string> lines = Lines(text);
    const auto marker = std::find_if(lines.begin(), lines.end(), [](const std::string& l) { return l.starts_with("... "); });
    ASSERT_NE(marker, lines.end()) << text;
    const auto head = static_cast<int>(marker - lines.begin());
    const auto tail = static_cast<int>(lines.end() - marker - 1);
    EXPECT_GT(head, 0);
    EXPECT_GT(tail, 0);
    // The head is lines 0.., the tail the last ones, and the marker counts the others.
    for (int i = 0; i < head; ++i) EXPECT_EQ(lines[static_cast<std::size_t>(i)], "line " + std::to_string(i));
    for (int i = 0; i < tail; ++i) {
      EXPECT_EQ(lines[static_cast<std::size_t>(head + 1 + i)], "line " + std::to_string(c.lines - tail + i));
    }
    const std::uint64_t left = static_cast<std::uint64_t>(c.lines - head - tail);
    EXPECT_EQ(*marker, LeftOutLine(left).substr(0, LeftOutLine(left).size() - 1));
    EXPECT_EQ(log.LeftOut(), left);
    // Most of the limit is used: neither half is left nearly empty.
    EXPECT_GT(text.size(), c.max_bytes * 3 / 4) << text.size();
  }
}

TEST(TaskLog, UnderTheLimitKeepsEveryLineWithoutAMarker) {
  TaskLog log(1024);
  for (int i = 0; i < 20; ++i) log.Add("line " + std::to_string(i));
  const std::vector<std::string> lines = Lines(log.Text());
  ASSERT_EQ(lines.size(), 20u);
  EXPECT_EQ(lines.back(), "line 19");
  EXPECT_EQ(log.LeftOut(), 0u);
}

TEST(TaskLog, CutsALineLongerThanItsHalfAtACharacter) {
  TaskLog log(256);
  std::string line(50, 'a');
  for (int i = 0; i < 100; ++i) line += "\xc3\xa9";  // é, two bytes each
  log.Add(line);
  const std::string text = log.Text();
  EXPECT_LE(text.size(), 256u);
  ASSERT_TRUE(text.ends_with("...\n")) << text;
  const std::string kept = text.substr(50, text.size() - 50 - 4);
  EXPECT_EQ(kept.size() % 2, 0u) << "a character was cut in two";
  EXPECT_TRUE(text.starts_with(std::string(50, 'a')));
}

TEST(TaskLog, RefusesALimitWithoutRoomForTheMarker) {
  EXPECT_THROW(TaskLog(10), std::invalid_argument);
}

}  // namespace
}  // namespace farm
