// The shared state of a run and its small helpers.
#include "harness/run/matrix/state.h"

#include <fnmatch.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <new>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "harness/cli/report_error.h"
#include "harness/compare/attachments.h"
#include "harness/compare/diagnosis.h"
#include "harness/run/expectations.h"
#include "harness/run/external_images.h"
#include "harness/compare/diff.h"
#include "harness/compare/flip.h"
#include "harness/run/golden.h"
#include "harness/io/image_io.h"
#include "rhi/timing_device.h"
#include "harness/run/process.h"
#include "harness/run/render.h"
#include "harness/run/report.h"
#include "harness/scripts/runner.h"
#include "platforms/common/platform.h"
#include "rhi/rhi.h"
#include "scene/scene.h"
#include "techniques/technique.h"

namespace parity::harness::matrix {

std::string projectCommit() {
  std::string git = findInPath("git");
  if (git.empty()) return "";
  ProcessResult p = runProcess({git, "-C", PARITY_SOURCE_DIR, "describe", "--always", "--dirty", "--abbrev=12"}, 10);
  std::string out = p.exitCode == 0 ? p.out : "";
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

std::string fmtDuration(double s) {
  int t = static_cast<int>(std::lround(s));
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%d:%02d", t / 60, t % 60);
  return buf;
}

int MatrixState::jobs() const {
  int j = o_.jobs > 0 ? o_.jobs : static_cast<int>(std::thread::hardware_concurrency());
  return std::max(1, j);
}

fs::path MatrixState::caseDir(const CaseKey& k) const {
  return fs::path(o_.outDir) / "cases" / k.technique / k.scene / k.platform;
}

const Expectation* MatrixState::expectedFor(const CaseState& c) const {
  std::string device = c.device.value("renderer", "") + " | " + c.device.value("driver", "");
  return findExpectation(expectations_, c.key.id(), device);
}

void MatrixState::progress(const CaseState& c, CaseResult r) {
  double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  counts_[resultName(r)]++;
  bool notable = r != CaseResult::Pass;
  if (tty_) {
    if (notable) std::printf("\r\033[K%-16s %s: %s\n", resultName(r), c.key.id().c_str(), c.reason.c_str());
    std::string line;
    for (const auto& [name, n] : counts_) line += " " + std::to_string(n) + " " + name;
    double eta = done_ ? elapsed / static_cast<double>(done_) * static_cast<double>(total_ - done_) : 0;
    std::printf("\r\033[K[%zu/%zu]%s (%zu skipped) | %s elapsed, ETA %s", done_, total_, line.c_str(), skipped_,
                fmtDuration(elapsed).c_str(), fmtDuration(eta).c_str());
  } else {
    std::printf("%-16s %s%s%s\n", resultName(r), c.key.id().c_str(), notable ? ": " : "", notable ? c.reason.c_str() : "");
  }
  std::fflush(stdout);
}

}  // namespace parity::harness::matrix
