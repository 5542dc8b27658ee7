// `parity test FILE|DIR ... [--backend gl|vk ...] [--platform P ...] [--json]`: runs shader-test
// scripts (docs/script-format.md) on every backend x platform. Scripts run in child processes,
// several to a child on one backend (`parity test --in-process --backend X --platform P... --
// FILE...`, one device for them all), so GL and Vulkan never share a process and a crash or a
// hang becomes a result (runOnBackend).
// Files named *.expect_fail.amber must fail.
#include <nlohmann/json.hpp>

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "harness/cli/commands.h"
#include "harness/io/text.h"
#include "harness/run/devices.h"
#include "harness/run/process.h"
#include "harness/scripts/script.h"
#include "harness/scripts/runner.h"
#include "platforms/common/platform.h"
#include "rhi/rhi.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

// A note carries the translator's error and often the GLSL it generated: one line, cut.
constexpr size_t kNoteChars = 400, kJsonNoteChars = 2000;

struct TestOptions {
  std::vector<std::string> paths;
  std::vector<std::string> backends;
  std::vector<std::string> platforms;  // empty: every platform a script allows
  bool json = false;
  bool inProcess = false;
  bool debug = false;  // driver validation: GL debug context, Vulkan validation layer
  // Tests only: SIGSEGV before that platform of every script, or of crashOnScript's alone (`parity
  // run --inject-fault script/...=crash`; `parity test` passes both to the child that runs it).
  std::string crashOnPlatform, crashOnScript;
  double timeout = 120;
};

// One check's line, outcome and message; "warn" where its failure is piglit's warn.
nlohmann::json expectJson(const script::ExpectResult& e) {
  nlohmann::json j{{"line", e.line}, {"pass", e.pass}, {"message", e.message}};
  if (e.warning) j["warn"] = true;
  return j;
}

// `invalid`: the script broke an RHI or driver rule. Such a failure is never the one an
// *.expect_fail script expects.
nlohmann::json resultJson(const script::RunResult& r, const std::string& platform, bool invalid) {
  nlohmann::json j{{"platform", platform}, {"result", script::verdictName(r.verdict)}, {"reason", r.reason}};
  if (invalid) j["invalid"] = true;
  j["expects"] = nlohmann::json::array();
  for (const auto& e : r.expects) j["expects"].push_back(expectJson(e));
  if (!r.notes.empty()) j["notes"] = r.notes;
  return j;
}

// Child: scripts in turn on one backend and one or more platforms, sharing one device; prints
// one JSON object per script and platform ("script", "platform"), each on its own line, as soon
// as it is known. The *.expect_fail rule is applied by the parent.
int runInProcess(const TestOptions& o) {
  using Clock = std::chrono::steady_clock;
  auto msSince = [](Clock::time_point start) { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); };
  const Clock::time_point workerStart = Clock::now();
  if (o.paths.empty() || o.backends.size() != 1 || o.platforms.empty())
    return reportError("--in-process takes one or more scripts, one --backend and at least one --platform");
  // Two devices at most: piglit's files run in a compatibility context (script::compatibilityProfile).
  std::unique_ptr<rhi::Device> devices[2];
  std::string deviceErrors[2];
  // On a backend whose driver compiles no OpenGL GLSL, the GL driver judges the OpenGL GLSL that
  // glslang cannot port (script::RunOptions::openGlCompiler), made the first time it is asked.
  std::unique_ptr<rhi::Device> openGlCompilers[2];
  bool openGlCompilerTried[2] = {false, false};
  std::vector<std::string> validation, driver;
  bool anyFail = false;
  for (const std::string& path : o.paths) {
    // The first script's time since the process began, every other's since its parse began.
    const Clock::time_point scriptStart = path == o.paths.front() ? workerStart : Clock::now();
    script::ParseResult parsed = script::parseScriptFile(path);
    for (const std::string& platform : o.platforms) {
      if (platform == o.crashOnPlatform && (o.crashOnScript.empty() || path == o.crashOnScript)) ::raise(SIGSEGV);
      const Clock::time_point platformStart = Clock::now();
      double deviceMs = 0, renderMs = 0;
      script::RunResult r;
      bool invalid = false;
      script::RunOptions ro;
      ro.platform = platform;
      if (!parsed.ok) {
        r = {script::Verdict::Fail, parsed.error, {}};
      } else if (std::string why = script::skipReasonBeforeRun(parsed.script, backendOfDevice(o.backends[0]), ro); !why.empty()) {
        r = {script::Verdict::Skip, why, {}};
      } else {
        const bool compatibility = script::compatibilityProfile(parsed.script);
        std::unique_ptr<rhi::Device>& dev = devices[compatibility];
        std::string& deviceError = deviceErrors[compatibility];
        // One GL device a process (rhi.h): GL calls go to the context made current last, the
        // newest device's, so the other profile's device goes before this one is made.
        if (!dev && deviceError.empty() && devices[!compatibility] && devices[!compatibility]->info().backend == "gl")
          devices[!compatibility].reset();
        if (!dev && deviceError.empty()) {
          rhi::DeviceDesc desc;
          if (!resolveDevice(o.backends[0], &desc, &deviceError)) desc.backend.clear();
          desc.glCompatibilityProfile = compatibility;
          desc.onValidationError = [&validation](const std::string& id, const std::string& msg) {
            validation.push_back(id + ": " + msg);
            std::fprintf(stderr, "parity: validation: %s: %s\n", id.c_str(), msg.c_str());
          };
          desc.debug = o.debug;
          desc.log = [&driver](const std::string& msg) {
            driver.push_back(msg);
            std::fprintf(stderr, "parity: driver validation: %s\n", msg.c_str());
          };
          const Clock::time_point deviceStart = Clock::now();
          if (!desc.backend.empty()) dev = rhi::createDevice(desc, &deviceError);
          deviceMs = msSince(deviceStart);
          if (!dev && deviceError.empty()) deviceError = "no device";
        }
        if (!dev) {
          r = {script::Verdict::Skip, "backend " + o.backends[0] + " unavailable: " + deviceError, {}};
        } else {
          validation.clear();
          driver.clear();
          const Clock::time_point runStart = Clock::now();
          if (dev->info().backend != "gl")
            ro.openGlCompiler = [&openGlCompilers, &openGlCompilerTried, compatibility]() -> rhi::Device* {
              if (!std::exchange(openGlCompilerTried[compatibility], true)) {
                rhi::DeviceDesc desc;
                desc.backend = "gl";
                desc.glCompatibilityProfile = compatibility;
                std::string error;
                openGlCompilers[compatibility] = rhi::createDevice(desc, &error);
              }
              return openGlCompilers[compatibility].get();
            };
          r = script::runScript(parsed.script, *dev, ro);
          renderMs = msSince(runStart);
          for (std::string& note : dev->takeNotes()) r.notes.push_back(std::move(note));
          std::string broken = !validation.empty() ? "RHI validation: " + validation.front()
                               : !driver.empty()   ? "driver validation: " + oneLine(driver.front())
                                                   : "";
          if (!broken.empty() && r.verdict == script::Verdict::Pass) {
            r.verdict = script::Verdict::Fail;
            r.reason = broken;
          } else if (!broken.empty() && r.verdict == script::Verdict::Fail) {
            r.reason += " (" + broken + ")";
          }
          invalid = !broken.empty();
        }
      }
      anyFail |= r.verdict == script::Verdict::Fail;
      // Where the child's time went, as a technique case's child reports it (harness/run/case_worker.cpp):
      // the script's commands are its rendering; a script's first platform's line also carries the parse.
      const bool first = platform == o.platforms.front();
      nlohmann::json j = resultJson(r, platform, invalid);
      j["script"] = path;
      j["render_ms"] = {renderMs};
      j["device_ms"] = deviceMs;
      j["setup_ms"] = first ? std::chrono::duration<double, std::milli>(platformStart - scriptStart).count() : 0.0;
      j["worker_ms"] = msSince(first ? scriptStart : platformStart);
      std::cout << j.dump() << std::endl;
    }
  }
  return anyFail ? 1 : 0;
}

std::vector<std::string> kAllPlatforms() { return {"reference", "dx10", "ps3", "x360"}; }

// Scripts that share a child on one backend. Measured on 60 VK-GL-CTS files here: one child
// each took 4.6 s (GL) and 3.8 s (Vulkan), one child for all 1.1 and 1.3 s; the rest is each
// child's start and device. Few enough that the output comes in steady steps. (`parity run`
// gives a child 8, matrix::kScriptsPerChild, under one timeout for the whole child.)
constexpr size_t kScriptsPerChild = 16;

// One script's verdicts, as the parent gathers them before it records them in order.
struct Outcome {
  std::string platform;
  script::RunResult result;
  bool mustFail = false;  // the *.expect_fail rule applies (never to a crash or a broken rule)
  double deviceMs = 0;    // the child created its device for this run (--json: device_ms)
};
struct ScriptRuns {
  std::string path;
  bool mustFail = false;
  std::map<std::string, std::vector<Outcome>> outcomes;   // by backend, in the order they are recorded
  std::map<std::string, std::vector<std::string>> toRun;  // by backend: the platforms a child has still to run
};

// A child's result lines (resultJson) by script and platform.
std::map<std::pair<std::string, std::string>, nlohmann::json> childLines(const std::string& out) {
  std::map<std::pair<std::string, std::string>, nlohmann::json> lines;
  for (nlohmann::json& j : resultLines(out, "result"))
    if (j.contains("script") && j["script"].is_string() && j.contains("platform") && j["platform"].is_string()) {
      std::pair<std::string, std::string> key{j["script"], j["platform"]};  // before j is moved
      lines[std::move(key)] = std::move(j);
    }
  return lines;
}

// The run a child's line reports, as the parent records it.
Outcome outcomeOf(const std::string& platform, const nlohmann::json& line, bool mustFail) {
  Outcome o{platform, {}, false, 0};
  try {
    o.result.verdict = script::verdictFromName(line.value("result", ""));
    o.result.reason = line.value("reason", "");
    for (const auto& e : line.value("expects", nlohmann::json::array()))
      o.result.expects.push_back({e.value("line", 0), e.value("pass", false), e.value("message", ""), e.value("warn", false)});
    o.result.notes = line.value("notes", std::vector<std::string>{});
    o.mustFail = mustFail && !line.value("invalid", false);
    o.deviceMs = line.value("device_ms", 0.0);
  } catch (const nlohmann::json::exception& e) {
    o.result = {script::Verdict::Fail, std::string("the child's result line is unreadable: ") + e.what(), {}};
  }
  return o;
}

// Runs the platforms the scripts have still to run on `backend`, up to kScriptsPerChild scripts
// in a child, one after the other. The child prints a line per script and platform as it
// finishes it, and the timeout is on each line, so a batch may take as long as its scripts need.
// A child that dies leaves the scripts after the one it was running to the next child; that one
// is the verdict's: a hang is its timeout at once (a rerun would wait as long again), a crash is
// attempted again alone, so what it records is the script's own doing.
void runOnBackend(const TestOptions& o, const std::string& backend, const std::vector<ScriptRuns*>& scripts) {
  std::deque<ScriptRuns*> pending;
  for (ScriptRuns* s : scripts)
    if (!s->toRun[backend].empty()) pending.push_back(s);
  std::string crashedBeside;  // how the last batch died: its culprit is attempted alone
  while (!pending.empty()) {
    const size_t batch = crashedBeside.empty() ? kScriptsPerChild : 1;
    const std::vector<ScriptRuns*> child(pending.begin(), pending.begin() + std::min(batch, pending.size()));
    std::vector<std::string> args = {selfExecutable(), "test", "--in-process", "--backend", backend};
    if (o.debug) args.push_back("--debug");
    std::vector<std::string> platforms;  // each script's child skips the ones it does not run, as the parent did
    for (const std::string& p : kAllPlatforms())
      for (const ScriptRuns* s : child) {
        const std::vector<std::string>& run = s->toRun.at(backend);
        if (std::find(run.begin(), run.end(), p) != run.end()) {
          platforms.push_back(p);
          break;
        }
      }
    for (const std::string& p : platforms) args.insert(args.end(), {"--platform", p});
    for (const ScriptRuns* s : child)
      if (s->path == o.crashOnScript) args.insert(args.end(), {"--crash-on-script", s->path, "--crash-on-platform", o.crashOnPlatform});
    args.push_back("--");  // the scripts: not more values of --platform
    for (const ScriptRuns* s : child) args.push_back(s->path);
    ProcessResult p = runProcess(args, o.timeout, TimeoutScope::EachLine);
    std::map<std::pair<std::string, std::string>, nlohmann::json> got = childLines(p.out);
    // A child that died after every line died of its last script (a crash at exit, say): that
    // script is not done.
    const bool allLines = std::all_of(child.begin(), child.end(), [&](const ScriptRuns* s) {
      const std::vector<std::string>& run = s->toRun.at(backend);
      return std::all_of(run.begin(), run.end(), [&](const std::string& platform) { return got.count({s->path, platform}) > 0; });
    });
    if (p.died() && allLines) std::erase_if(got, [&](const auto& g) { return g.first.first == child.back()->path; });
    ScriptRuns* culprit = nullptr;  // the first script left without all its lines
    for (ScriptRuns* s : child) {
      std::vector<std::string> missing;
      for (const std::string& platform : s->toRun[backend]) {
        auto it = got.find({s->path, platform});
        if (it == got.end()) {
          missing.push_back(platform);
          continue;
        }
        Outcome outcome = outcomeOf(platform, it->second, s->mustFail);
        if (!crashedBeside.empty()) outcome.result.notes.push_back(crashedBeside);
        s->outcomes[backend].push_back(std::move(outcome));
      }
      s->toRun[backend] = missing;
      if (!missing.empty()) {
        culprit = s;
        break;
      }
      pending.pop_front();
    }
    crashedBeside.clear();
    if (!culprit) continue;
    if (p.crashed && child.size() > 1) {
      crashedBeside = "its child, running it after other scripts, crashed (signal " + std::to_string(p.signal) + "); run alone, it did not";
      continue;
    }
    const std::string why = p.timedOut              ? "timed out after " + std::to_string(static_cast<int>(o.timeout)) + " s"
                            : p.crashed             ? "crashed (signal " + std::to_string(p.signal) + ")"
                            : !p.startError.empty() ? "cannot start: " + p.startError
                                                    : "child printed no result (exit " + std::to_string(p.exitCode) + "): " + oneLine(p.err);
    // A crash or a hang is never an expected failure.
    for (const std::string& platform : culprit->toRun[backend])
      culprit->outcomes[backend].push_back({platform, {script::Verdict::Fail, why, {}}, false});
    culprit->toRun[backend].clear();
    pending.pop_front();
  }
}

int runTests(const TestOptions& o) {
  for (const std::string& p : o.platforms)
    if (p != "all" && !platforms::platformFromName(p))
      return reportError("--platform " + p + ": unknown platform (reference, dx10, ps3, x360, all)");
  std::vector<std::string> requested;
  for (const std::string& p : o.platforms) {
    if (p == "all") requested = kAllPlatforms();
    else if (std::find(requested.begin(), requested.end(), p) == requested.end()) requested.push_back(p);
  }
  if (o.inProcess) {
    TestOptions child = o;
    child.platforms = requested;
    return runInProcess(child);
  }
  if (requested.empty()) requested = kAllPlatforms();
  std::string error;
  std::vector<std::string> scripts = script::collectScripts(o.paths, &error);
  if (!error.empty()) return reportError(error);
  std::vector<std::string> backends = o.backends.empty() ? rhi::compiledBackends() : o.backends;
  int passed = 0, failed = 0, skipped = 0;
  nlohmann::json cases = nlohmann::json::array(), discrepancies = nlohmann::json::array();
  // The verdicts of the current script on each backend, by platform: a script both backends run
  // (neither skips) with different verdicts is a cross-backend discrepancy, reported on one line.
  std::map<std::string, std::map<std::string, std::pair<std::string, std::string>>> ran;  // platform -> backend -> (verdict, reason)
  auto record = [&](const std::string& scriptPath, const std::string& backend, const Outcome& outcome) {
    const std::string& platform = outcome.platform;
    const script::RunResult r = script::applyExpectFail(outcome.result, outcome.mustFail);
    std::string verdict = script::verdictName(r.verdict), reason = oneLine(r.reason);
    if (r.verdict != script::Verdict::Skip) ran[platform][backend] = {verdict, reason};
    if (r.verdict == script::Verdict::Pass) ++passed;
    else if (r.verdict == script::Verdict::Fail) ++failed;
    else ++skipped;
    if (o.json) {
      nlohmann::json c{{"script", scriptPath}, {"backend", backend}, {"platform", platform}, {"result", verdict}};
      if (!reason.empty()) c["reason"] = reason;
      nlohmann::json ex = nlohmann::json::array();
      for (const auto& e : r.expects) ex.push_back(expectJson(e));
      c["expects"] = ex;
      for (const std::string& note : r.notes) c["notes"].push_back(oneLine(note, kJsonNoteChars));
      if (outcome.deviceMs > 0) c["device_ms"] = outcome.deviceMs;
      cases.push_back(c);
    } else {
      std::printf("%s %-3s %-9s %s%s%s\n", verdict.c_str(), backend.c_str(), platform.c_str(), scriptPath.c_str(),
                  reason.empty() ? "" : ": ", reason.c_str());
      for (const std::string& note : r.notes) std::printf("  note: %s\n", oneLine(note, kNoteChars).c_str());
      std::fflush(stdout);
    }
  };
  auto reportDiscrepancies = [&](const std::string& scriptPath) {
    for (const auto& [platform, byBackend] : ran) {
      auto gl = byBackend.find("gl"), vk = byBackend.find("vk");
      if (gl == byBackend.end() || vk == byBackend.end() || gl->second.first == vk->second.first) continue;
      if (o.json) {
        discrepancies.push_back({{"script", scriptPath}, {"platform", platform}, {"gl", gl->second.first}, {"gl_reason", gl->second.second},
                                 {"vk", vk->second.first}, {"vk_reason", vk->second.second}});
      } else {
        std::printf("DIFFER gl/vk %-9s %s: gl %s%s%s; vk %s%s%s\n", platform.c_str(), scriptPath.c_str(), gl->second.first.c_str(),
                    gl->second.second.empty() ? "" : ": ", gl->second.second.c_str(), vk->second.first.c_str(),
                    vk->second.second.empty() ? "" : ": ", vk->second.second.c_str());
        std::fflush(stdout);
      }
    }
    ran.clear();
  };
  // kScriptsPerChild scripts at a time: each backend's children run them, then their verdicts
  // are recorded script by script, in the order of the files.
  for (size_t first = 0; first < scripts.size(); first += kScriptsPerChild) {
    std::vector<ScriptRuns> chunk;
    for (size_t n = first; n < std::min(scripts.size(), first + kScriptsPerChild); ++n) {
      ScriptRuns s{scripts[n], script::isExpectFail(scripts[n]), {}, {}};
      script::ParseResult parsed = script::parseScriptFile(s.path);
      for (const std::string& backend : backends) {
        std::vector<Outcome>& known = s.outcomes[backend];
        std::vector<std::string>& run = s.toRun[backend];
        for (const std::string& platform : requested) {
          script::RunOptions ro;
          ro.platform = platform;
          if (!parsed.ok) {
            known.push_back({platform, {script::Verdict::Fail, parsed.error, {}}, s.mustFail});
          } else if (std::string why = script::skipReasonBeforeRun(parsed.script, backend, ro); !why.empty()) {
            known.push_back({platform, {script::Verdict::Skip, why, {}}, false});
          } else {
            run.push_back(platform);
          }
        }
      }
      chunk.push_back(std::move(s));
    }
    std::vector<ScriptRuns*> order;
    for (ScriptRuns& s : chunk) order.push_back(&s);
    for (const std::string& backend : backends) runOnBackend(o, backend, order);
    for (const ScriptRuns& s : chunk) {
      for (const std::string& backend : backends)
        for (const Outcome& outcome : s.outcomes.at(backend)) record(s.path, backend, outcome);
      reportDiscrepancies(s.path);
    }
  }
  if (o.json) {
    nlohmann::json j{{"cases", cases}, {"passed", passed}, {"failed", failed}, {"skipped", skipped}, {"discrepancies", discrepancies}};
    std::cout << j.dump(2) << std::endl;
  } else {
    std::printf("%d passed, %d failed, %d skipped\n", passed, failed, skipped);
  }
  return failed == 0 ? 0 : 1;
}

}  // namespace

void registerTestCommand(CLI::App& app, CommandSet& commands) {
  auto o = std::make_shared<TestOptions>();
  CLI::App* test = app.add_subcommand("test", "run shader-test scripts (AmberScript, piglit/VkRunner shader_test; docs/script-format.md) on every backend");
  test->add_option("paths", o->paths, "script files or folders (searched for *.amber and *.shader_test)")->required();
  test->add_option("--backend,-b", o->backends, "backends or devices to run (gl, vk, or a device of `parity list`: gl-zink; default: every compiled backend)")
      ->check([](const std::string& b) { return backendOfDevice(b).empty() ? "not a backend or device (gl, vk, gl-zink, ...)" : std::string(); });
  test->add_option("--platform", o->platforms,
                   "platform layers to run on (reference, dx10, ps3, x360, all; default: every platform a script allows)");
  test->add_option("--timeout", o->timeout, "seconds a script may take on one backend and platform before it counts as a failure")
      ->capture_default_str();
  test->add_flag("--json", o->json, "machine-readable output");
  test->add_flag("--debug", o->debug,
                 "driver validation (GL debug context, Vulkan validation layer): any message fails the script");
  test->add_flag("--in-process", o->inProcess, "")->group("");  // the child of each case
  test->add_option("--crash-on-platform", o->crashOnPlatform, "")->group("");  // tests only (TestOptions)
  test->add_option("--crash-on-script", o->crashOnScript, "")->group("");
  commands.add(test, [o] { return runTests(*o); });
}

}  // namespace parity::harness
