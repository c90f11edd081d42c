#include "util/progress.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace farm {
namespace {

TEST(Progress, DefaultCountsNowhere) {
  const Progress nowhere;
  nowhere.Advance(5);  // Must not crash: callers that do not report pass this.
  SUCCEED();
}

TEST(Progress, CopiesAdvanceTheSameCounterFromManyThreads) {
  ProgressCounter counter{0};
  const Progress progress(counter);
  std::vector<std::jthread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([progress] {
      for (int i = 0; i < 10'000; ++i) progress.Advance();
    });
  }
  threads.clear();  // Joins.
  EXPECT_EQ(counter.load(), 40'000u);
  progress.Advance(7);
  EXPECT_EQ(counter.load(), 40'007u);
}

}  // namespace
}  // namespace farm
