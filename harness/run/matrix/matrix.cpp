// The whole run (`parity run`): enumerate, attempt, compare, report.
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
#include "harness/run/baseline.h"
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

int MatrixRun::run() {
  auto wallStart = std::chrono::steady_clock::now();
  std::string error;
  std::vector<CaseKey> keys = o_.imagesDir.empty() ? enumerateCases(o_.filters, o_.shard, &error)
                                                   : enumerateImageCases(o_.imagesDir, o_.filters, o_.shard, &error);
  if (!error.empty()) return reportError(error);
  std::set<std::string> selected;
  for (const CaseKey& k : keys) selected.insert(k.backend);
  // A device the user named is one the run must have run on.
  for (const std::string& d : o_.filters.devices)
    if (selected.count(d)) required_.insert(d);
  for (const std::string& b : o_.requireBackends) {
    if (b != "gl" && b != "vk") return reportError("required backend '" + b + "' is not a backend (gl, vk)");
    if (selected.count(b)) required_.insert(b);
    else if (o_.requireBackendsFromCommandLine && !keys.empty())
      return reportError("--require-backends " + b + ": the run selects no " + b + " case");
  }
  goldenDir_ = o_.goldenDir.empty() ? defaultGoldenDir() : o_.goldenDir;
  std::string expFile = o_.expectationsFile.empty() ? (fs::path(goldenDir_) / "expectations.json").string() : o_.expectationsFile;
  std::string tolFile = o_.tolerancesFile.empty() ? (fs::path(goldenDir_) / "tolerances.json").string() : o_.tolerancesFile;
  // Both files are checked whole before the output folder exists: a bad file fails the run
  // with nothing written, rather than after cases have rendered.
  if (!loadExpectations(expFile, &expectations_, &error)) return reportError(error);
  if (!checkTolerancesFile(tolFile, &error)) return reportError(error);
  if (!readManifest(goldenDir_, &manifest_, &error)) return reportError(error);
  nlohmann::json baseline;
  if (!o_.baselineDir.empty() && !loadBaseline(o_.baselineDir, &baseline, &error)) return reportError(error);
  uint32_t w, h;
  if (!parseSize(o_.size, &w, &h, &error)) return reportError(error);
  static const std::set<std::string> kFaultKinds = {"crash", "abort", "oom", "hang", "fail", "flaky",
                                                    "nondeterministic", "perturb", "subtle", "perturb-target"};
  for (const std::string& f : o_.faults) {
    size_t eq = f.find('=');
    if (eq == std::string::npos || !kFaultKinds.count(f.substr(eq + 1)))
      return reportError("fault '" + f + "' is not CASE=KIND (KIND: crash, abort, oom, hang, fail, flaky, "
                         "nondeterministic, perturb, subtle, perturb-target)");
    faults_[f.substr(0, eq)] = f.substr(eq + 1);
  }
  std::error_code ec;
  fs::create_directories(fs::path(o_.outDir) / "cases", ec);
  if (ec) return reportError(o_.outDir + ": cannot create output folder: " + ec.message());

  results_["schema"] = "parity-results/1";
  results_["started"] = nowIso();
  results_["run_id"] = results_["started"].get<std::string>() + "-" + std::to_string(::getpid());
  results_["project_commit"] = projectCommit();
  results_["size"] = o_.size;
  results_["gl_provider"] = o_.glProvider;
  results_["repeat"] = o_.repeat;
  results_["retries"] = o_.retries;
  results_["shard"] = std::to_string(o_.shard.index) + "/" + std::to_string(o_.shard.count);
  results_["golden_dir"] = goldenDir_;
  if (!o_.imagesDir.empty()) results_["images_dir"] = o_.imagesDir;
  results_["expectations_file"] = expFile;
  results_["policy"] = {{"require_backends", std::vector<std::string>(required_.begin(), required_.end())},
                        {"strict", o_.strict}};

  // No probe: every child creates its own device, and one that cannot says so
  // (kExitBackendUnavailable): its case is a Skip with the driver's reason, and the backend's
  // later cases skip without a child. A probe process per run would double the cost of a
  // one-case run, which is what each CTest case is. The devices the children rendered with are
  // the run's record of its backends (results.json "backends").
  if (std::any_of(keys.begin(), keys.end(), [](const CaseKey& k) { return k.technique == kScriptTechnique; }) &&
      !scriptsByName(o_.filters, &scripts_, &error))
    return reportError(error);
  cases_.resize(keys.size());
  std::vector<size_t> todo;
  for (size_t i = 0; i < keys.size(); ++i) {
    CaseState& c = cases_[i];
    c.key = keys[i];
    if (!loadTolerance(tolFile, c.key, &c.tolerance, &error)) return reportError(error);
    todo.push_back(i);
  }
  total_ = todo.size() + 0;
  skipped_ = keys.size() - todo.size();
  tty_ = o_.progress && ::isatty(1);
  start_ = std::chrono::steady_clock::now();
  std::printf("parity run: %zu cases (%zu to render, %zu skipped), %d jobs, out %s\n", keys.size(), todo.size(), skipped_,
              jobs(), o_.outDir.c_str());
  std::fflush(stdout);

  // First attempt of every case.
  runAll(todo, false);
  // Unexpected failures again, to tell flakes from failures (another program's images are
  // what they are: read again, they would only fail again).
  const int retries = o_.imagesDir.empty() ? o_.retries : 0;
  for (int attempt = 0; attempt < retries; ++attempt) {
    std::vector<size_t> again;
    for (size_t i : todo) {
      CaseState& c = cases_[i];
      // A missing golden stays missing: no rerun.
      bool retriable = (c.raw == CaseResult::Fail && !c.golden.value("missing", false)) || c.raw == CaseResult::Crash ||
                       c.raw == CaseResult::Timeout;
      if (retriable && !expectedFor(c) && c.result != CaseResult::Flake) again.push_back(i);
    }
    if (again.empty()) break;
    total_ += again.size();
    runAll(again, true);
  }
  if (tty_) std::printf("\r\033[K");
  for (const auto& [name, b] : backends_) {
    nlohmann::json e{{"name", name}, {"available", b.available}};
    if (b.available) e.update({{"renderer", b.renderer}, {"driver", b.driver}, {"api", b.api}});
    else e["reason"] = oneLine(b.reason, kMessageChars);
    results_["backends"].push_back(e);
  }
  // A script's child reports no device, nor does a child that died before it rendered: the one
  // its backend's other cases rendered with (so that an expected crash on one driver can name it).
  for (CaseState& c : cases_) {
    auto b = backends_.find(c.key.backend);
    if ((c.key.technique == kScriptTechnique || c.device.empty()) && b != backends_.end() && b->second.available)
      c.device = {{"renderer", b->second.renderer}, {"driver", b->second.driver}, {"api", b->second.api}};
  }

  auto groupsStart = std::chrono::steady_clock::now();
  compareGroups();
  for (CaseState& c : cases_) applyExpectation(c);
  compareSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - groupsStart).count();

  double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
  double renderS = 0, childS = 0;
  std::map<std::string, double> phaseSeconds;  // "setup_s", ... from kChildPhases
  for (const CaseState& c : cases_) {
    childS += c.childSeconds;
    for (const auto& ms : c.worker.value("render_ms", nlohmann::json::array())) renderS += ms.get<double>() / 1000.0;
    for (const std::string phase : kChildPhases)
      phaseSeconds[phase.substr(0, phase.size() - 3) + "_s"] += c.worker.value(phase, 0.0) / 1000.0;
  }
  results_["finished"] = nowIso();
  // render_s: the children's renders (device work, shader compilation, readback). The rest of
  // child_process_s, from the children's own clocks: setup_s (arguments, the scene), device_s
  // (device creation), write_s (the image and targets written, the JSON made); what is left of
  // child_process_s beyond worker_s is the processes' start and exit. compare_s: the parent's
  // comparisons (idiff statistics, FLIP, targets, diagnosis, GL vs Vulkan), summed over threads.
  results_["timing"] = {{"wall_s", wall},         {"child_process_s", childS}, {"render_s", renderS},
                        {"compare_s", compareSeconds_}, {"jobs", jobs()}};
  for (const auto& [field, seconds] : phaseSeconds) results_["timing"][field] = seconds;
  for (CaseState& c : cases_) results_["cases"].push_back(caseJson(c));
  results_["groups"] = groups_;
  // Expired entries that cover a case of this run (a shard or a --case run answers for its own).
  results_["expired_expectations"] = nlohmann::json::array();
  for (const Expectation& e : expectations_)
    if (e.expired && std::any_of(cases_.begin(), cases_.end(),
                                 [&](const CaseState& c) { return globMatch(e.casePattern, c.key.id()); }))
      results_["expired_expectations"].push_back(toJson(e));
  // Required backends that no case could render with.
  std::vector<std::pair<std::string, std::string>> unmet;
  for (const std::string& b : required_) {
    auto it = backends_.find(b);
    if (it == backends_.end() || !it->second.available)
      unmet.push_back({b, it == backends_.end() ? "no case of it rendered" : oneLine(it->second.reason, kMessageChars)});
  }
  for (const auto& [b, why] : unmet) results_["policy"]["unavailable"][b] = why;
  if (!o_.baselineDir.empty()) results_["baseline"] = compareWithBaseline(o_.baselineDir, baseline, results_);
  if (!writeReports(o_.outDir, results_, &error)) return reportError(error);

  std::map<std::string, int> counts;
  bool bad = !unmet.empty();
  for (const CaseState& c : cases_) {
    counts[resultName(c.result)]++;
    bad = bad || isBadResult(c.result, o_.strict);
  }
  std::string line;
  for (const auto& [name, n] : counts) line += (line.empty() ? "" : ", ") + std::to_string(n) + " " + name;
  const nlohmann::json& expired = results_["expired_expectations"];
  if (!expired.empty()) line += ", " + std::to_string(expired.size()) + " expired expectation" + (expired.size() == 1 ? "" : "s");
  bad = bad || (o_.strict && !expired.empty());
  for (const nlohmann::json& e : expired)
    std::fprintf(stderr, "parity run: %s: expectation for %s expired on %s (%s%s): renew its date or remove it\n",
                 o_.strict ? "FAILED" : "note", e["case"].get<std::string>().c_str(), e["expires"].get<std::string>().c_str(),
                 e["reason"].get<std::string>().c_str(), e.contains("bug") ? ("; bug " + e["bug"].get<std::string>()).c_str() : "");
  std::string policy;
  for (const std::string& b : required_) policy += (policy.empty() ? "require " : ",") + b;
  if (o_.strict) policy += (policy.empty() ? "" : "; ") + std::string("strict");
  const std::string against = results_.contains("baseline") ? "; " + baselineSummary(results_["baseline"]) : "";
  std::printf("parity run: %s in %s (rendering %.1f s of %.1f s in child processes; policy: %s)%s; report %s\n",
              line.c_str(), fmtDuration(wall).c_str(), renderS, childS, policy.empty() ? "default" : policy.c_str(),
              against.c_str(), (fs::path(o_.outDir) / "report" / "index.html").c_str());
  if (results_.contains("baseline")) printBaselineChanges("parity run", results_["baseline"]);
  for (const auto& [b, why] : unmet)
    std::printf("parity run: FAILED: required backend %s unavailable: %s\n", b.c_str(), why.c_str());
  // The backend whose image differs from all the others of its group, which agree.
  for (const nlohmann::json& g : groups_)
    if (g.contains("odd_one_out"))
      std::printf("parity run: %s: odd one out %s: %s\n", g["group"].get<std::string>().c_str(),
                  g["odd_one_out"]["backend"].get<std::string>().c_str(), g["verdict"].get<std::string>().c_str());
  if (unmet.empty() && !o_.filters.cases.empty() && !cases_.empty() &&
      std::all_of(cases_.begin(), cases_.end(), [](const CaseState& c) { return c.result == CaseResult::Skip; }))
    return 77;  // CTest's SKIP_RETURN_CODE
  return bad ? 2 : 0;
}

nlohmann::json MatrixRun::caseJson(const CaseState& c) const {
  nlohmann::json j{{"id", c.key.id()},          {"technique", c.key.technique}, {"scene", c.key.scene},
                   {"platform", c.key.platform}, {"backend", c.key.backend},     {"result", resultName(c.result)}};
  if (!c.reason.empty()) j["reason"] = c.reason;
  if (c.rendered) {
    j["image"] = rel(caseDir(c.key) / (c.key.backend + ".png"));
    j["deterministic"] = c.worker.value("deterministic", false);
  }
  // Where the child's time went (case_worker.cpp, and a script child's line).
  if (c.worker.contains("render_ms")) j["render_ms"] = c.worker["render_ms"];
  for (const char* phase : kChildPhases)
    if (c.worker.contains(phase)) j[phase] = c.worker[phase];
  // The device it ran on: the backend's default ("gl", "vk") or one named with --devices.
  j["device"] = c.key.backend;
  if (!c.device.empty()) j.update(c.device);
  if (!c.golden.empty()) j["golden"] = c.golden;
  if (c.golden.contains("targets")) j["targets"] = c.golden["targets"];
  if (c.worker.contains("passes")) j["passes"] = c.worker["passes"];
  if (c.worker.contains("pass_ms")) j["pass_ms"] = c.worker["pass_ms"];
  if (c.worker.contains("lost_light")) j["lost_light"] = c.worker["lost_light"];
  if (c.worker.contains("port_paths")) j["port_paths"] = c.worker["port_paths"];
  if (c.worker.contains("script")) j["script"] = c.worker["script"];
  if (c.worker.contains("external")) j["external"] = c.worker["external"];
  if (c.worker.contains("expects")) j["expects"] = c.worker["expects"];
  if (!c.attempts.empty()) j["attempts"] = c.attempts;
  if (!c.stderrText.empty()) j["stderr"] = c.stderrText;
  if (!c.expectation.empty()) {
    j["expectation"] = {{"result", c.expected}, {"reason", c.expectation}};
    if (c.expectationEntry && !c.expectationEntry->bug.empty()) j["expectation"]["bug"] = c.expectationEntry->bug;
    if (c.expectationEntry && !c.expectationEntry->expires.empty())
      j["expectation"].update({{"expires", c.expectationEntry->expires}, {"expired", c.expectationEntry->expired}});
  }
  j["child_s"] = c.childSeconds;
  return j;
}

}  // namespace parity::harness::matrix

namespace parity::harness {

int runMatrix(const RunOptions& options) {
  matrix::MatrixRun run(options);
  return run.run();
}

}  // namespace parity::harness
