// runProcess's timeouts: on the whole run, or on each wait for the next line of output (a child
// that prints a result per line, such as `parity test`'s children of several scripts).
#include <gtest/gtest.h>

#include "harness/run/process.h"

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
