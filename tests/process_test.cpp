// runProcess's timeouts: on the whole run, or on each wait for the next line of output (a child
// that prints a result per line, such as `parity test`'s children of several scripts).
#include <gtest/gtest.h>

#include "harness/run/process.h"

using namespace parity;

namespace {

// Five lines, 0.4 s apart: 2 s in all, never more than 0.4 s without a line.
const std::vector<std::string> kSteadyLines = {"/bin/sh", "-c", "for i in 1 2 3 4 5; do echo $i; sleep 0.4; done"};

TEST(Process, AWholeRunTimeoutKillsAChildThatTakesLongerInAll) {
  harness::ProcessResult r = harness::runProcess(kSteadyLines, 1.0);
  EXPECT_TRUE(r.timedOut);
  EXPECT_TRUE(r.died());
  EXPECT_LT(r.out.size(), 10u) << r.out;
}

TEST(Process, AnEachLineTimeoutLetsAChildRunWhileItPrintsLines) {
  harness::ProcessResult r = harness::runProcess(kSteadyLines, 1.0, harness::TimeoutScope::EachLine);
  EXPECT_FALSE(r.timedOut);
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_EQ(r.out, "1\n2\n3\n4\n5\n");
  // A child that stops printing is still killed.
  harness::ProcessResult silent = harness::runProcess({"/bin/sh", "-c", "echo 1; sleep 30"}, 1.0, harness::TimeoutScope::EachLine);
  EXPECT_TRUE(silent.timedOut);
  EXPECT_EQ(silent.out, "1\n");
}

}  // namespace
