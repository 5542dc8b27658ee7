// Each case of a run in a child process, and what its exit means.
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

void CaseAttempts::runAll(const std::vector<size_t>& list, bool rerun) {
  // What each child does: one case, or on a first attempt up to kCasesPerChild rendered cases
  // of one backend, in the matrix's order (attemptPlatforms), or the platforms of one script on
  // one backend, then of several scripts (attemptScriptPlatforms).
  std::vector<std::vector<CaseState*>> work;
  std::map<std::tuple<std::string, std::string, std::string>, size_t> shared;  // the group being filled
  std::set<size_t> faulted;  // the groups with a case with an injected fault: one per child
  for (size_t n : list) {
    CaseState& c = cases_[n];
    const bool fault = faults_.count(c.key.id()) > 0;
    const bool script = c.key.technique == kScriptTechnique;
    const auto key = script ? std::make_tuple(c.key.technique, c.key.scene, c.key.backend)
                            : std::make_tuple(std::string(), std::string(), c.key.backend);
    auto it = shared.find(key);
    if (rerun || !o_.imagesDir.empty() || (fault && it != shared.end() && faulted.count(it->second))) {
      work.push_back({&c});
      continue;
    }
    if (it == shared.end() || (!script && work[it->second].size() == kCasesPerChild)) {
      it = shared.insert_or_assign(key, work.size()).first;
      work.emplace_back();
    }
    work[it->second].push_back(&c);
    if (fault) faulted.insert(it->second);
  }
  // Scripts are short: several share a child, kScriptsPerChild at most, when they run on the
  // same backend and platforms and none has a fault injected.
  std::vector<std::vector<CaseState*>> merged;
  std::map<std::string, size_t> open;  // backend and platforms -> the group of merged being filled
  std::map<size_t, size_t> scriptsIn;
  for (std::vector<CaseState*>& group : work) {
    const CaseKey& k = group.front()->key;
    const bool hasFault = std::any_of(group.begin(), group.end(), [&](const CaseState* c) { return faults_.count(c->key.id()) > 0; });
    if (k.technique != kScriptTechnique || rerun || !o_.imagesDir.empty() || hasFault) {
      merged.push_back(std::move(group));
      continue;
    }
    std::string signature = k.backend;
    for (const CaseState* c : group) signature += " " + c->key.platform;
    auto it = open.find(signature);
    if (it == open.end() || scriptsIn[it->second] == kScriptsPerChild) {
      it = open.insert_or_assign(signature, merged.size()).first;
      merged.emplace_back();
    }
    ++scriptsIn[it->second];
    merged[it->second].insert(merged[it->second].end(), group.begin(), group.end());
  }
  work = std::move(merged);
  std::atomic<size_t> next{0};
  auto worker = [&] {
    for (size_t n; (n = next.fetch_add(1)) < work.size();) {
      if (work[n].size() == 1) attempt(*work[n].front(), rerun);
      else if (work[n].front()->key.technique == kScriptTechnique) attemptScriptPlatforms(work[n]);
      else attemptPlatforms(work[n]);
    }
  };
  std::vector<std::thread> threads;
  int count = std::min<int>(jobs(), static_cast<int>(work.size()));
  for (int t = 0; t < count; ++t) threads.emplace_back(worker);
  for (auto& t : threads) t.join();
}

namespace {

// A rendering child's standard error by case (run.h: kCaseMarker); what came before the first
// case, under "".
std::map<std::string, std::string> stderrByCase(const std::string& err) {
  std::map<std::string, std::string> parts;
  std::string* part = &parts[""];
  std::istringstream in(err);
  for (std::string l; std::getline(in, l);) {
    if (l.rfind(kCaseMarker, 0) == 0) {
      part = &parts[l.substr(std::strlen(kCaseMarker))];
      continue;
    }
    *part += l + "\n";
  }
  return parts;
}

// The rendering child's lines by case id.
std::map<std::string, nlohmann::json> caseLines(const std::string& out) {
  std::map<std::string, nlohmann::json> lines;
  for (nlohmann::json& j : resultLines(out, "case")) {
    const std::string id = j["case"];
    lines[id] = std::move(j);
  }
  return lines;
}

}  // namespace

bool CaseAttempts::backendUnavailable(CaseState& c, bool rerun) {
  std::string unavailable;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto b = backends_.find(c.key.backend);
    if (b != backends_.end() && !b->second.available) unavailable = b->second.reason;
  }
  if (unavailable.empty()) return false;
  finishAttempt(c, rerun, CaseResult::Skip, "backend " + c.key.backend + " unavailable: " + unavailable,
                0, ProcessResult{}, nlohmann::json::object(), nlohmann::json::object(), false);
  return true;
}

std::vector<std::string> CaseAttempts::renderArgs(const std::vector<CaseState*>& cases) const {
  std::vector<std::string> args = {selfExecutable(), "run-case",   "--size",   o_.size,
                                   "--gl-provider",  o_.glProvider, "--repeat", std::to_string(o_.repeat)};
  for (const CaseState* c : cases) {
    std::error_code ec;
    fs::create_directories(caseDir(c->key), ec);
    args.insert(args.end(), {"--case", c->key.id(), "-o", imagePath(c->key)});
  }
  for (const CaseState* c : cases) {
    auto fault = faults_.find(c->key.id());
    if (fault == faults_.end()) continue;
    std::error_code ec;
    fs::create_directories(fs::path(o_.outDir) / ".faults", ec);
    std::string state = fault->first;
    std::replace(state.begin(), state.end(), '/', '.');
    args.insert(args.end(), {"--fault", fault->second, "--fault-case", fault->first, "--fault-state",
                             (fs::path(o_.outDir) / ".faults" / state).string()});
    break;  // one fault per child: a case with another is attempted alone (runAll)
  }
  return args;
}

std::string CaseAttempts::imagePath(const CaseKey& k) const { return (caseDir(k) / (k.backend + ".png")).string(); }

void CaseAttempts::attempt(CaseState& c, bool rerun) {
  if (!o_.imagesDir.empty()) return attemptExternal(c, rerun);
  if (c.key.technique == kScriptTechnique) return attemptScript(c, rerun);
  if (backendUnavailable(c, rerun)) return;
  auto start = std::chrono::steady_clock::now();
  ProcessResult p = runProcess(renderArgs({&c}), o_.timeout);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // A child that died is the case's verdict, even after its line (a crash while it exits).
  std::map<std::string, nlohmann::json> lines = caseLines(p.out);
  auto line = lines.find(c.key.id());
  finishRendered(c, rerun, p, line == lines.end() || p.died() ? nullptr : &line->second, seconds);
}

void CaseAttempts::attemptPlatforms(const std::vector<CaseState*>& cases) {
  std::vector<CaseState*> alone, batch;
  for (CaseState* c : cases)
    if (!backendUnavailable(*c, false)) batch.push_back(c);
  if (batch.empty()) return;
  auto start = std::chrono::steady_clock::now();
  // The timeout of one child: a batch renders in seconds, and one that runs past it (a hang, or
  // cases slow enough together) leaves its unreached cases to run alone, each with its own.
  ProcessResult p = runProcess(renderArgs(batch), o_.timeout);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::map<std::string, nlohmann::json> lines = caseLines(p.out);
  // A child that died after its last line: the last case is attempted again alone, so a crash on
  // the way out is still seen (as that case's, when it happens again).
  if (p.died()) lines.erase(batch.back()->key.id());
  // child_s: the child's time in equal shares (one process and device served them all); its
  // standard error: the case's own part, after what came before the first.
  std::map<std::string, std::string> err = stderrByCase(p.err);
  for (CaseState* c : batch) {
    auto line = lines.find(c->key.id());
    if (line == lines.end()) {
      alone.push_back(c);
      continue;
    }
    ProcessResult own = p;
    own.err = err[""] + err[c->key.id()];
    finishRendered(*c, false, own, &line->second, seconds / batch.size());
  }
  for (CaseState* c : alone) attempt(*c, false);
}

void CaseAttempts::finishRendered(CaseState& c, bool rerun, const ProcessResult& p, const nlohmann::json* line,
                                  double seconds) {
  CaseResult r;
  std::string reason;
  nlohmann::json worker = nlohmann::json::object(), golden = nlohmann::json::object();
  if (line && line->contains("error")) {
    r = CaseResult::Fail;
    reason = "render failed: " + oneLine(line->value("error", ""), kMessageChars);
  } else if (line) {
    worker = *line;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      BackendInfo& b = backends_[c.key.backend];
      if (!b.available || b.renderer.empty())  // a script case knows no device name
        b = {true, worker.value("renderer", ""), worker.value("driver", ""), worker.value("api", ""), ""};
    }
    if (!worker.value("deterministic", true)) {
      r = CaseResult::Nondeterministic;
      reason = std::to_string(worker.value("renders", 2)) + " renders in one process differ in " +
               std::to_string(worker.value("differing_bytes", 0)) + " bytes";
    } else {
      auto compareStart = std::chrono::steady_clock::now();
      r = compareGolden(c, imagePath(c.key), worker, &golden, &reason);
      r = judgeDiagnostics(c, r, worker, &golden, &reason);
      double compareS = std::chrono::duration<double>(std::chrono::steady_clock::now() - compareStart).count();
      std::lock_guard<std::mutex> lock(mutex_);
      compareSeconds_ += compareS;
    }
  } else if (deathVerdict(p, &r, &reason)) {
    // r and reason say how
  } else if (p.exitCode == kExitBackendUnavailable) {
    nlohmann::json said = nlohmann::json::parse(p.out, nullptr, false);
    std::string why = said.is_object() ? said.value("unavailable", "") : oneLine(p.err, kMessageChars);
    if (why.empty()) why = "the child gave no reason";
    r = CaseResult::Skip;
    reason = "backend " + c.key.backend + " unavailable: " + oneLine(why, kMessageChars);
    std::lock_guard<std::mutex> lock(mutex_);
    BackendInfo& b = backends_[c.key.backend];
    if (!b.available) b.reason = why;
  } else {
    r = CaseResult::Fail;
    reason = "render failed: " + (p.err.empty() ? "the child printed no result (exit " + std::to_string(p.exitCode) + ")"
                                                : oneLine(p.err, kMessageChars));
  }
  finishAttempt(c, rerun, r, reason, seconds, p, worker, golden, line != nullptr);
}

// Another program's render (harness/run/external_images.h): read instead of rendered, then judged
// as a render is.
void CaseAttempts::attemptExternal(CaseState& c, bool rerun) {
  const fs::path dir = caseDir(c.key);
  std::error_code ec;
  fs::create_directories(dir, ec);
  const std::string image = (dir / (c.key.backend + ".png")).string();
  nlohmann::json worker, golden = nlohmann::json::object();
  std::string reason;
  if (!loadExternalCase(o_.imagesDir, c.key, image, &worker, &reason))
    return finishAttempt(c, rerun, CaseResult::Fail, reason, 0, ProcessResult{}, nlohmann::json::object(), golden, false);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    BackendInfo& b = backends_[c.key.backend];
    if (!b.available) b = {true, worker.value("renderer", ""), worker.value("driver", ""), worker.value("api", ""), ""};
  }
  CaseResult r;
  if (!worker.value("deterministic", true)) {
    r = CaseResult::Nondeterministic;
    reason = "its two renders differ in " + std::to_string(worker.value("differing_pixels", 0)) + " pixels";
  } else {
    r = compareGolden(c, image, worker, &golden, &reason);
    r = judgeDiagnostics(c, r, worker, &golden, &reason);
  }
  finishAttempt(c, rerun, r, reason, 0, ProcessResult{}, worker, golden, true);
}

std::vector<std::string> CaseAttempts::scriptArgs(const std::vector<CaseState*>& cases) const {
  std::vector<std::string> args = {selfExecutable(), "test", "--in-process", "--debug", "--backend", cases.front()->key.backend};
  std::vector<std::string> platforms, scripts;
  auto addOnce = [](std::vector<std::string>& list, const std::string& v) {
    if (std::find(list.begin(), list.end(), v) == list.end()) list.push_back(v);
  };
  for (const CaseState* c : cases) {
    addOnce(platforms, c->key.platform);
    addOnce(scripts, scripts_.at(c->key.scene));
    auto fault = faults_.find(c->key.id());
    if (fault != faults_.end() && fault->second == "crash") args.insert(args.end(), {"--crash-on-platform", c->key.platform});
  }
  for (const std::string& p : platforms) args.insert(args.end(), {"--platform", p});
  args.push_back("--");  // the scripts: not more values of --platform
  args.insert(args.end(), scripts.begin(), scripts.end());
  return args;
}

// A script case: `parity test --in-process` in a child, with the drivers' validation on as the
// test suite runs scripts; its JSON line is the result. No image, no golden: the script's own
// expectations are the verdict (*.expect_fail.amber applied here, never to a rule broken).
void CaseAttempts::attemptScript(CaseState& c, bool rerun) {
  auto start = std::chrono::steady_clock::now();
  ProcessResult p = runProcess(scriptArgs({&c}), o_.timeout);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CaseResult r = CaseResult::Fail;
  std::string reason;
  const std::vector<nlohmann::json> lines = resultLines(p.out, "result");
  if (deathVerdict(p, &r, &reason)) {
    // r and reason say how
  } else if (lines.empty()) {
    reason = "the script's child printed no result (exit " + std::to_string(p.exitCode) + "): " + oneLine(p.err, kMessageChars);
  } else {
    return finishScript(c, rerun, lines.front(), seconds, p);
  }
  finishAttempt(c, rerun, r, reason, seconds, p, nlohmann::json::object(), nlohmann::json::object(), false);
}

void CaseAttempts::attemptScriptPlatforms(const std::vector<CaseState*>& cases) {
  auto start = std::chrono::steady_clock::now();
  ProcessResult p = runProcess(scriptArgs(cases), o_.timeout);  // as attemptPlatforms
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::map<std::pair<std::string, std::string>, nlohmann::json> byCase;  // (script file, platform)
  for (nlohmann::json& line : resultLines(p.out, "result")) {
    std::pair<std::string, std::string> key{line.value("script", ""), line.value("platform", "")};
    byCase.emplace(std::move(key), std::move(line));
  }
  // child_s: the child's time in equal shares (one process and device served them all).
  std::vector<CaseState*> alone;
  for (CaseState* c : cases) {
    auto it = byCase.find({scripts_.at(c->key.scene), c->key.platform});
    if (it == byCase.end()) alone.push_back(c);
    else finishScript(*c, false, it->second, seconds / cases.size(), p);
  }
  for (CaseState* c : alone) attemptScript(*c, false);
}

void CaseAttempts::finishScript(CaseState& c, bool rerun, const nlohmann::json& line, double seconds,
                                const ProcessResult& p) {
  const std::string& path = scripts_.at(c.key.scene);
  script::RunResult s;
  std::string v = line["result"];
  s.verdict = script::verdictFromName(v);
  s.reason = line.value("reason", "");
  s = script::applyExpectFail(s, script::isExpectFail(path) && !line.value("invalid", false));
  CaseResult r = s.verdict == script::Verdict::Pass ? CaseResult::Pass
                 : s.verdict == script::Verdict::Skip ? CaseResult::Skip
                                                      : CaseResult::Fail;
  nlohmann::json worker = {{"script", path}, {"expects", line.value("expects", nlohmann::json::array())}};
  if (line.contains("render_ms")) worker["render_ms"] = line["render_ms"];
  for (const char* phase : kChildPhases)
    if (line.contains(phase)) worker[phase] = line[phase];
  {
    // The script's child had a device unless it says its backend is unavailable: that is what
    // the exit policy's required backends are judged on in a run of scripts alone.
    const std::string unavailable = "backend " + c.key.backend + " unavailable";
    std::lock_guard<std::mutex> lock(mutex_);
    BackendInfo& b = backends_[c.key.backend];
    const std::string said = line.value("reason", "");
    if (v == "SKIP" && said.rfind(unavailable, 0) == 0) {
      // The driver's own words, as a technique case's child gives them.
      if (!b.available) b.reason = said.size() > unavailable.size() + 2 ? said.substr(unavailable.size() + 2) : said;
    } else {
      b.available = true;
    }
  }
  finishAttempt(c, rerun, r, oneLine(s.reason, kMessageChars), seconds, p, worker, nlohmann::json::object(), false);
}

bool CaseAttempts::deathVerdict(const ProcessResult& p, CaseResult* r, std::string* reason) const {
  if (!p.died()) return false;
  if (!p.startError.empty()) {
    *r = CaseResult::Crash;
    *reason = "cannot start the child process: " + p.startError;
  } else if (p.timedOut) {
    *r = CaseResult::Timeout;
    *reason = "no result after " + std::to_string(static_cast<int>(o_.timeout)) + " s; the child was killed";
  } else {
    *r = CaseResult::Crash;
    *reason = "the child died from signal " + std::to_string(p.signal) + " (" + strsignal(p.signal) + ")";
  }
  return true;
}

void CaseAttempts::finishAttempt(CaseState& c, bool rerun, CaseResult r, const std::string& reason, double seconds,
                                 const ProcessResult& p, const nlohmann::json& worker, const nlohmann::json& golden, bool image) {
  std::lock_guard<std::mutex> lock(mutex_);
  c.childSeconds += seconds;
  c.attempts.push_back({{"result", resultName(r)}, {"seconds", seconds}, {"reason", reason}});
  if (!p.err.empty()) c.stderrText = oneLine(p.err, kMessageChars);
  if (!worker.empty()) {
    c.worker = worker;
    c.rendered = image;
    if (image)  // the device the child rendered with; a script case keeps the probed one
      c.device = {{"renderer", worker.value("renderer", "")}, {"driver", worker.value("driver", "")},
                  {"api", worker.value("api", "")}};
  }
  c.golden = golden;
  if (rerun && r == CaseResult::Pass) {
    c.result = c.raw = CaseResult::Flake;
    c.reason = "failed first (" + c.reason + "), passed on rerun " + std::to_string(c.attempts.size() - 1);
  } else if (!rerun || c.result != CaseResult::Flake) {
    c.raw = c.result = r;
    c.reason = reason;
  }
  ++done_;
  progress(c, r);
}

}  // namespace parity::harness::matrix
