// `parity run`: the test matrix technique × scene × platform × backend, each case rendered in a
// child process with a timeout, compared with its golden and with the other backend, classified
// with expectations, flake reruns and determinism checks. See docs/HARNESS.md.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace parity::harness {

// Every result a case can have. "Bad" results (Fail, Crash, Timeout, Nondeterministic,
// UnexpectedPass) make `parity run` exit non-zero.
enum class CaseResult {
  Pass,
  Fail,
  ParityWarning,     // both backends match the golden but differ from each other beyond the parity budget
  Crash,             // the child process died from a signal
  Timeout,           // the child process ran past --timeout
  Skip,              // with a reason (backend unavailable, platform path not implemented, ...)
  ExpectedFail,      // failed the way the expectations file says
  UnexpectedPass,    // the expectations file says it fails, but it passed
  Flake,             // failed unexpectedly, then passed on a rerun
  Nondeterministic,  // the same case rendered twice on one backend is not bit-identical
};
const char* resultName(CaseResult r);
bool parseResultName(const std::string& name, CaseResult* out);
// True for results that fail a run (and a CTest test); `strict` adds ParityWarning and Flake.
bool isBadResult(CaseResult r, bool strict = false);

// The platforms a case can target. Only "reference" has a render path today.
const std::vector<std::string>& platformNames();
bool platformHasRenderPath(const std::string& platform);

struct CaseKey {
  std::string technique, scene, platform, backend;
  // "technique/scene/platform/backend"
  std::string id() const;
  // "technique/scene/platform": the group whose backends are compared with each other.
  std::string group() const;
  static bool parse(const std::string& id, CaseKey* out, std::string* error);
};

struct RunFilters {
  std::vector<std::string> techniques, scenes, platforms, backends;  // empty: all
  // The backend axis as devices (harness/run/devices.h: "gl-llvmpipe", "gl-zink", "vk-lavapipe");
  // empty: each backend's default device, named by the backend ("gl", "vk").
  std::vector<std::string> devices;
  std::vector<std::string> cases;                                    // exact case ids; empty: all
  std::vector<std::string> scripts;  // script files or folders; empty: the project's tests/scripts
};
// Whether a filter list (empty: everything) takes `value`.
bool inFilter(const std::vector<std::string>& filter, const std::string& value);

// Shader-test scripts (docs/script-format.md) are cases of the matrix too: technique "script",
// scene the script's name (its file name without .amber), each platform the script allows, each
// backend. They have no image and no golden: their verdict is their own expectations.
inline constexpr const char* kScriptTechnique = "script";
// Name -> path of every script under the filters' script paths. False with a reason for a path
// that does not exist or two scripts of one name.
bool scriptsByName(const RunFilters& filters, std::map<std::string, std::string>* byName, std::string* error);

struct Shard {
  int index = 0, count = 1;  // 0-based index, as GTEST_SHARD_INDEX
};
// Parses "i/n" (0 <= i < n). False with a reason.
bool parseShard(const std::string& text, Shard* out, std::string* error);
// --shard wins; otherwise GTEST_SHARD_INDEX / GTEST_TOTAL_SHARDS when both are set.
bool shardFromEnvironment(Shard* out, std::string* error);

// The matrix for the given filters. Backends are all compiled ones (availability is checked
// later). Sorted; sharding keeps each group (both backends of one technique/scene/platform)
// together so GL↔Vulkan parity is always judged within one shard.
std::vector<CaseKey> enumerateCases(const RunFilters& filters, const Shard& shard, std::string* error);

struct RunOptions {
  RunFilters filters;
  Shard shard;
  std::string outDir = "parity-out";
  std::string goldenDir;            // default: the project's golden/ folder
  // Another program's renders to judge instead of rendering (harness/run/external_images.h); empty:
  // parity renders its techniques and scripts.
  std::string imagesDir;
  // An earlier run's output folder: its results.json is compared with this run's case by case
  // (harness/run/baseline.h); empty: none.
  std::string baselineDir;
  std::string expectationsFile;     // default: <goldenDir>/expectations.json
  std::string tolerancesFile;       // default: <goldenDir>/tolerances.json
  std::string size = "320x180";
  std::string glProvider = "egl";
  int jobs = 0;                     // 0: hardware concurrency
  double timeout = 120;             // seconds per child
  int retries = 2;                  // reruns of an unexpected failure to detect flakes
  int repeat = 2;                   // renders per case in the child, compared bit-exactly
  bool progress = true;             // ETA line, only when stdout is a terminal
  // Exit policy (deqp-runner's): each backend named here that the run selects must be available,
  // or the run fails (a CI that loses its Vulkan ICD must not stay green). Default: the
  // PARITY_REQUIRE_BACKENDS variable, when set; a name given on the command line that the run does
  // not select is an error.
  std::vector<std::string> requireBackends;
  bool requireBackendsFromCommandLine = false;
  // ParityWarning and Flake fail the run too.
  bool strict = false;
  // test-only: "CASE_ID=crash|abort|oom|hang|fail|flaky|nondeterministic|perturb|subtle"
  std::vector<std::string> faults;
};

// The project's golden/ folder (from the build's source path).
std::string defaultGoldenDir();

// Runs the matrix, writes DIR/results.json, DIR/junit.xml, DIR/report/index.html and the images.
// Returns the exit code: 0 when no case is bad, 2 otherwise (and for errors).
int runMatrix(const RunOptions& options);

// The exit status of `run-case` when the backend's device cannot be created (the case is then a
// Skip, not a failure); it prints {"unavailable": reason} on stdout.
inline constexpr int kExitBackendUnavailable = 3;

// With several cases, the child's standard error starts each case's part with this and its id.
inline constexpr char kCaseMarker[] = "parity: run-case: ";

// The hidden child command: renders its cases in turn on one device (they share a backend),
// each `repeat` times, writes each case's first image and its targets, and prints one JSON object
// per case on stdout ("case": its id; device, timings, determinism, or "error" when that case
// could not be rendered; a render that fails ends the child, the cases after it get no line).
// Exit 0 when every case rendered, 1 when one could not.
struct CaseWorkerOptions {
  std::vector<CaseKey> keys;         // one backend
  std::vector<std::string> outputs;  // the image of each key
  std::string size = "320x180";
  std::string glProvider = "egl";
  int repeat = 2;
  std::string fault;       // test-only fault injection
  std::string faultCase;   // the case it is injected into; empty: every case
  std::string faultState;  // file marking that a "flaky" fault already fired
};
int runCaseWorker(const CaseWorkerOptions& options);

// Lists the matrix (after filters and shard) one case id per line, or as CTest script lines.
// ctest: add_test lines running `binary run --case ID --out outRoot/ID`.
int listCases(const RunFilters& filters, const Shard& shard, bool ctest, const std::string& binary,
              const std::string& outRoot);

// Joins the results of several runs (shards) into one output folder and writes its reports.
// `baselineDir` (empty: none) is an earlier run's output folder to compare the merged run with.
int mergeRuns(const std::vector<std::string>& inputs, const std::string& outDir, const std::string& baselineDir = "");
}  // namespace parity::harness
