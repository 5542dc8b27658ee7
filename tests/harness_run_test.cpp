// `parity run`, `bless` and `merge` as CI and a user run them: results, faults in child
// processes, goldens, expectations, shards and reports. Every run uses temporary folders for its
// output and its goldens; the project's golden/ is only read.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "harness/run/process.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

harness::ProcessResult parity(std::vector<std::string> args, double timeout = 120) {
  args.insert(args.begin(), PARITY_BINARY);
  return harness::runProcess(args, timeout);
}

nlohmann::json readJson(const fs::path& p) {
  std::ifstream in(p);
  nlohmann::json j;
  if (in) in >> j;
  return j;
}

std::string readText(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::map<std::string, nlohmann::json> casesById(const nlohmann::json& results) {
  std::map<std::string, nlohmann::json> m;
  for (const auto& c : results["cases"]) m[c["id"].get<std::string>()] = c;
  return m;
}

// Both backends must be available for these tests (they compare GL with Vulkan).
bool bothBackends(std::string* why) {
  auto r = parity({"list", "--json"});
  if (r.exitCode != 0) {
    *why = "parity list failed: " + r.err;
    return false;
  }
  const nlohmann::json listing = nlohmann::json::parse(r.out);  // outlives the loop below
  for (const auto& b : listing["backends"])
    if (!b["available"].get<bool>()) {
      *why = b["name"].get<std::string>() + " unavailable: " + b.value("reason", "");
      return false;
    }
  return true;
}

// Processes whose command line contains `needle`.
std::vector<int> processesNaming(const std::string& needle) {
  std::vector<int> pids;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || !std::all_of(name.begin(), name.end(), ::isdigit)) continue;
    std::ifstream in(entry.path() / "cmdline", std::ios::binary);
    std::string cmdline((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::replace(cmdline.begin(), cmdline.end(), '\0', ' ');
    if (cmdline.find(needle) != std::string::npos) pids.push_back(std::stoi(name));
  }
  return pids;
}

const std::vector<std::string> kSmallMatrix = {"--technique", "forward,forward-multipass", "--scene", "default",
                                               "--platform", "reference", "--size", "96x64"};

// One temporary root per suite: a first run without goldens, then goldens blessed from it.
class HarnessRun : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("parity-harness-test-" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_ / "golden");
    available_ = bothBackends(&why_);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  void SetUp() override {
    if (!available_) {
      const char* env = std::getenv("PARITY_REQUIRE_BACKENDS");
      if (env && std::string(env).find("vk") != std::string::npos && std::string(env).find("gl") != std::string::npos)
        FAIL() << why_;
      GTEST_SKIP() << why_;
    }
  }

  // A run of the small matrix into root/<name> against root/golden.
  harness::ProcessResult run(const std::string& name, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"run", "--out", (root_ / name).string(), "--golden", (root_ / "golden").string(),
                                     "--no-progress", "--jobs", "2"};
    args.insert(args.end(), kSmallMatrix.begin(), kSmallMatrix.end());
    args.insert(args.end(), extra.begin(), extra.end());
    return parity(args);
  }

  // Goldens for the small matrix, blessed (once) from a run without goldens.
  void ensureGoldens() {
    if (fs::exists(root_ / "golden" / "manifest.json")) return;
    auto r = run("seed");
    ASSERT_EQ(r.exitCode, 2) << r.out << r.err;
    test::writeEvidence((root_ / "golden").string(), "tests/harness_run_test.cpp: HarnessRun.BlessRecordsProvenanceAndTheNextRunPasses");
    auto b = parity({"bless", "--from", (root_ / "seed").string(), "--golden", (root_ / "golden").string()});
    ASSERT_EQ(b.exitCode, 0) << b.out << b.err;
  }

  static fs::path root_;
  static bool available_;
  static std::string why_;
};
fs::path HarnessRun::root_;
bool HarnessRun::available_ = false;
std::string HarnessRun::why_;

TEST_F(HarnessRun, MissingGoldenFailsWithHowToCreateItAndWritesNoGolden) {
  fs::path golden = root_ / "empty-golden";
  fs::create_directories(golden);
  auto r = parity({"run", "--out", (root_ / "nogolden").string(), "--golden", golden.string(), "--no-progress",
                   "--technique", "forward", "--scene", "default", "--size", "96x64"});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_TRUE(fs::is_empty(golden)) << "run must never write goldens";
  auto cases = casesById(readJson(root_ / "nogolden" / "results.json"));
  ASSERT_EQ(cases.size(), 8u);  // 4 platforms x 2 backends
  // Every platform renders (through its platform layer) and has its own golden.
  for (const std::string b : {"gl", "vk"})
    for (const std::string p : {"reference", "dx10", "ps3", "x360"}) {
      const auto& c = cases["forward/default/" + p + "/" + b];
      EXPECT_EQ(c["result"], "Fail") << c.dump();
      EXPECT_NE(c["reason"].get<std::string>().find("parity bless --technique forward --scene default --platform " + p),
                std::string::npos)
          << c["reason"];
      EXPECT_EQ(c["attempts"].size(), 1u) << "a missing golden is not rerun";
      EXPECT_TRUE(fs::exists(root_ / "nogolden" / c["image"].get<std::string>())) << c.dump();
    }
}

TEST_F(HarnessRun, BlessRecordsProvenanceAndTheNextRunPasses) {
  ensureGoldens();
  nlohmann::json manifest = readJson(root_ / "golden" / "manifest.json");
  ASSERT_TRUE(manifest["goldens"].contains("forward/default/reference")) << manifest.dump(2);
  const auto& g = manifest["goldens"]["forward/default/reference"];
  EXPECT_NE(g["reason"].get<std::string>().find("bit-identical images in the same run"), std::string::npos) << g["reason"];
  EXPECT_EQ(g["size"], "96x64");
  EXPECT_FALSE(g["backends"]["gl"]["renderer"].get<std::string>().empty());
  EXPECT_FALSE(g["backends"]["vk"]["driver"].get<std::string>().empty());
  EXPECT_FALSE(g["mesa_version"].get<std::string>().empty());
  EXPECT_FALSE(g["blessed"].get<std::string>().empty());
  EXPECT_TRUE(g.contains("project_commit"));
  EXPECT_TRUE(fs::exists(root_ / "golden" / "forward" / "default" / "reference.png"));
  for (const auto& e : fs::recursive_directory_iterator(root_ / "golden"))
    EXPECT_EQ(e.path().filename().string().find(".parity-tmp"), std::string::npos) << "left a temporary file";

  auto r = run("pass");
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  nlohmann::json results = readJson(root_ / "pass" / "results.json");
  EXPECT_EQ(results["counts"]["Pass"], 4) << results["counts"];
  for (const auto& grp : results["groups"]) EXPECT_EQ(grp["verdict"], "pass") << grp.dump();
  // The reports: a grid cell per case, one JUnit testcase per case.
  std::string html = readText(root_ / "pass" / "report" / "index.html");
  size_t cells = 0;
  for (size_t at = 0; (at = html.find("class=\"cell\"", at)) != std::string::npos; ++at) ++cells;
  EXPECT_EQ(cells, 4u);
  std::string junit = readText(root_ / "pass" / "junit.xml");
  // Four cases, plus one policy case per backend PARITY_REQUIRE_BACKENDS requires (the test
  // command requires both).
  const size_t required = results["policy"]["require_backends"].size();
  EXPECT_NE(junit.find("tests=\"" + std::to_string(4 + required) + "\" failures=\"0\" errors=\"0\""), std::string::npos)
      << junit;
  size_t cases = 0;
  for (size_t at = 0; (at = junit.find("<testcase classname=\"parity.forward", at)) != std::string::npos; ++at) ++cases;
  EXPECT_EQ(cases, 4u) << junit;
}

// Under AddressSanitizer a crashing child first symbolises its stack, which takes seconds on a
// loaded machine: the crash must not reach the timeout that turns the hanging case into a Timeout.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PARITY_TEST_UNDER_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define PARITY_TEST_UNDER_ASAN 1
#endif
#ifdef PARITY_TEST_UNDER_ASAN
constexpr const char* kFaultTimeout = "30";
#else
constexpr const char* kFaultTimeout = "4";
#endif

TEST_F(HarnessRun, CrashHangFlakeAndNondeterminismBecomeResults) {
  ensureGoldens();
  auto r = run("faults", {"--timeout", kFaultTimeout, "--retries", "1",                             //
                          "--inject-fault", "forward/default/reference/gl=crash",                    //
                          "--inject-fault", "forward/default/reference/vk=hang",                     //
                          "--inject-fault", "forward-multipass/default/reference/gl=flaky",          //
                          "--inject-fault", "forward-multipass/default/reference/vk=nondeterministic"});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  auto cases = casesById(readJson(root_ / "faults" / "results.json"));
  EXPECT_EQ(cases["forward/default/reference/gl"]["result"], "Crash") << cases["forward/default/reference/gl"].dump();
  EXPECT_EQ(cases["forward/default/reference/vk"]["result"], "Timeout") << cases["forward/default/reference/vk"].dump();
  EXPECT_EQ(cases["forward-multipass/default/reference/gl"]["result"], "Flake")
      << cases["forward-multipass/default/reference/gl"].dump();
  EXPECT_EQ(cases["forward-multipass/default/reference/gl"]["attempts"].size(), 2u);
  EXPECT_EQ(cases["forward-multipass/default/reference/vk"]["result"], "Nondeterministic")
      << cases["forward-multipass/default/reference/vk"].dump();
  std::string junit = readText(root_ / "faults" / "junit.xml");
  EXPECT_NE(junit.find("<error type=\"Crash\""), std::string::npos);
  EXPECT_NE(junit.find("<error type=\"Timeout\""), std::string::npos);
  // Nothing of the run outlives it: not the hanging child killed at the timeout, not the fork
  // server its children come from (harness/run/process.h), not a waiter between them. Each of them
  // carries the run's command line, which names its output folder.
  std::vector<int> left;
  for (int tries = 0; tries < 50; ++tries) {
    left = processesNaming((root_ / "faults").string());
    if (left.empty()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_TRUE(left.empty()) << left.size() << " processes of the run are still alive, e.g. pid " << left.front();
}

// The cases of one backend (here one technique's four platforms) render in one child on one
// device (the device is created once), and a fault is still its own case's: a crash on one platform
// is that case's Crash, the platforms the child did not reach run again alone; a case that
// fails before it reaches the device fails alone, its error in its own stderr, not in its
// neighbours', and the child goes on; a render that fails ends the child, and the cases after
// it render alone, each on a device of its own.
TEST_F(HarnessRun, ATechniquesPlatformsShareOneChildAndAFaultIsItsCaseAlone) {
  auto verdictOf = [](const std::string&) { return "Pass"; };  // forward raises nothing on any platform
  auto runForward = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"run",     "--out",     (root_ / name).string(), "--no-progress", "--retries", "0",
                                     "--technique", "forward", "--scene", "default",       "--backend", "vk"};
    args.insert(args.end(), extra.begin(), extra.end());
    auto r = parity(args);
    auto cases = casesById(readJson(root_ / name / "results.json"));
    EXPECT_EQ(cases.size(), 4u) << r.out << r.err;
    return std::make_pair(r, cases);
  };
  auto [shared, cases] = runForward("shared-child", {});
  EXPECT_EQ(shared.exitCode, 0) << shared.out << shared.err;
  int devicesCreated = 0;
  for (const auto& [id, c] : cases) {
    EXPECT_EQ(c["result"], verdictOf(c["platform"])) << c.dump();
    EXPECT_EQ(c["attempts"].size(), 1u) << c.dump();
    devicesCreated += c.value("device_ms", 0.0) > 0;
  }
  EXPECT_EQ(devicesCreated, 1) << "one child, one device for the four platforms";

  // Two techniques' eight cases on one backend: still one child (kCasesPerChild is 16).
  auto two = parity({"run", "--out", (root_ / "shared-child-two").string(), "--no-progress", "--retries", "0",
                     "--technique", "forward,forward-multipass", "--scene", "default", "--backend", "vk"});
  const nlohmann::json twoResults = readJson(root_ / "shared-child-two" / "results.json");
  EXPECT_EQ(twoResults["cases"].size(), 8u) << two.out << two.err;
  devicesCreated = 0;
  for (const auto& c : twoResults["cases"]) devicesCreated += c.value("device_ms", 0.0) > 0;
  EXPECT_EQ(devicesCreated, 1) << "one child, one device for two techniques' cases";

  auto [crashed, crashCases] = runForward("shared-child-crash", {"--inject-fault", "forward/default/ps3/vk=crash"});
  EXPECT_EQ(crashed.exitCode, 2) << crashed.out << crashed.err;
  EXPECT_EQ(crashCases["forward/default/ps3/vk"]["result"], "Crash") << crashCases["forward/default/ps3/vk"].dump();
  EXPECT_NE(crashCases["forward/default/ps3/vk"].value("reason", "").find("signal 11"), std::string::npos);
  for (const char* platform : {"reference", "dx10", "x360"}) {
    const auto& c = crashCases[std::string("forward/default/") + platform + "/vk"];
    EXPECT_EQ(c["result"], verdictOf(platform)) << c.dump();
  }

  auto [flaky, flakyCases] = runForward("shared-child-flaky", {"--inject-fault", "forward/default/dx10/vk=flaky"});
  EXPECT_EQ(flaky.exitCode, 2) << flaky.out << flaky.err;
  const auto& dx10 = flakyCases["forward/default/dx10/vk"];
  EXPECT_EQ(dx10["result"], "Fail") << dx10.dump();
  EXPECT_EQ(dx10.value("reason", ""), "render failed: injected flaky failure (first attempt)") << dx10.dump();
  EXPECT_NE(dx10.value("stderr", "").find("injected flaky"), std::string::npos) << dx10.dump();
  devicesCreated = 0;
  for (const char* platform : {"reference", "ps3", "x360"}) {
    const auto& c = flakyCases[std::string("forward/default/") + platform + "/vk"];
    EXPECT_EQ(c["result"], verdictOf(platform)) << c.dump();
    EXPECT_EQ(c.value("stderr", "").find("injected flaky"), std::string::npos) << c.dump();
    devicesCreated += c.value("device_ms", 0.0) > 0;
  }
  EXPECT_EQ(devicesCreated, 1) << "the child went on after the case that failed before its device";

  // reference is the batch's first platform (the matrix's order): every other case comes after it.
  auto [failed, failCases] = runForward("shared-child-fail", {"--inject-fault", "forward/default/reference/vk=fail"});
  EXPECT_EQ(failed.exitCode, 2) << failed.out << failed.err;
  const auto& reference = failCases["forward/default/reference/vk"];
  EXPECT_EQ(reference["result"], "Fail") << reference.dump();
  EXPECT_EQ(reference.value("reason", ""), "render failed: injected failure") << reference.dump();
  for (const char* platform : {"dx10", "ps3", "x360"}) {
    const auto& c = failCases[std::string("forward/default/") + platform + "/vk"];
    EXPECT_EQ(c["result"], verdictOf(platform)) << c.dump();
    EXPECT_GT(c.value("device_ms", 0.0), 0.0) << "rendered alone, after the shared child ended: " << c.dump();
  }
}

// The other ways a case dies: abort() and memory exhaustion (the oom fault caps its own address
// space, then allocates until new fails). Each is a Crash with the child's stderr in
// results.json and the report; the cases beside them keep their results.
TEST_F(HarnessRun, AbortAndMemoryExhaustionAreCrashesWithTheirStderr) {
  ensureGoldens();
  auto r = run("abort-oom", {"--retries", "0",                                          //
                             "--inject-fault", "forward/default/reference/gl=abort",    //
                             "--inject-fault", "forward/default/reference/vk=oom"});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  auto cases = casesById(readJson(root_ / "abort-oom" / "results.json"));
  const auto& aborted = cases["forward/default/reference/gl"];
  const auto& exhausted = cases["forward/default/reference/vk"];
  EXPECT_EQ(aborted["result"], "Crash") << aborted.dump();
  EXPECT_NE(aborted.value("stderr", "").find("injected abort"), std::string::npos) << aborted.dump();
  EXPECT_EQ(exhausted["result"], "Crash") << exhausted.dump();
  EXPECT_NE(exhausted.value("stderr", "").find("bad_alloc"), std::string::npos) << exhausted.dump();
  EXPECT_EQ(cases["forward-multipass/default/reference/gl"]["result"], "Pass");
  EXPECT_EQ(cases["forward-multipass/default/reference/vk"]["result"], "Pass");
  // The grid links each cell to its group's page, which shows the stderr.
  std::string index = readText(root_ / "abort-oom" / "report" / "index.html");
  EXPECT_NE(index.find("cases/g-forward-default-reference.html"), std::string::npos);
  std::string page = readText(root_ / "abort-oom" / "report" / "cases" / "g-forward-default-reference.html");
  EXPECT_NE(page.find("injected abort"), std::string::npos) << "the report shows the crashed case's stderr";
  EXPECT_NE(page.find("bad_alloc"), std::string::npos);
  // A fault of an unknown kind is refused before anything is written.
  auto bad = run("bad-fault", {"--inject-fault", "forward/default/reference/gl=explode"});
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(bad.err.find("not CASE=KIND"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(root_ / "bad-fault"));
}

TEST_F(HarnessRun, ExpectationsRegressionsAndTriangulatedVerdicts) {
  ensureGoldens();
  fs::path exp = root_ / "expectations.json";
  std::ofstream(exp) << R"({"expectations": [
    {"case": "forward/default/reference/gl", "driver": "*llvmpipe*", "result": "Crash", "reason": "test: known crash on one driver"},
    {"case": "forward/default/reference/vk", "driver": "*llvmpipe*", "result": "Fail", "reason": "test: fixed since"}
  ]})";
  auto r = run("expect", {"--expectations", exp.string(), "--retries", "0",                  //
                          "--inject-fault", "forward/default/reference/gl=crash",            //
                          "--inject-fault", "forward-multipass/default/reference/gl=perturb"});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  nlohmann::json results = readJson(root_ / "expect" / "results.json");
  auto cases = casesById(results);
  // The crashed child named no device: the case takes the one its backend's other cases rendered
  // with, so an expectation for one driver's crash matches it.
  EXPECT_EQ(cases["forward/default/reference/gl"]["result"], "ExpectedFail") << cases["forward/default/reference/gl"].dump();
  EXPECT_NE(cases["forward/default/reference/gl"].value("renderer", "").find("llvmpipe"), std::string::npos)
      << cases["forward/default/reference/gl"].dump();
  EXPECT_EQ(cases["forward/default/reference/vk"]["result"], "UnexpectedPass");
  const auto& perturbed = cases["forward-multipass/default/reference/gl"];
  EXPECT_EQ(perturbed["result"], "Fail");
  EXPECT_NE(perturbed["reason"].get<std::string>().find("differs from golden"), std::string::npos) << perturbed["reason"];
  EXPECT_TRUE(perturbed["golden"].contains("heatmap"));
  EXPECT_EQ(cases["forward-multipass/default/reference/vk"]["result"], "Pass");
  for (const auto& g : results["groups"]) {
    if (g["group"] == "forward-multipass/default/reference") {
      EXPECT_EQ(g["verdict"], "gl regression") << g.dump();
    }
  }
}

// The exit policy: a required backend that is unavailable fails the run with one line naming it
// (the flag, or PARITY_REQUIRE_BACKENDS when no flag is given); without a requirement its cases
// are Skips and the run passes. A name the run selects no case of is an error before anything is
// written.
TEST_F(HarnessRun, RequiredBackendThatIsUnavailableFailsTheRun) {
  ensureGoldens();
  // Set around the calls only: the child inherits the environment.
  struct Env {
    std::map<std::string, std::optional<std::string>> saved;
    void set(const std::string& k, const char* v) {
      if (!saved.count(k)) saved[k] = std::getenv(k.c_str()) ? std::optional<std::string>(std::getenv(k.c_str())) : std::nullopt;
      if (v) setenv(k.c_str(), v, 1);
      else unsetenv(k.c_str());
    }
    ~Env() {
      for (const auto& [k, v] : saved) v ? setenv(k.c_str(), v->c_str(), 1) : unsetenv(k.c_str());
    }
  } env;
  env.set("VK_ICD_FILENAMES", "/nonexistent/icd.json");
  env.set("VK_DRIVER_FILES", "/nonexistent/icd.json");
  env.set("PARITY_REQUIRE_BACKENDS", nullptr);

  auto r = run("no-vk-required", {"--require-backends", "gl,vk"});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.out.find("parity run: FAILED: required backend vk unavailable: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("policy: require gl,vk"), std::string::npos) << r.out;
  nlohmann::json results = readJson(root_ / "no-vk-required" / "results.json");
  EXPECT_TRUE(results["policy"]["unavailable"].contains("vk")) << results["policy"].dump();
  EXPECT_FALSE(results["policy"]["unavailable"].contains("gl")) << results["policy"].dump();
  const std::string junit = readText(root_ / "no-vk-required" / "junit.xml");
  EXPECT_NE(junit.find("name=\"backend vk available\">\n      <failure type=\"RequiredBackendUnavailable\""), std::string::npos)
      << junit;

  r = run("no-vk-optional");
  EXPECT_EQ(r.exitCode, 0) << "no requirement: vk's cases are Skips " << r.out << r.err;
  EXPECT_EQ(casesById(readJson(root_ / "no-vk-optional" / "results.json"))["forward/default/reference/vk"]["result"], "Skip");

  env.set("PARITY_REQUIRE_BACKENDS", "vk");
  r = run("no-vk-from-environment");
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.out.find("required backend vk unavailable"), std::string::npos) << r.out;
  // The variable asks only for the backends a run selects (a CTest case runs one).
  r = run("gl-only-from-environment", {"--backend", "gl"});
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;

  r = run("vk-not-selected", {"--backend", "gl", "--require-backends", "vk"});
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--require-backends vk: the run selects no vk case"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(root_ / "vk-not-selected")) << "nothing is written";
}

// Per-pass verdicts: a regression planted in an intermediate target (forward's depth) that the
// final image does not show fails the case with the pass and the target named, on the backend it
// happened on; tolerances.json can relax that target by name, with a reason.
TEST_F(HarnessRun, AnIntermediateTargetOverItsToleranceFailsTheCaseNamingItsPass) {
  ensureGoldens();
  auto r = run("target-regression", {"--inject-fault", "forward/default/reference/vk=perturb-target", "--retries", "0"});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  auto cases = casesById(readJson(root_ / "target-regression" / "results.json"));
  const auto& vk = cases["forward/default/reference/vk"];
  EXPECT_EQ(vk["result"], "Fail") << vk.dump();
  EXPECT_TRUE(vk["golden"]["metrics"]["pixels_over_fail"] == 0) << "the final image matches its golden";
  EXPECT_NE(vk.value("reason", "").find("pass shade: target depth differs from golden/forward/default/reference/depth.exr"),
            std::string::npos)
      << vk["reason"];
  EXPECT_EQ(cases["forward/default/reference/gl"]["result"], "Pass") << "the other backend is compared as well";

  fs::path tolerances = root_ / "relaxed-tolerances.json";
  std::ofstream(tolerances) << R"({"default": {}, "targets": {"forward/*": {"dep*": {
      "attachment_depth_absolute": 1, "attachment_fail_percent": 100, "reason": "test: depth may differ"}}}})";
  r = run("target-relaxed", {"--inject-fault", "forward/default/reference/vk=perturb-target", "--retries", "0",
                             "--tolerances", tolerances.string()});
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  cases = casesById(readJson(root_ / "target-relaxed" / "results.json"));
  EXPECT_EQ(cases["forward/default/reference/vk"]["result"], "Pass") << cases["forward/default/reference/vk"].dump();
  bool recorded = false;
  for (const auto& t : cases["forward/default/reference/vk"]["golden"]["targets"])
    recorded = recorded || (t["name"] == "depth" && t.value("tolerance", nlohmann::json::object()).value("reason", "") ==
                                                         "test: depth may differ");
  EXPECT_TRUE(recorded) << "the relaxed target records its reason";
}

// Float, depth and normal targets are shown on the case page through a stated mapping: forward's
// D32F depth as a grey ramp, its PNG written beside the EXR.
TEST_F(HarnessRun, CasePageShowsDepthTargetsThroughAStatedMapping) {
  ensureGoldens();
  auto r = run("previews");
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  auto cases = casesById(readJson(root_ / "previews" / "results.json"));
  nlohmann::json depth;
  for (const auto& t : cases["forward/default/reference/vk"]["golden"]["targets"])
    if (t["name"] == "depth") depth = t;
  ASSERT_TRUE(depth.contains("preview")) << cases["forward/default/reference/vk"].dump();
  EXPECT_TRUE(fs::exists(root_ / "previews" / depth["preview"]["image"].get<std::string>()));
  const std::string mapping = depth["preview"]["mapping"].get<std::string>();
  EXPECT_EQ(mapping.rfind("depth: ", 0), 0u) << mapping;
  bool onPage = false;
  for (const auto& e : fs::directory_iterator(root_ / "previews" / "report" / "cases"))
    onPage = onPage || readText(e.path()).find("shown as " + mapping) != std::string::npos;
  EXPECT_TRUE(onPage) << "the case page states the mapping";
}

// --strict: a ParityWarning (and a Flake) fails the run and its junit case.
TEST_F(HarnessRun, StrictFailsOnAParityWarning) {
  ensureGoldens();
  auto r = run("strict", {"--inject-fault", "forward/default/reference/vk=subtle", "--strict"});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.out.find("strict"), std::string::npos) << r.out;
  auto cases = casesById(readJson(root_ / "strict" / "results.json"));
  EXPECT_EQ(cases["forward/default/reference/vk"]["result"], "ParityWarning");
  EXPECT_NE(readText(root_ / "strict" / "junit.xml").find("<failure type=\"ParityWarning\""), std::string::npos);
}

TEST_F(HarnessRun, BackendsThatBothMatchTheGoldenButDifferAreAParityWarning) {
  ensureGoldens();
  auto r = run("parity", {"--inject-fault", "forward/default/reference/vk=subtle"});
  EXPECT_EQ(r.exitCode, 0) << "a parity warning does not fail the run: " << r.out << r.err;
  nlohmann::json results = readJson(root_ / "parity" / "results.json");
  auto cases = casesById(results);
  EXPECT_EQ(cases["forward/default/reference/gl"]["result"], "ParityWarning") << cases["forward/default/reference/gl"].dump();
  EXPECT_EQ(cases["forward/default/reference/vk"]["result"], "ParityWarning");
  EXPECT_EQ(cases["forward-multipass/default/reference/vk"]["result"], "Pass");
  for (const auto& g : results["groups"]) {
    if (g["group"] != "forward/default/reference") continue;
    EXPECT_EQ(g["verdict"], "parity warning");
    EXPECT_TRUE(fs::exists(root_ / "parity" / g["parity"]["heatmap"].get<std::string>()));
  }
}

TEST_F(HarnessRun, BlessRefusesWithoutBothBackendsUnlessGivenAReason) {
  auto r = run("glonly", {"--backend", "gl"});
  fs::path golden = root_ / "golden-single";
  test::writeEvidence(golden.string(), "tests/harness_run_test.cpp: HarnessRun.BlessRefusesWithoutBothBackendsUnlessGivenAReason");
  auto b = parity({"bless", "--from", (root_ / "glonly").string(), "--golden", golden.string()});
  EXPECT_NE(b.exitCode, 0);
  EXPECT_NE(b.err.find("refused"), std::string::npos) << b.err;
  EXPECT_FALSE(fs::exists(golden / "forward" / "default" / "reference.png"));
  b = parity({"bless", "--from", (root_ / "glonly").string(), "--golden", golden.string(), "--backend", "gl"});
  EXPECT_NE(b.exitCode, 0) << "--backend without --reason";
  b = parity({"bless", "--from", (root_ / "glonly").string(), "--golden", golden.string(), "--backend", "gl", "--reason",
              "checked by eye"});
  EXPECT_EQ(b.exitCode, 0) << b.err;
  nlohmann::json manifest = readJson(golden / "manifest.json");
  std::string reason = manifest["goldens"]["forward/default/reference"]["reason"];
  EXPECT_NE(reason.find("checked by eye"), std::string::npos) << reason;
}

TEST_F(HarnessRun, DefaultMatrixIsTheDefaultSceneAndTheScenesWithGoldens) {
  // Without --scene, run what the project checks in; `--scene all` adds every available scene.
  auto sceneOf = [](const std::string& id) {
    size_t a = id.find('/'), b = id.find('/', a + 1);
    return id.substr(a + 1, b - a - 1);
  };
  std::set<std::string> withGoldens{"default"};
  for (const auto& t : fs::directory_iterator(fs::path(PARITY_SOURCE_DIR) / "golden"))
    if (t.is_directory())
      for (const auto& s : fs::directory_iterator(t.path()))
        if (s.is_directory()) withGoldens.insert(s.path().filename().string());
  auto list = [&](std::vector<std::string> extra) {
    std::vector<std::string> args{"run", "--list-cases"};
    args.insert(args.end(), extra.begin(), extra.end());
    auto r = parity(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    std::set<std::string> scenes;
    std::stringstream s(r.out);
    for (std::string line; std::getline(s, line);)
      if (line.rfind("script/", 0) != 0) scenes.insert(sceneOf(line));  // scripts: ScriptCli tests
    return scenes;
  };
  // The library's scripts are in the default matrix too (technique "script").
  EXPECT_NE(parity({"run", "--list-cases"}).out.find("script/clear/reference/vk\n"), std::string::npos);
  auto listed = parity({"list", "--json"});
  ASSERT_EQ(listed.exitCode, 0) << listed.err;
  std::set<std::string> available, expected;
  const nlohmann::json listing = nlohmann::json::parse(listed.out);
  for (const auto& s : listing["scenes"]) available.insert(s["name"].get<std::string>());
  for (const std::string& s : withGoldens)
    if (available.count(s)) expected.insert(s);
  EXPECT_EQ(list({}), expected);
  EXPECT_EQ(list({"--scene", "all"}), available);
  EXPECT_EQ(list({"--scene", "default"}), std::set<std::string>{"default"});
}

TEST_F(HarnessRun, ShardsPartitionTheMatrixByGroupAndMergeJoinsThem) {
  // The case lists: --shard and the GoogleTest variables agree, shards are disjoint and complete,
  // and both backends of a group stay in one shard.
  auto all = parity({"run", "--list-cases"});
  ASSERT_EQ(all.exitCode, 0) << all.err;
  std::set<std::string> union_, allSet;
  std::stringstream s(all.out);
  for (std::string line; std::getline(s, line);) allSet.insert(line);
  for (int i = 0; i < 3; ++i) {
    auto r = parity({"run", "--list-cases", "--shard", std::to_string(i) + "/3"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    setenv("GTEST_SHARD_INDEX", std::to_string(i).c_str(), 1);
    setenv("GTEST_TOTAL_SHARDS", "3", 1);
    auto e = parity({"run", "--list-cases"});
    unsetenv("GTEST_SHARD_INDEX");
    unsetenv("GTEST_TOTAL_SHARDS");
    EXPECT_EQ(r.out, e.out);
    std::stringstream ls(r.out);
    std::set<std::string> groups;
    for (std::string line; std::getline(ls, line);) {
      EXPECT_TRUE(union_.insert(line).second) << line << " in two shards";
      groups.insert(line.substr(0, line.rfind('/')));
    }
    for (const std::string& g : groups) {
      EXPECT_NE(r.out.find(g + "/gl"), std::string::npos);
      EXPECT_NE(r.out.find(g + "/vk"), std::string::npos);
    }
  }
  EXPECT_EQ(union_, allSet);
  EXPECT_NE(parity({"run", "--list-cases", "--shard", "3/3"}).exitCode, 0);

  ensureGoldens();
  auto a = run("shard0", {"--shard", "0/2"});
  auto b = run("shard1", {"--shard", "1/2"});
  EXPECT_EQ(a.exitCode, 0) << a.out << a.err;
  EXPECT_EQ(b.exitCode, 0) << b.out << b.err;
  auto m = parity({"merge", (root_ / "shard0").string(), (root_ / "shard1").string(), "--out", (root_ / "merged").string()});
  EXPECT_EQ(m.exitCode, 0) << m.out << m.err;
  nlohmann::json merged = readJson(root_ / "merged" / "results.json");
  EXPECT_EQ(merged["cases"].size(), 4u);
  EXPECT_EQ(merged["counts"]["Pass"], 4);
  for (const auto& c : merged["cases"]) EXPECT_TRUE(fs::exists(root_ / "merged" / c["image"].get<std::string>()));
  EXPECT_TRUE(fs::exists(root_ / "merged" / "junit.xml"));
  EXPECT_TRUE(fs::exists(root_ / "merged" / "report" / "index.html"));
}

TEST_F(HarnessRun, UnknownNamesAreOneLineErrors) {
  auto r = parity({"run", "--platform", "wii", "--out", (root_ / "bad").string()});
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("parity: error: unknown platform 'wii'"), std::string::npos) << r.err;
  r = parity({"run", "--shard", "2/1", "--out", (root_ / "bad").string()});
  EXPECT_NE(r.err.find("parity: error: shard '2/1'"), std::string::npos) << r.err;
}

}  // namespace

namespace {

TEST_F(HarnessRun, ReportSaysHowManyPixelsLostLight) {
  // Light-indexed deferred with room for one light per pixel loses light where volumes overlap;
  // with room for eight it loses less; forward has no packing to overflow.
  fs::path out = root_ / "lost-light";
  auto r = parity({"run", "--out", out.string(), "--no-progress", "--jobs", "2", "--technique",
                   "lidr-bits-1x255,lidr-bits-8x255,forward", "--scene", "default", "--platform", "reference",
                   "--backend", "vk"});
  ASSERT_LE(r.exitCode, 1) << r.out << r.err;
  auto cases = casesById(readJson(out / "results.json"));
  const auto& one = cases["lidr-bits-1x255/default/reference/vk"];
  const auto& eight = cases["lidr-bits-8x255/default/reference/vk"];
  ASSERT_TRUE(one.contains("lost_light")) << one.dump();
  ASSERT_TRUE(eight.contains("lost_light")) << eight.dump();
  EXPECT_FALSE(cases["forward/default/reference/vk"].contains("lost_light"));
  uint64_t lostOne = one["lost_light"]["pixels"], lostEight = eight["lost_light"]["pixels"];
  EXPECT_GT(lostOne, 0u);
  EXPECT_LT(lostEight, lostOne);
  EXPECT_EQ(one["lost_light"]["of"].get<uint64_t>(), 320u * 180u);
  std::string page = readText(out / "report" / "index.html");
  EXPECT_NE(page.find(std::to_string(lostOne) + "</b> of 57600 pixels lost light"), std::string::npos);
}


// Platform diagnostics of a technique's real calls reach the verdict: the stencil-routed A-buffer
// binds an F_W16Z16Y16X16 and an F_X32 target in one pass, which RSX cannot (E_MRT_FORMAT_MISMATCH,
// P1). Unexpected, the error fails the case; expected by an expectation as narrow as the problem
// (code, target and pass), the case is an ExpectedFail while its image matches and a Fail when it
// does not; an expectation that matches the code in another pass does not absorb it; an expected
// diagnostic that does not fire (the reference platform has no such rule) is an UnexpectedPass.
// results.json, junit.xml, the case page and its verdict line carry them, a line per code.
TEST_F(HarnessRun, PlatformDiagnosticsReachTheVerdict) {
  auto runWith = [&](const std::string& name, const std::string& expectations, std::vector<std::string> extra = {}) {
    fs::path exp = root_ / (name + "-expectations.json");
    std::ofstream(exp) << expectations;
    std::vector<std::string> args = {"run", "--out", (root_ / name).string(), "--technique", "abuffer",
                                     "--platform", "ps3,reference", "--backend", "vk", "--scene", "default", "--retries", "0",
                                     "--no-progress", "--expectations", exp.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return parity(args);
  };
  auto r = runWith("diag-none", R"({"expectations": []})");
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  auto cases = casesById(readJson(root_ / "diag-none" / "results.json"));
  const auto& ps3 = cases["abuffer/default/ps3/vk"];
  EXPECT_EQ(ps3["result"], "Fail") << ps3.dump();
  EXPECT_NE(ps3.value("reason", "").find("platform diagnostic E_MRT_FORMAT_MISMATCH"), std::string::npos) << ps3["reason"];
  ASSERT_EQ(ps3["golden"]["diagnostics"].size(), 1u) << ps3["golden"].dump();
  const auto& d = ps3["golden"]["diagnostics"][0];
  EXPECT_EQ(d["pass"], "store") << d.dump();
  EXPECT_EQ(d["targets"], nlohmann::json({"abuffer.colors", "abuffer.depths"})) << d.dump();
  EXPECT_EQ(cases["abuffer/default/reference/vk"]["result"], "Pass") << cases["abuffer/default/reference/vk"].dump();
  EXPECT_NE(readText(root_ / "diag-none" / "junit.xml")
                .find("<property name=\"diagnostic\" value=\"error E_MRT_FORMAT_MISMATCH [P1]: store binds abuffer.colors"),
            std::string::npos);
  const std::string page = readText(root_ / "diag-none" / "report" / "cases" / "g-abuffer-default-ps3.html");
  EXPECT_NE(page.find("E_MRT_FORMAT_MISMATCH [P1]: store binds abuffer.colors"), std::string::npos) << page;
  EXPECT_NE(page.find("pass store; targets abuffer.colors, abuffer.depths"), std::string::npos) << page;
  EXPECT_NE(page.find(">Fail</b>"), std::string::npos) << "the verdict line is the grid's: " << page;

  // An expectation of the code in another pass does not absorb it.
  r = runWith("diag-elsewhere", R"({"expectations": [
    {"case": "abuffer/*/ps3/*", "diagnostic": "E_MRT_*", "pass": "resolve", "reason": "test: another pass"}]})");
  cases = casesById(readJson(root_ / "diag-elsewhere" / "results.json"));
  EXPECT_EQ(cases["abuffer/default/ps3/vk"]["result"], "Fail") << cases["abuffer/default/ps3/vk"].dump();

  const std::string expected = R"({"expectations": [
    {"case": "abuffer/*/ps3/*", "diagnostic": "E_MRT_*", "pass": "store", "target": "abuffer.depths", "reason": "test: one MRT format"},
    {"case": "abuffer/*/reference/*", "diagnostic": "E_MRT_FORMAT_MISMATCH", "reason": "test: never fires"}]})";
  r = runWith("diag-expected", expected);
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;  // the UnexpectedPass
  cases = casesById(readJson(root_ / "diag-expected" / "results.json"));
  EXPECT_EQ(cases["abuffer/default/ps3/vk"]["result"], "ExpectedFail") << cases["abuffer/default/ps3/vk"].dump();
  EXPECT_EQ(cases["abuffer/default/ps3/vk"]["golden"]["diagnostics"][0].value("expected", ""), "test: one MRT format");
  EXPECT_EQ(cases["abuffer/default/reference/vk"]["result"], "UnexpectedPass")
      << cases["abuffer/default/reference/vk"].dump();
  const std::string expectedPage = readText(root_ / "diag-expected" / "report" / "cases" / "g-abuffer-default-ps3.html");
  EXPECT_NE(expectedPage.find(">ExpectedFail</b>"), std::string::npos) << expectedPage;
  EXPECT_NE(expectedPage.find("(expected: test: one MRT format)"), std::string::npos) << expectedPage;

  r = runWith("diag-perturbed", expected, {"--inject-fault", "abuffer/default/ps3/vk=perturb"});
  cases = casesById(readJson(root_ / "diag-perturbed" / "results.json"));
  EXPECT_EQ(cases["abuffer/default/ps3/vk"]["result"], "Fail") << "an expected diagnostic must not hide a regression";
  EXPECT_NE(cases["abuffer/default/ps3/vk"].value("reason", "").find("differs from golden"), std::string::npos);
}

}  // namespace
