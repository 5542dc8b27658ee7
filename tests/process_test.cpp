// runProcess's timeouts: on the whole run, or on each wait for the next line of output (a child
// that prints a result per line, such as `parity test`'s children of several scripts).
#include <gtest/gtest.h>

#include "harness/run/process.h"

#include <malloc.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

using namespace parity;

namespace {

// Eight lines, 0.4 s apart: 3.2 s in all, never more than 0.4 s without a line. The timeouts
// below are 2 s: five times the gap, so a loaded machine does not make the child look silent.
const std::vector<std::string> kSteadyLines = {"/bin/sh", "-c", "for i in 1 2 3 4 5 6 7 8; do echo $i; sleep 0.4; done"};
constexpr double kTimeout = 2.0;

TEST(Process, AWholeRunTimeoutKillsAChildThatTakesLongerInAll) {
  harness::ProcessResult r = harness::runProcess(kSteadyLines, kTimeout);
  EXPECT_TRUE(r.timedOut);
  EXPECT_TRUE(r.died());
  EXPECT_EQ(r.out.find("8\n"), std::string::npos) << "killed before its last line: " << r.out;
}

TEST(Process, AnEachLineTimeoutLetsAChildRunWhileItPrintsLines) {
  harness::ProcessResult r = harness::runProcess(kSteadyLines, kTimeout, harness::TimeoutScope::EachLine);
  EXPECT_FALSE(r.timedOut);
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_EQ(r.out, "1\n2\n3\n4\n5\n6\n7\n8\n");
  // A child that stops printing is still killed.
  harness::ProcessResult silent = harness::runProcess({"/bin/sh", "-c", "echo 1; sleep 30"}, kTimeout, harness::TimeoutScope::EachLine);
  EXPECT_TRUE(silent.timedOut);
  EXPECT_EQ(silent.out, "1\n");
}

}  // namespace

// The pattern of Mesa's GL draw path: a block malloc'd and freed per draw. With the thresholds
// fixed, the block is reused from the heap every time: the program break stays where the first
// draw left it, and no block is mapped on its own. With glibc's adjusting thresholds the first
// block is mapped, and the break then moves.
TEST(Process, ABlockFreedPerDrawStaysInTheHeap) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's allocator replaces glibc's; its thresholds are not glibc's";
#endif
  harness::fixAllocatorThresholds();
  constexpr size_t kBlock = 3 << 20;  // larger than glibc's default mmap threshold of 128 KiB
  const auto draw = [&] {
    const size_t mappedBefore = mallinfo2().hblks;
    char* block = static_cast<char*>(std::malloc(kBlock));
    std::memset(block, 1, kBlock);
    const size_t mapped = mallinfo2().hblks - mappedBefore;
    std::free(block);
    return mapped;
  };
  EXPECT_EQ(draw(), 0u) << "the first block was mapped on its own";
  const void* breakAfterFirstDraw = sbrk(0);
  for (int i = 0; i < 50; ++i) {
    EXPECT_EQ(draw(), 0u) << "draw " << i;
    ASSERT_EQ(sbrk(0), breakAfterFirstDraw) << "the heap grew or shrank at draw " << i;
  }
}
