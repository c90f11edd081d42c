#include "daemon/task_log.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace farm {
namespace {

// Room for the marker with the largest count.
const std::size_t kMarkerRoom = LeftOutLine(UINT64_MAX).size();

// The live task logs; Log feeds each (log.cpp's AddToTaskLogs).
std::mutex live_mu;
std::vector<TaskLog*> live;

// line, with its newline, cut to at most max bytes (newline included) at a UTF-8 boundary.
std::string Fitted(std::string_view line, std::size_t max) {
  if (line.size() + 1 <= max) return std::string(line).append("\n");
  constexpr std::string_view kCut = "...\n";
  std::size_t n = max - kCut.size();
  while (n > 0 && (static_cast<unsigned char>(line[n]) & 0xC0) == 0x80) --n;  // not inside a character
  return std::string(line.substr(0, n)).append(kCut);
}

}  // namespace

std::string LeftOutLine(std::uint64_t n) { return "... " + std::to_string(n) + " lines left out ...\n"; }

TaskLog::TaskLog(std::size_t max_bytes)
    : head_max_((max_bytes - kMarkerRoom) / 2), tail_max_(max_bytes - kMarkerRoom - head_max_) {
  if (max_bytes < kMinBytes) throw std::invalid_argument("TaskLog: max_bytes must be at least 256");
  std::lock_guard lock(live_mu);
  live.push_back(this);
}

TaskLog::~TaskLog() {
  std::lock_guard lock(live_mu);
  std::erase(live, this);
}

void TaskLog::Add(std::string_view line) {
  std::lock_guard lock(mu_);
  if (!head_closed_) {
    std::string l = Fitted(line, head_max_);
    if (head_.size() + l.size() <= head_max_) {
      head_ += l;
      return;
    }
    head_closed_ = true;  // later lines go to the tail, or the head would have a gap
  }
  std::string l = Fitted(line, tail_max_);
  tail_bytes_ += l.size();
  tail_.push_back(std::move(l));
  while (tail_bytes_ > tail_max_) {
    tail_bytes_ -= tail_.front().size();
    tail_.pop_front();
    ++left_out_;
  }
}

std::string TaskLog::Text() const {
  std::lock_guard lock(mu_);
  std::string text = head_;
  if (left_out_ > 0) text += LeftOutLine(left_out_);
  for (const std::string& l : tail_) text += l;
  return text;
}

std::uint64_t TaskLog::LeftOut() const {
  std::lock_guard lock(mu_);
  return left_out_;
}

void AddToTaskLogs(std::string_view line) {
  std::lock_guard lock(live_mu);
  for (TaskLog* log : live) log->Add(line);
}

}  // namespace farm
