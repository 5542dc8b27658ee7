// What the steps of one `parity run` share: the options, the cases and their states, the golden
// folder, the backends, counters and the progress line. The families of steps are layers over it:
// comparisons (comparisons.cpp) under attempts (attempts.cpp) under the run (matrix.cpp).
#pragma once

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "harness/run/expectations.h"
#include "harness/run/golden.h"
#include "harness/io/text.h"
#include "harness/run/process.h"
#include "harness/run/run.h"

namespace parity::harness {
struct DiffResult;
}

namespace parity::harness::matrix {

// How many rendered cases of one backend one child renders on the first attempt
// (CaseAttempts::attemptPlatforms): a child's first render pays Mesa's first compilations and
// set-up (docs/BENCH.md), so the more cases share it the less it costs each; few enough that two
// workers stay busy to the end of a run.
inline constexpr size_t kCasesPerChild = 16;

// How many scripts one child runs on the first attempt (CaseAttempts::attemptScriptPlatforms):
// enough that a device and a process serve tens of cases, few enough that two workers stay busy
// to the end of a run's scripts.
inline constexpr size_t kScriptsPerChild = 8;

namespace fs = std::filesystem;

struct BackendInfo {
  bool available = false;
  std::string renderer, driver, api, reason;
};

// The commit of the source tree the binary was built from ("" outside a git checkout).
std::string projectCommit();
// m:ss
std::string fmtDuration(double s);
// What a child says of its own time beside render_ms (case_worker.cpp, a script child's line):
// kept per case in results.json and summed into its `timing` as `<phase>_s`.
inline constexpr const char* kChildPhases[] = {"setup_ms", "device_ms", "write_ms", "worker_ms"};
// Where a child's message is cut in results and reports.
inline constexpr size_t kMessageChars = 2000;

struct CaseState {
  CaseKey key;
  CaseResult raw = CaseResult::Skip;  // result of the latest attempt, before expectations
  CaseResult result = CaseResult::Skip;
  std::string reason;
  bool rendered = false;
  nlohmann::json device = nlohmann::json::object();  // renderer, driver, api
  nlohmann::json worker = nlohmann::json::object();  // the child's JSON
  nlohmann::json golden = nlohmann::json::object();  // comparison with the golden
  nlohmann::json attempts = nlohmann::json::array();
  std::string stderrText;
  std::string expectation;                  // reason of the matching expectation
  std::string expected;                     // its result
  const Expectation* expectationEntry = nullptr;  // the entry itself (its bug and expiry)
  double childSeconds = 0;
  Tolerance tolerance;
};

class MatrixState {
 public:
  explicit MatrixState(const RunOptions& o) : o_(o) {}

 protected:
  int jobs() const;
  fs::path caseDir(const CaseKey& k) const;
  std::string rel(const fs::path& p) const { return fs::relative(p, o_.outDir).string(); }
  const Expectation* expectedFor(const CaseState& c) const;
  void progress(const CaseState& c, CaseResult r);

  const RunOptions& o_;
  std::string goldenDir_;
  std::vector<Expectation> expectations_;
  std::map<std::string, BackendInfo> backends_;
  std::set<std::string> required_;  // required backends the run selects
  nlohmann::json manifest_;          // the golden folder's provenance, read once before the run
  std::map<std::string, std::string> faults_;
  std::map<std::string, std::string> scripts_;  // script name -> file
  std::vector<CaseState> cases_;
  nlohmann::json results_;
  nlohmann::json groups_ = nlohmann::json::array();
  std::mutex mutex_;
  double compareSeconds_ = 0;
  std::map<std::string, int> counts_;
  size_t done_ = 0, total_ = 0, skipped_ = 0;
  bool tty_ = false;
  std::chrono::steady_clock::time_point start_;
};

// Golden comparisons of each case (image, targets, diagnostics), the cross-backend groups, and
// the expectations applied to the verdicts.
class Comparisons : public MatrixState {
 public:
  using MatrixState::MatrixState;

 protected:
  CaseResult compareGolden(CaseState& c, const std::string& image, const nlohmann::json& worker, nlohmann::json* out,
                           std::string* reason);
  // The platform layer's diagnostics of the case's real targets and resolves reach the verdict:
  // an error-level one fails a case whose image passed, unless golden/expectations.json expects
  // its code for the case ({"case", "diagnostic", "reason"}): then the case is an ExpectedFail.
  // An expected diagnostic that no longer fires makes a passing case an UnexpectedPass. Each
  // diagnostic is kept in the case's golden comparison, marked with its expectation.
  CaseResult judgeDiagnostics(const CaseState& c, CaseResult r, const nlohmann::json& worker, nlohmann::json* golden,
                              std::string* reason) const;
  // Each target the child wrote against golden/<technique>/<scene>/<platform>/<file>, with the
  // metric of its kind; the first pass (in the technique's order) writing a differing target is
  // where the case starts to diverge.
  void compareTargets(CaseState& c, const nlohmann::json& worker, nlohmann::json* out);
  // GL↔Vulkan per group, the triangulated verdict, and ParityWarning; every pair of the
  // group's backends (comparePairs).
  void compareGroups();
  // Every pair of the rendered backends of a group (harness/run/matrix/pairs.cpp) into
  // g["pairs"], and the odd one out with its diagnosis into g["odd_one_out"]; `glVk` is the GL↔Vulkan
  // comparison already made, if any. Returns the verdict over the pairs.
  std::string comparePairs(const std::vector<CaseState*>& rendered, const DiffResult* glVk, nlohmann::json* g);
  // Both backends differ from the golden the same way: the golden is stale when it was made on
  // another driver than the one this run used; otherwise the technique changed.
  bool staleGolden(const CaseState& c) const;
  void applyExpectation(CaseState& c);
};

// The one backend of three or more whose image differs from every other while all the others
// agree with each other (`pairs` as comparePairs writes them); none when there is no such backend.
std::optional<std::string> oddOneOut(const std::vector<std::string>& backends, const nlohmann::json& pairs);

// Each case in a child process (rendered cases, scripts, external images), with retries of
// failures and the child's death read as a verdict.
class CaseAttempts : public Comparisons {
 public:
  using Comparisons::Comparisons;

 protected:
  void runAll(const std::vector<size_t>& list, bool rerun);
  // One case in a child of its own: a rendered case, a script or another program's images.
  void attempt(CaseState& c, bool rerun);
  // The first attempt of rendered cases of one backend (up to kCasesPerChild, see runAll): in
  // turn in one child and on one device (`run-case` with several cases), so that the process,
  // the device and Mesa's first-time costs are paid once instead of once per case. A case the child gave no line for (it
  // died, ran past the timeout or failed a render before that case) is attempted alone, as is
  // the last case when the child died after its line: a crash or a hang is still the result of
  // the case that caused it.
  void attemptPlatforms(const std::vector<CaseState*>& cases);
  // A rendered case's verdict: from its line of the child's output, or (none) from how the child ended.
  void finishRendered(CaseState& c, bool rerun, const ProcessResult& p, const nlohmann::json* line, double seconds);
  // The rendering child's command line, with the fault injected (--inject-fault) into one of
  // its cases, if any (runAll gives a child at most one).
  std::vector<std::string> renderArgs(const std::vector<CaseState*>& cases) const;
  // Where a rendered case's image is written: <case folder>/<backend>.png.
  std::string imagePath(const CaseKey& k) const;
  // A case whose backend is already known to be unavailable is finished as a Skip (true).
  bool backendUnavailable(CaseState& c, bool rerun);
  // Another program's render (harness/run/external_images.h): read instead of rendered, then judged
  // as a render is.
  void attemptExternal(CaseState& c, bool rerun);
  // A script case: `parity test --in-process` in a child, with the drivers' validation on as the
  // test suite runs scripts; its JSON line is the result. No image, no golden: the script's own
  // expectations are the verdict (*.expect_fail.amber applied here, never to a rule broken).
  void attemptScript(CaseState& c, bool rerun);
  // The first attempt of script cases on one backend: each script's platforms in turn, as
  // `parity test` runs a script, and up to kScriptsPerChild scripts one after the other, in one
  // child and on one device, which are paid once instead of once per case. A case the child gave
  // no line for (it died, or ran past the timeout, before that case) is attempted alone, so a
  // crash or a hang is still the result of the case that caused it.
  void attemptScriptPlatforms(const std::vector<CaseState*>& cases);
  // The script child's command line for these cases (one backend, the same platforms for each
  // script); an injected crash fault (--inject-fault) makes the child crash before that case's
  // platform of its first script (a script with a fault shares its child with no other script).
  std::vector<std::string> scriptArgs(const std::vector<CaseState*>& cases) const;
  // A script case's verdict from its line of the child's output.
  void finishScript(CaseState& c, bool rerun, const nlohmann::json& line, double seconds, const ProcessResult& p);
  // How a child that died (ProcessResult::died) ended, as the case's Crash or Timeout and its reason;
  // false for a child that exited.
  bool deathVerdict(const ProcessResult& p, CaseResult* r, std::string* reason) const;
  void finishAttempt(CaseState& c, bool rerun, CaseResult r, const std::string& reason, double seconds,
                     const ProcessResult& p, const nlohmann::json& worker, const nlohmann::json& golden, bool image);
};

// The whole run: cases enumerated, attempted on `jobs` workers, compared, reported.
class MatrixRun : public CaseAttempts {
 public:
  using CaseAttempts::CaseAttempts;
  int run();

 private:
  nlohmann::json caseJson(const CaseState& c) const;
};

}  // namespace parity::harness::matrix
