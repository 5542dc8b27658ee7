// `parity test FILE|DIR ... [--backend gl|vk ...] [--json]`: runs shader-test scripts
// (docs/script-format.md). Each script x backend runs in its own child process
// (`parity test --in-process --backend X FILE`), so GL and Vulkan never share a process and a
// crash or a hang becomes a result. Files named *.expect_fail.amber must fail.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "harness/commands.h"
#include "harness/process.h"
#include "harness/script_parser.h"
#include "harness/script_runner.h"
#include "rhi/rhi.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

struct TestOptions {
  std::vector<std::string> paths;
  std::vector<std::string> backends;
  std::string platform = "reference";
  bool json = false;
  bool inProcess = false;
  double timeout = 120;
};

bool expectFail(const std::string& path) {
  std::string name = fs::path(path).filename().string();
  const std::string suffix = ".expect_fail.amber";
  return name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string oneLine(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (char& c : s)
    if (c == '\n') c = ' ';
  return s;
}

nlohmann::json resultJson(const script::RunResult& r) {
  nlohmann::json j{{"result", script::verdictName(r.verdict)}, {"reason", r.reason}};
  j["expects"] = nlohmann::json::array();
  for (const auto& e : r.expects) j["expects"].push_back({{"line", e.line}, {"pass", e.pass}, {"message", e.message}});
  return j;
}

// Child: one script on one backend, in this process; prints one JSON object.
int runInProcess(const TestOptions& o) {
  if (o.paths.size() != 1 || o.backends.size() != 1)
    return reportError("--in-process takes one script and one --backend");
  const std::string& path = o.paths[0];
  script::RunResult r;
  script::ParseResult parsed = script::parseScriptFile(path);
  script::RunOptions ro;
  ro.platform = o.platform;
  if (!parsed.ok) {
    r.verdict = script::Verdict::Fail;
    r.reason = parsed.error;
  } else if (std::string why = script::skipReasonBeforeRun(parsed.script, o.backends[0], ro); !why.empty()) {
    r.verdict = script::Verdict::Skip;
    r.reason = why;
  } else {
    rhi::DeviceDesc desc;
    desc.backend = o.backends[0];
    std::vector<std::string> validation;
    desc.onValidationError = [&validation](const std::string& id, const std::string& msg) {
      validation.push_back(id + ": " + msg);
      std::fprintf(stderr, "parity: validation: %s: %s\n", id.c_str(), msg.c_str());
    };
    std::string whyNot;
    std::unique_ptr<rhi::Device> dev = rhi::createDevice(desc, &whyNot);
    if (!dev) {
      r.verdict = script::Verdict::Skip;
      r.reason = "backend " + o.backends[0] + " unavailable: " + whyNot;
    } else {
      r = script::runScript(parsed.script, *dev, ro);
      if (!validation.empty() && r.verdict == script::Verdict::Pass) {
        r.verdict = script::Verdict::Fail;
        r.reason = "RHI validation: " + validation.front();
      } else if (!validation.empty() && r.verdict == script::Verdict::Fail) {
        r.reason += " (RHI validation: " + validation.front() + ")";
      }
    }
  }
  std::cout << resultJson(r).dump() << std::endl;
  return r.verdict == script::Verdict::Fail ? 1 : 0;
}

std::vector<std::string> collectScripts(const std::vector<std::string>& paths, std::string* error) {
  std::vector<std::string> out;
  for (const std::string& p : paths) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<std::string> found;
      for (auto it = fs::recursive_directory_iterator(p, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
        if (it->is_regular_file() && it->path().extension() == ".amber") found.push_back(it->path().string());
      std::sort(found.begin(), found.end());
      out.insert(out.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(p, ec)) {
      out.push_back(p);
    } else {
      *error = p + ": no such file or folder";
      return {};
    }
  }
  return out;
}

int runTests(const TestOptions& o) {
  // The platform render path (platforms/) is not wired into the script runner yet.
  if (o.platform != "reference")
    return reportError("--platform " + o.platform + ": scripts run on the reference platform only for now");
  if (o.inProcess) return runInProcess(o);
  std::string error;
  std::vector<std::string> scripts = collectScripts(o.paths, &error);
  if (!error.empty()) return reportError(error);
  std::vector<std::string> backends = o.backends.empty() ? rhi::compiledBackends() : o.backends;
  int passed = 0, failed = 0, skipped = 0;
  nlohmann::json cases = nlohmann::json::array();
  auto record = [&](const std::string& scriptPath, const std::string& backend, std::string verdict, std::string reason,
                    const nlohmann::json& expects) {
    if (verdict == "PASS") ++passed;
    else if (verdict == "FAIL") ++failed;
    else ++skipped;
    if (o.json) {
      nlohmann::json c{{"script", scriptPath}, {"backend", backend}, {"platform", o.platform}, {"result", verdict}};
      if (!reason.empty()) c["reason"] = reason;
      if (!expects.is_null()) c["expects"] = expects;
      cases.push_back(c);
    } else {
      std::printf("%s %-3s %s%s%s\n", verdict.c_str(), backend.c_str(), scriptPath.c_str(), reason.empty() ? "" : ": ",
                  reason.c_str());
      std::fflush(stdout);
    }
  };
  for (const std::string& path : scripts) {
    bool mustFail = expectFail(path);
    script::ParseResult parsed = script::parseScriptFile(path);
    for (const std::string& backend : backends) {
      std::string verdict, reason;
      nlohmann::json expects;
      script::RunOptions ro;
      ro.platform = o.platform;
      if (!parsed.ok) {
        verdict = "FAIL";
        reason = parsed.error;
      } else if (std::string why = script::skipReasonBeforeRun(parsed.script, backend, ro); !why.empty()) {
        verdict = "SKIP";
        reason = why;
      } else {
        ProcessResult p = runProcess({selfExecutable(), "test", "--in-process", "--backend", backend, "--platform",
                                      o.platform, path}, o.timeout);
        if (p.timedOut) {
          verdict = "FAIL", reason = "timed out after " + std::to_string(static_cast<int>(o.timeout)) + " s";
        } else if (p.crashed) {
          verdict = "FAIL", reason = "crashed (signal " + std::to_string(p.signal) + ")";
        } else if (!p.startError.empty()) {
          verdict = "FAIL", reason = "cannot start: " + p.startError;
        } else {
          try {
            std::string out = p.out;
            size_t brace = out.rfind("\n{");
            nlohmann::json j = nlohmann::json::parse(brace == std::string::npos ? out : out.substr(brace + 1));
            verdict = j.at("result").get<std::string>();
            reason = j.value("reason", "");
            expects = j.value("expects", nlohmann::json::array());
          } catch (const std::exception&) {
            verdict = "FAIL", reason = "child printed no result (exit " + std::to_string(p.exitCode) + "): " + oneLine(p.err);
          }
        }
      }
      if (mustFail && verdict == "FAIL") {
        verdict = "PASS";
        reason = "failed as expected: " + reason;
      } else if (mustFail && verdict == "PASS") {
        verdict = "FAIL";
        reason = "expected to fail (*.expect_fail.amber) but passed";
      }
      record(path, backend, verdict, oneLine(reason), expects);
    }
  }
  if (o.json) {
    nlohmann::json j{{"cases", cases}, {"passed", passed}, {"failed", failed}, {"skipped", skipped}};
    std::cout << j.dump(2) << std::endl;
  } else {
    std::printf("%d passed, %d failed, %d skipped\n", passed, failed, skipped);
  }
  return failed == 0 ? 0 : 1;
}

}  // namespace

void registerTestCommand(CLI::App& app, CommandSet& commands) {
  auto o = std::make_shared<TestOptions>();
  CLI::App* test = app.add_subcommand("test", "run shader-test scripts (AmberScript subset, docs/script-format.md) on every backend");
  test->add_option("paths", o->paths, "script files or folders (searched for *.amber)")->required();
  test->add_option("--backend,-b", o->backends, "backends to run (default: every compiled backend)")
      ->check(CLI::IsMember({"gl", "vk"}));
  test->add_option("--platform", o->platform, "platform layer the scripts run on")->capture_default_str();
  test->add_option("--timeout", o->timeout, "seconds per script and backend before it counts as a failure")->capture_default_str();
  test->add_flag("--json", o->json, "machine-readable output");
  test->add_flag("--in-process", o->inProcess, "")->group("");  // the child of each case
  commands.add(test, [o] { return runTests(*o); });
}

}  // namespace parity::harness
