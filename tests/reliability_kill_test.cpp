// `parity bless` and a report write (`parity merge`) killed with SIGKILL at every step of their
// atomic writes (PARITY_KILL_AT_WRITE_STEP, harness/io/atomic_file.h) and at random moments: every
// golden, manifest, image and report file is then the old file or the new one, never a part, and
// the next run completes and leaves no temporary file behind.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "harness/run/process.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

harness::ProcessResult parity(std::vector<std::string> args, double timeout = 120) {
  args.insert(args.begin(), PARITY_BINARY);
  return harness::runProcess(args, timeout);
}

// Runs parity with PARITY_KILL_AT_WRITE_STEP=step (0: not set).
harness::ProcessResult parityKilledAt(long step, std::vector<std::string> args) {
  if (step > 0) ::setenv("PARITY_KILL_AT_WRITE_STEP", std::to_string(step).c_str(), 1);
  auto r = parity(std::move(args));
  ::unsetenv("PARITY_KILL_AT_WRITE_STEP");
  return r;
}

bool isTemporary(const fs::path& p) { return p.filename().string().rfind(".parity-tmp-", 0) == 0; }

// Text files carry the time they were written ("blessed", "finished"); the comparison is of
// everything else, byte for byte.
std::string comparable(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  std::string ext = p.extension().string();
  if (ext != ".json" && ext != ".html" && ext != ".xml") return s.str();
  static const std::regex iso(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)");
  return std::regex_replace(s.str(), iso, "<time>");
}

// Every file under root (temporaries apart), by relative path.
std::map<std::string, std::string> snapshot(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file() && !isTemporary(e.path())) files[fs::relative(e.path(), root).string()] = comparable(e.path());
  return files;
}

int temporariesUnder(const fs::path& root) {
  int n = 0;
  for (const auto& e : fs::recursive_directory_iterator(root)) n += isTemporary(e.path());
  return n;
}

void copyTree(const fs::path& from, const fs::path& to) {
  fs::remove_all(to);
  fs::copy(from, to, fs::copy_options::recursive);
}

// After an interrupted write: each file is the old or the new one, no old file is gone.
void expectOldOrNew(const fs::path& root, const std::map<std::string, std::string>& before,
                    const std::map<std::string, std::string>& after, const std::string& when) {
  auto now = snapshot(root);
  for (const auto& [path, bytes] : now) {
    auto o = before.find(path), n = after.find(path);
    bool isOld = o != before.end() && o->second == bytes, isNew = n != after.end() && n->second == bytes;
    EXPECT_TRUE(isOld || isNew) << when << ": " << path << " is neither the old nor the new file (" << bytes.size()
                                << " bytes)";
  }
  for (const auto& [path, bytes] : before) EXPECT_TRUE(now.count(path)) << when << ": " << path << " was lost";
}

class KillDuringWrites : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("parity-kill-" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_ / "no-goldens");
    // Two runs of one case at different sizes: the goldens and reports of the first are "old",
    // those of the second "new", and every file differs between them. Deferred shading: a final
    // image and its G-buffer targets, so a bless writes several goldens.
    for (const auto& [name, size] : {std::pair{"old", "64x36"}, std::pair{"new", "80x45"}}) {
      auto r = parity({"run", "--technique", "deferred", "--scene", "default", "--platform", "reference", "--size", size,
                       "--golden", (root_ / "no-goldens").string(), "--out", (root_ / ("run-" + std::string(name))).string()});
      if (r.exitCode != 0 && r.exitCode != 2) setupError_ = "parity run failed: " + r.err;
    }
  }
  static void TearDownTestSuite() {
    if (!::getenv("PARITY_KEEP_TEST_OUTPUT")) fs::remove_all(root_);
  }
  void SetUp() override {
    if (!setupError_.empty()) GTEST_FAIL() << setupError_;
  }

  // Runs `args` (which write into `target`) killed at step 1, 1 + stride, ... until it completes,
  // each time from the `before` tree; checks old-or-new after each kill and a clean, complete
  // result after the next uninterrupted run. A file takes three (images) or four (text) steps, so
  // a stride of 3 still stops at every kind of step. Returns the number of kills.
  static int killAtSteps(long stride, const fs::path& before, const fs::path& target, const std::vector<std::string>& args,
                         int* killsLeavingTemporaries) {
    auto oldFiles = snapshot(before);
    copyTree(before, target);
    auto done = parity(args);
    EXPECT_TRUE(done.exitCode == 0 || done.exitCode == 2) << done.err;
    auto newFiles = snapshot(target);
    EXPECT_NE(oldFiles, newFiles);
    int kills = 0;
    for (long step = 1; step < 1000; step += stride) {
      copyTree(before, target);
      auto r = parityKilledAt(step, args);
      if (!r.crashed) break;  // the write finished before step N: every step has been tried
      EXPECT_EQ(r.signal, SIGKILL) << r.err;
      ++kills;
      std::string when = "killed at write step " + std::to_string(step);
      expectOldOrNew(target, oldFiles, newFiles, when);
      *killsLeavingTemporaries += temporariesUnder(target) > 0;
      // The next run completes: the new files, and nothing the killed one left.
      auto next = parity(args);
      EXPECT_TRUE(next.exitCode == 0 || next.exitCode == 2) << when << ": " << next.err;
      EXPECT_EQ(temporariesUnder(target), 0) << when << ": the next run left temporary files";
      EXPECT_EQ(snapshot(target), newFiles) << when << ": the next run did not write the new files";
    }
    return kills;
  }

  static fs::path root_;
  static std::string setupError_;
};
fs::path KillDuringWrites::root_;
std::string KillDuringWrites::setupError_;

TEST_F(KillDuringWrites, BlessLeavesEveryGoldenOldOrNew) {
  fs::path before = root_ / "golden-before";
  fs::create_directories(before);
  test::writeEvidence(before.string(), "tests/reliability_kill_test.cpp: KillDuringWrites.BlessLeavesEveryGoldenOldOrNew");
  auto b = parity({"bless", "--from", (root_ / "run-old").string(), "--golden", before.string()});
  ASSERT_EQ(b.exitCode, 0) << b.err;
  int withTemporaries = 0;
  int kills = killAtSteps(1, before, root_ / "golden",
                              {"bless", "--from", (root_ / "run-new").string(), "--golden", (root_ / "golden").string()},
                              &withTemporaries);
  // One final image, its per-pass targets and the manifest, four steps each.
  EXPECT_GE(kills, 20);
  EXPECT_GT(withTemporaries, 0) << "no kill left a temporary file: the clean-up was not exercised";
  std::cout << kills << " kills during bless, " << withTemporaries << " left temporary files\n";
}

TEST_F(KillDuringWrites, MergedReportLeavesEveryFileOldOrNew) {
  fs::path before = root_ / "report-before";
  auto m = parity({"merge", (root_ / "run-old").string(), "--out", before.string()});
  ASSERT_TRUE(m.exitCode == 0 || m.exitCode == 2) << m.err;
  int withTemporaries = 0;
  int kills = killAtSteps(3, before, root_ / "report", {"merge", (root_ / "run-new").string(), "--out", (root_ / "report").string()},
                              &withTemporaries);
  // Images (both backends' final image and per-pass targets), case pages, results.json, junit.xml
  // and index.html: over 70 steps, every third one.
  EXPECT_GE(kills, 20);
  EXPECT_GT(withTemporaries, 0);
  std::cout << kills << " kills during merge, " << withTemporaries << " left temporary files\n";
}

// Not only at the write steps: SIGKILL at random moments of a bless (seeded, so a failure can be
// replayed), through the harness's own timeout kill.
TEST_F(KillDuringWrites, BlessKilledAtRandomMoments) {
  fs::path before = root_ / "golden-before-random";
  fs::create_directories(before);
  test::writeEvidence(before.string(), "tests/reliability_kill_test.cpp: KillDuringWrites.BlessKilledAtRandomMoments");
  ASSERT_EQ(parity({"bless", "--from", (root_ / "run-old").string(), "--golden", before.string()}).exitCode, 0);
  auto oldFiles = snapshot(before);
  fs::path target = root_ / "golden-random";
  std::vector<std::string> args{"bless", "--from", (root_ / "run-new").string(), "--golden", target.string()};
  copyTree(before, target);
  auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(parity(args).exitCode, 0);
  double full = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  auto newFiles = snapshot(target);
  std::mt19937 rng(20261123);
  std::uniform_real_distribution<double> moment(0.001, full);
  int interrupted = 0;
  for (int i = 0; i < 10; ++i) {
    copyTree(before, target);
    double at = moment(rng);
    auto r = harness::runProcess([&] {
      auto a = args;
      a.insert(a.begin(), PARITY_BINARY);
      return a;
    }(), at);
    std::string when = "killed after " + std::to_string(at) + " s";
    if (r.timedOut) ++interrupted;
    expectOldOrNew(target, oldFiles, newFiles, when);
    ASSERT_EQ(parity(args).exitCode, 0) << when;
    EXPECT_EQ(temporariesUnder(target), 0) << when;
    EXPECT_EQ(snapshot(target), newFiles) << when;
  }
  // Moments after the bless finished would check nothing: most must land inside it.
  EXPECT_GE(interrupted, 5) << "full bless " << full << " s";
  std::cout << interrupted << " of 10 random kills interrupted the bless (full bless " << full << " s)\n";
}

}  // namespace
