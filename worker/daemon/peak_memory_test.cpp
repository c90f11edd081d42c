#include "daemon/peak_memory.h"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>

namespace farm {
namespace {

constexpr std::size_t kBlock = 256 << 20;

// Touches every page of a fresh block, so that it is resident.
std::unique_ptr<char[]> Resident(std::size_t bytes) {
  std::unique_ptr<char[]> block(new char[bytes]);
  std::memset(block.get(), 1, bytes);
  return block;
}

TEST(PeakMemory, CountsWhatATaskTouchedAndStartsAfreshForTheNext) {
  const PeakMemory before = PeakMemory::Start();
  ASSERT_TRUE(before.Bytes());
  const std::uint64_t baseline = *before.Bytes();
  {
    const PeakMemory task = PeakMemory::Start();
    const auto block = Resident(kBlock);
    ASSERT_TRUE(task.Bytes());
    EXPECT_GE(*task.Bytes(), baseline + kBlock * 9 / 10);
  }
  // The block is freed (a large block goes back to the kernel at once); where the mark can
  // be reset, the next task's peak no longer counts it.
  const PeakMemory next = PeakMemory::Start();
  if (next.since_start()) GTEST_SKIP() << "this kernel cannot reset the resident high-water mark";
  EXPECT_LT(*next.Bytes(), baseline + kBlock / 2);
}

}  // namespace
}  // namespace farm
