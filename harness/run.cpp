#include "harness/run.h"
#include "rhi/shader_compiler.h"

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

#include "harness/report_error.h"
#include "harness/attachments.h"
#include "harness/diagnosis.h"
#include "harness/expectations.h"
#include "harness/external_images.h"
#include "harness/diff.h"
#include "harness/flip.h"
#include "harness/golden.h"
#include "harness/image_io.h"
#include "rhi/timing_device.h"
#include "harness/process.h"
#include "harness/render.h"
#include "harness/report.h"
#include "harness/script_runner.h"
#include "platforms/common/platform.h"
#include "rhi/rhi.h"
#include "scene/scene.h"
#include "techniques/technique.h"

namespace fs = std::filesystem;

namespace parity::harness {

// ---------------------------------------------------------------------------------------------
// Names, keys, filters, shards

bool parseShard(const std::string& text, Shard* out, std::string* error) {
  size_t slash = text.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no slash");
    size_t ui = 0, un = 0;
    int i = std::stoi(text.substr(0, slash), &ui);
    int n = std::stoi(text.substr(slash + 1), &un);
    if (ui != slash || un != text.size() - slash - 1 || n < 1 || i < 0 || i >= n) throw std::invalid_argument("range");
    *out = Shard{i, n};
    return true;
  } catch (const std::exception&) {
    *error = "shard '" + text + "' is not INDEX/COUNT with 0 <= INDEX < COUNT (e.g. 0/4)";
    return false;
  }
}

bool shardFromEnvironment(Shard* out, std::string* error) {
  const char* index = std::getenv("GTEST_SHARD_INDEX");
  const char* total = std::getenv("GTEST_TOTAL_SHARDS");
  if (!index || !total) return true;
  if (!parseShard(std::string(index) + "/" + total, out, error)) {
    *error = "GTEST_SHARD_INDEX/GTEST_TOTAL_SHARDS: " + *error;
    return false;
  }
  return true;
}

namespace {


bool checkNames(const std::vector<std::string>& filter, const std::vector<std::string>& known, const std::string& what,
                std::string* error) {
  for (const std::string& f : filter)
    if (std::find(known.begin(), known.end(), f) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      *error = "unknown " + what + " '" + f + "' (" + scene::didYouMean(f, known) + "known: " + list + ")";
      return false;
    }
  return true;
}

}  // namespace

bool scriptsByName(const RunFilters& f, std::map<std::string, std::string>* byName, std::string* error) {
  std::vector<std::string> roots = f.scripts;
  if (roots.empty()) roots.push_back((fs::path(rhi::dataDirectory()) / "tests" / "scripts").string());
  error->clear();
  std::vector<std::string> files = script::collectScripts(roots, error);
  if (!error->empty()) return false;
  byName->clear();
  for (const std::string& file : files) {
    std::string name = fs::path(file).filename().string();
    name = name.substr(0, name.size() - std::string(".amber").size());
    auto [it, added] = byName->emplace(name, file);
    if (!added) {
      *error = file + ": another script has the name '" + name + "' (" + it->second + "); case ids need distinct names";
      return false;
    }
  }
  return true;
}

std::vector<CaseKey> enumerateCases(const RunFilters& f, const Shard& shard, std::string* error) {
  std::vector<std::string> techniques, scenes = scene::sceneNames(), backends = rhi::compiledBackends();
  for (const auto& t : techniques::techniqueRegistry()) techniques.push_back(t.name);
  error->clear();
  bool allScenes = f.scenes.size() == 1 && f.scenes[0] == "all";
  // Scripts join the matrix unless the technique filter leaves them out.
  bool scriptCaseNamed = std::any_of(f.cases.begin(), f.cases.end(),
                                     [](const std::string& id) { return id.rfind(std::string(kScriptTechnique) + "/", 0) == 0; });
  bool wantScripts = f.techniques.empty() || inFilter(f.techniques, kScriptTechnique) || scriptCaseNamed;
  std::map<std::string, std::string> scripts;
  std::vector<std::string> knownTechniques = techniques, knownScenes = scenes;
  knownTechniques.push_back(kScriptTechnique);
  if (wantScripts) {
    if (!scriptsByName(f, &scripts, error)) return {};
    for (const auto& entry : scripts) knownScenes.push_back(entry.first);
  }
  if (!checkNames(f.techniques, knownTechniques, "technique", error) ||
      (!allScenes && !checkNames(f.scenes, knownScenes, "scene", error)) ||
      !checkNames(f.platforms, platformNames(), "platform", error) || !checkNames(f.backends, backends, "backend", error))
    return {};
  std::set<std::string> wanted(f.cases.begin(), f.cases.end());
  for (const std::string& id : f.cases) {
    CaseKey k;
    if (!CaseKey::parse(id, &k, error)) return {};
    if (!checkNames({k.technique}, knownTechniques, "technique", error) ||
        !checkNames({k.scene}, k.technique == kScriptTechnique ? knownScenes : scenes, "scene", error) ||
        !checkNames({k.platform}, platformNames(), "platform", error) || !checkNames({k.backend}, backends, "backend", error))
      return {};
  }
  std::sort(techniques.begin(), techniques.end());
  std::sort(scenes.begin(), scenes.end());
  // The default matrix is what the project checks in: the default scene and every scene with a
  // golden. Other available scenes (the shared asset models) are rendered when named, or with
  // `--scene all`; without goldens they would only report "no golden".
  RunFilters filters = f;
  if (filters.scenes.empty() && filters.cases.empty()) {
    filters.scenes.push_back("default");
    std::error_code ec;
    for (const std::string& s : scenes)
      for (const std::string& t : techniques)
        if (fs::is_directory(fs::path(defaultGoldenDir()) / t / s, ec)) {
          filters.scenes.push_back(s);
          break;
        }
  } else if (filters.scenes.size() == 1 && filters.scenes[0] == "all") {
    filters.scenes.clear();
  }
  std::vector<CaseKey> cases;
  size_t groupIndex = 0;
  for (const std::string& t : techniques) {
    if (!inFilter(filters.techniques, t)) continue;
    for (const std::string& s : scenes) {
      if (!inFilter(filters.scenes, s)) continue;
      for (const std::string& p : platformNames()) {
        if (!inFilter(f.platforms, p)) continue;
        // Shards split the matrix by group, so both backends of a group land in one shard.
        bool mine = static_cast<int>(groupIndex++ % static_cast<size_t>(shard.count)) == shard.index;
        for (const std::string& b : backends) {
          CaseKey k{t, s, p, b};
          if (!inFilter(f.backends, b) || (!wanted.empty() && !wanted.count(k.id()))) continue;
          if (mine) cases.push_back(k);
        }
      }
    }
  }
  if (!wantScripts) return cases;
  // Scripts: a scene filter names scripts; without one (or with "all") every script is taken.
  std::vector<std::string> paths;
  std::map<std::string, std::string> nameOf;
  for (const auto& [name, path] : scripts)
    if (f.scenes.empty() || allScenes || inFilter(f.scenes, name)) {
      paths.push_back(path);
      nameOf[path] = name;
    }
  if (paths.empty()) return cases;
  // Each script x platform it allows x backend, grouped by script and platform (in name order).
  std::map<std::pair<std::string, std::string>, std::vector<std::string>> groups;
  for (const script::ScriptCase& c : script::listScriptCases(paths, backends, f.platforms, error))
    groups[{nameOf[c.script], c.platform}].push_back(c.backend);
  if (!error->empty()) return {};
  for (const auto& [group, groupBackends] : groups) {
    bool mine = static_cast<int>(groupIndex++ % static_cast<size_t>(shard.count)) == shard.index;
    for (const std::string& b : groupBackends) {
      CaseKey k{kScriptTechnique, group.first, group.second, b};
      if (!inFilter(f.backends, b) || (!wanted.empty() && !wanted.count(k.id()))) continue;
      if (mine) cases.push_back(k);
    }
  }
  return cases;
}

std::string defaultGoldenDir() { return (fs::path(rhi::dataDirectory()) / "golden").string(); }

// ---------------------------------------------------------------------------------------------
// The child: one case, rendered `repeat` times in one process

int runCaseWorker(const CaseWorkerOptions& o) {
  std::string error;
  RenderRequest request;
  request.backend = o.key.backend;
  request.glProvider = o.glProvider;
  request.frame.technique = o.key.technique;
  request.frame.scene = o.key.scene;
  if (!parseSize(o.size, &request.frame.width, &request.frame.height, &error)) return reportError(error);
  scene::Scene sc;
  if (!scene::makeScene(o.key.scene, {}, &sc, &error)) return reportError(error);
  if (!sc.cameras.empty() &&
      std::none_of(sc.cameras.begin(), sc.cameras.end(), [](const auto& c) { return c.name == "default"; }))
    request.frame.camera = sc.cameras.front().name;
  std::optional<platforms::PlatformId> platform = platforms::platformFromName(o.key.platform);
  if (!platform) return reportError("unknown platform '" + o.key.platform + "'");
  request.frame.platform = *platform;
  request.frame.readTargets = true;

  if (o.fault == "flaky") {
    std::error_code ec;
    if (!fs::exists(o.faultState, ec)) {
      std::ofstream(o.faultState) << "fired\n";
      return reportError("injected flaky failure (first attempt)");
    }
  } else if (o.fault == "fail") {
    return reportError("injected failure");
  }

  rhi::DeviceDesc desc;
  desc.backend = o.key.backend;
  desc.glContextProvider = o.glProvider;
  std::unique_ptr<rhi::Device> device = rhi::createDevice(desc, &error);
  if (!device) {  // not a failure of the case: the parent makes it a Skip with this reason
    std::printf("%s\n", nlohmann::json{{"unavailable", error}}.dump().c_str());
    std::fprintf(stderr, "parity: backend %s unavailable: %s\n", o.key.backend.c_str(), error.c_str());
    return kExitBackendUnavailable;
  }
  if (o.fault == "crash") ::raise(SIGSEGV);
  if (o.fault == "abort") {
    std::fprintf(stderr, "injected abort\n");
    std::abort();
  }
  if (o.fault == "oom") {
    // Memory runs out for this process only: its address space is capped 256 MiB above what it
    // uses now, then it allocates and touches blocks until new fails (std::bad_alloc, uncaught:
    // terminate and SIGABRT, the way a real exhaustion ends), without pressing on the machine.
    struct rlimit cap;
    if (::getrlimit(RLIMIT_AS, &cap) == 0) {
      std::ifstream statm("/proc/self/statm");
      unsigned long long pages = 0;
      statm >> pages;
      cap.rlim_cur = pages * static_cast<unsigned long long>(::sysconf(_SC_PAGESIZE)) + (256ull << 20);
      ::setrlimit(RLIMIT_AS, &cap);
    }
    // nothrow new and an explicit throw: the same std::bad_alloc with or without AddressSanitizer
    // (whose allocator returns null here, scripts/test.sh: allocator_may_return_null).
    std::vector<std::unique_ptr<char[]>> blocks;
    for (;;) {
      char* block = new (std::nothrow) char[16 << 20];
      if (!block) throw std::bad_alloc();
      blocks.emplace_back(block);
      std::memset(block, 1, 16 << 20);
    }
  }
  if (o.fault == "hang")
    for (;;) ::pause();

  nlohmann::json j;
  const rhi::DeviceInfo& info = device->info();
  j["renderer"] = info.renderer;
  j["driver"] = info.driver;
  j["api"] = info.api;
  j["context_provider"] = info.contextProvider;
  std::vector<uint8_t> first;
  RenderResult firstResult;
  size_t differing = 0;
  int repeat = std::max(1, o.repeat);
  rhi::TimingDevice timed(*device);
  for (int i = 0; i < repeat; ++i) {
    auto start = std::chrono::steady_clock::now();
    timed.beginFrame();
    RenderResult r = renderFrame(timed, request);
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!r.ok) return reportError(r.error);
    j["render_ms"].push_back(ms);
    if (i == 0)  // device timestamps around each pass of the first render
      for (const rhi::PassTiming& p : timed.passTimings()) j["pass_ms"].push_back({{"pass", p.label}, {"ms", p.ms}});
    if (o.fault == "nondeterministic" && i == 1 && !r.texels.empty()) r.texels[r.texels.size() / 2] ^= 0x40;
    if (i == 0) {
      first = r.texels;
      firstResult = std::move(r);
    } else {
      size_t n = std::min(first.size(), r.texels.size());
      for (size_t k = 0; k < n; ++k) differing += first[k] != r.texels[k];
      differing += std::max(first.size(), r.texels.size()) - n;
    }
  }
  if (o.fault == "perturb") {  // a regression: a dark block in the middle
    OIIO::ImageBuf& img = firstResult.image;
    int w = img.spec().width, h = img.spec().height;
    OIIO::ROI roi(w / 3, w / 2, h / 3, h / 2, 0, 1, 0, 3);
    float black[4] = {0, 0, 0, 1};
    OIIO::ImageBufAlgo::fill(img, black, roi);
  }
  if (o.fault == "subtle") {  // within the golden tolerance, beyond the zero parity budget
    OIIO::ImageBuf& img = firstResult.image;
    float px[4] = {0, 0, 0, 0};
    img.getpixel(0, 0, px, 4);
    px[0] = px[0] > 0.5f ? px[0] - 1.0f / 255.0f : px[0] + 1.0f / 255.0f;
    img.setpixel(0, 0, px, 4);
  }
  // A regression in an intermediate target that the final image does not show: the middle band
  // of the first target that is not the output zeroed.
  if (o.fault == "perturb-target")
    for (techniques::TargetTexels& t : firstResult.targets) {
      if (t.name == "color" || t.height == 0) continue;
      const size_t row = t.texels.size() / t.height;
      std::fill(t.texels.begin() + row * (t.height / 3), t.texels.begin() + row * (t.height / 2), uint8_t{0});
      break;
    }
  // Every target the technique declares, next to the image: the per-pass comparison's input.
  if (!firstResult.targets.empty()) {
    fs::path out(o.output);
    fs::path targetsDir = out.parent_path() / (out.stem().string() + "-targets");
    std::vector<std::string> written;
    if (!writeTargets(firstResult, targetsDir.string(), &written, &error)) return reportError(error);
    // The logical format the platform planned each target as: the parent decodes the stored
    // values with it (two 16-bit channels are packed on ps3 and fixed point on x360).
    std::map<std::string, std::string> logical;
    if (std::unique_ptr<techniques::Technique> t = techniques::createTechnique(o.key.technique)) {
      techniques::RenderSettings settings;
      settings.width = request.frame.width;
      settings.height = request.frame.height;
      settings.platform = request.frame.platform;
      settings.platformParams = request.frame.platformParams;
      for (const platforms::LogicalTarget& l : t->logicalTargets(settings))
        logical[l.name] = std::string(platforms::logicalFormatName(l.format));
    }
    for (size_t i = 0; i < written.size() && i < firstResult.targets.size(); ++i) {
      const techniques::TargetTexels& t = firstResult.targets[i];
      j["targets"].push_back({{"name", t.name},
                              {"format", rhi::formatInfo(t.format).name},
                              {"logical", logical.count(t.name) ? logical[t.name] : ""},
                              {"file", (fs::path(targetsDir.filename()) / fs::path(written[i]).filename()).string()}});
    }
  }
  // Overflow made visible: a technique whose packing can drop lights (light-indexed deferred)
  // declares a "<name>.dropped" 8-bit target (R8, or the red of RGBA8) holding the lights each
  // pixel lost.
  for (const techniques::TargetTexels& t : firstResult.targets) {
    const std::string suffix = ".dropped";
    if ((t.format != rhi::Format::R8 && t.format != rhi::Format::RGBA8) || t.name.size() < suffix.size() ||
        t.name.compare(t.name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    uint64_t pixels = 0;
    uint8_t most = 0;
    const size_t stride = rhi::formatInfo(t.format).bytesPerTexel;
    for (size_t i = 0; i < t.texels.size(); i += stride) {
      pixels += t.texels[i] != 0;
      most = std::max(most, t.texels[i]);
    }
    j["lost_light"] = {{"target", t.name}, {"pixels", pixels}, {"of", uint64_t(t.width) * t.height}, {"max_per_pixel", most}};
  }
  if (std::unique_ptr<techniques::Technique> technique = techniques::createTechnique(o.key.technique))
    for (const techniques::PassInfo& p : technique->passes()) j["passes"].push_back({{"name", p.name}, {"targets", p.targets}});
  j["diagnostics"] = toJson(firstResult.diagnostics);
  j["deterministic"] = differing == 0;
  j["differing_bytes"] = differing;
  j["renders"] = repeat;
  j["width"] = request.frame.width;
  j["height"] = request.frame.height;
  if (!writeImage(o.output, firstResult.image, &error)) return reportError(error);
  std::cout << j.dump() << std::endl;
  return 0;
}

// ---------------------------------------------------------------------------------------------
// The parent: the matrix

namespace {

struct BackendInfo {
  bool available = false;
  std::string renderer, driver, api, reason;
};

std::string projectCommit() {
  std::string git = findInPath("git");
  if (git.empty()) return "";
  ProcessResult p = runProcess({git, "-C", PARITY_SOURCE_DIR, "describe", "--always", "--dirty", "--abbrev=12"}, 10);
  std::string out = p.exitCode == 0 ? p.out : "";
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

std::string nowIso() {
  std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

std::string oneLine(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (char& c : s)
    if (c == '\n') c = ' ';
  if (s.size() > 2000) s = s.substr(0, 2000) + "...";
  return s;
}

std::string fmtDuration(double s) {
  int t = static_cast<int>(std::lround(s));
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%d:%02d", t / 60, t % 60);
  return buf;
}

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
  double childSeconds = 0;
  Tolerance tolerance;
};

class Runner {
 public:
  Runner(const RunOptions& o) : o_(o) {}

  int run() {
    auto wallStart = std::chrono::steady_clock::now();
    std::string error;
    std::vector<CaseKey> keys = o_.imagesDir.empty() ? enumerateCases(o_.filters, o_.shard, &error)
                                                     : enumerateImageCases(o_.imagesDir, o_.filters, o_.shard, &error);
    if (!error.empty()) return reportError(error);
    std::set<std::string> selected;
    for (const CaseKey& k : keys) selected.insert(k.backend);
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
      else e["reason"] = oneLine(b.reason);
      results_["backends"].push_back(e);
    }
    // A script's child reports no device: the one its backend's technique cases rendered with.
    for (CaseState& c : cases_) {
      auto b = backends_.find(c.key.backend);
      if (c.key.technique == kScriptTechnique && b != backends_.end() && b->second.available)
        c.device = {{"renderer", b->second.renderer}, {"driver", b->second.driver}, {"api", b->second.api}};
    }

    auto groupsStart = std::chrono::steady_clock::now();
    compareGroups();
    for (CaseState& c : cases_) applyExpectation(c);
    compareSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - groupsStart).count();

    double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    double renderS = 0, childS = 0;
    for (const CaseState& c : cases_) {
      childS += c.childSeconds;
      for (const auto& ms : c.worker.value("render_ms", nlohmann::json::array())) renderS += ms.get<double>() / 1000.0;
    }
    results_["finished"] = nowIso();
    // render_s: the children's renders (device work, shader compilation, readback); the rest of
    // child_process_s is process start, device creation, image writing. compare_s: the parent's
    // comparisons (idiff statistics, FLIP, targets, diagnosis, GL vs Vulkan), summed over threads.
    results_["timing"] = {{"wall_s", wall},       {"child_process_s", childS}, {"render_s", renderS},
                          {"compare_s", compareSeconds_}, {"jobs", jobs()}};
    for (CaseState& c : cases_) results_["cases"].push_back(caseJson(c));
    results_["groups"] = groups_;
    // Required backends that no case could render with.
    std::vector<std::pair<std::string, std::string>> unmet;
    for (const std::string& b : required_) {
      auto it = backends_.find(b);
      if (it == backends_.end() || !it->second.available)
        unmet.push_back({b, it == backends_.end() ? "no case of it rendered" : oneLine(it->second.reason)});
    }
    for (const auto& [b, why] : unmet) results_["policy"]["unavailable"][b] = why;
    if (!writeReports(o_.outDir, results_, &error)) return reportError(error);

    std::map<std::string, int> counts;
    bool bad = !unmet.empty();
    for (const CaseState& c : cases_) {
      counts[resultName(c.result)]++;
      bad = bad || isBadResult(c.result, o_.strict);
    }
    std::string line;
    for (const auto& [name, n] : counts) line += (line.empty() ? "" : ", ") + std::to_string(n) + " " + name;
    std::string policy;
    for (const std::string& b : required_) policy += (policy.empty() ? "require " : ",") + b;
    if (o_.strict) policy += (policy.empty() ? "" : "; ") + std::string("strict");
    std::printf("parity run: %s in %s (rendering %.1f s of %.1f s in child processes; policy: %s); report %s\n",
                line.c_str(), fmtDuration(wall).c_str(), renderS, childS, policy.empty() ? "default" : policy.c_str(),
                (fs::path(o_.outDir) / "report" / "index.html").c_str());
    for (const auto& [b, why] : unmet)
      std::printf("parity run: FAILED: required backend %s unavailable: %s\n", b.c_str(), why.c_str());
    if (unmet.empty() && !o_.filters.cases.empty() && !cases_.empty() &&
        std::all_of(cases_.begin(), cases_.end(), [](const CaseState& c) { return c.result == CaseResult::Skip; }))
      return 77;  // CTest's SKIP_RETURN_CODE
    return bad ? 2 : 0;
  }

 private:
  int jobs() const {
    int j = o_.jobs > 0 ? o_.jobs : static_cast<int>(std::thread::hardware_concurrency());
    return std::max(1, j);
  }

  fs::path caseDir(const CaseKey& k) const {
    return fs::path(o_.outDir) / "cases" / k.technique / k.scene / k.platform;
  }
  std::string rel(const fs::path& p) const { return fs::relative(p, o_.outDir).string(); }

  const Expectation* expectedFor(const CaseState& c) const {
    std::string device = c.device.value("renderer", "") + " | " + c.device.value("driver", "");
    return findExpectation(expectations_, c.key.id(), device);
  }

  void runAll(const std::vector<size_t>& list, bool rerun) {
    std::atomic<size_t> next{0};
    auto worker = [&] {
      for (size_t n; (n = next.fetch_add(1)) < list.size();) attempt(cases_[list[n]], rerun);
    };
    std::vector<std::thread> threads;
    int count = std::min<int>(jobs(), static_cast<int>(list.size()));
    for (int t = 0; t < count; ++t) threads.emplace_back(worker);
    for (auto& t : threads) t.join();
  }

  void attempt(CaseState& c, bool rerun) {
    if (!o_.imagesDir.empty()) return attemptExternal(c, rerun);
    if (c.key.technique == kScriptTechnique) return attemptScript(c, rerun);
    std::string unavailable;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto b = backends_.find(c.key.backend);
      if (b != backends_.end() && !b->second.available) unavailable = b->second.reason;
    }
    if (!unavailable.empty())
      return finishAttempt(c, rerun, CaseResult::Skip, "backend " + c.key.backend + " unavailable: " + unavailable, 0,
                           ProcessResult{}, nlohmann::json::object(), nlohmann::json::object(), false);
    fs::path dir = caseDir(c.key);
    std::error_code ec;
    fs::create_directories(dir, ec);
    std::string image = (dir / (c.key.backend + ".png")).string();
    std::vector<std::string> args = {selfExecutable(), "run-case", "--case", c.key.id(), "--size", o_.size,
                                     "--gl-provider", o_.glProvider, "--repeat", std::to_string(o_.repeat), "-o", image};
    auto fault = faults_.find(c.key.id());
    if (fault != faults_.end()) {
      fs::create_directories(fs::path(o_.outDir) / ".faults", ec);
      std::string state = c.key.id();
      std::replace(state.begin(), state.end(), '/', '.');
      args.insert(args.end(), {"--fault", fault->second, "--fault-state", (fs::path(o_.outDir) / ".faults" / state).string()});
    }
    auto start = std::chrono::steady_clock::now();
    ProcessResult p = runProcess(args, o_.timeout);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    CaseResult r;
    std::string reason;
    nlohmann::json worker = nlohmann::json::object(), golden = nlohmann::json::object();
    if (childDied(p, &r, &reason)) {
      // r and reason say how
    } else if (p.exitCode == kExitBackendUnavailable) {
      nlohmann::json said = nlohmann::json::parse(p.out, nullptr, false);
      std::string why = said.is_object() ? said.value("unavailable", "") : oneLine(p.err);
      if (why.empty()) why = "the child gave no reason";
      r = CaseResult::Skip;
      reason = "backend " + c.key.backend + " unavailable: " + oneLine(why);
      std::lock_guard<std::mutex> lock(mutex_);
      BackendInfo& b = backends_[c.key.backend];
      if (!b.available) b.reason = why;
    } else if (p.exitCode != 0) {
      r = CaseResult::Fail;
      reason = "render failed: " + oneLine(p.err);
    } else {
      try {
        worker = nlohmann::json::parse(p.out);
      } catch (const std::exception& e) {
        worker = nlohmann::json::object();
      }
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
        r = compareGolden(c, image, worker, &golden, &reason);
        r = judgeDiagnostics(c, r, worker, &golden, &reason);
        double compareS = std::chrono::duration<double>(std::chrono::steady_clock::now() - compareStart).count();
        std::lock_guard<std::mutex> lock(mutex_);
        compareSeconds_ += compareS;
      }
    }
    finishAttempt(c, rerun, r, reason, seconds, p, worker, golden, true);
  }

  // Another program's render (harness/external_images.h): read instead of rendered, then judged
  // as a render is.
  void attemptExternal(CaseState& c, bool rerun) {
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

  // A script case: `parity test --in-process` in a child, with the drivers' validation on as the
  // test suite runs scripts; its JSON line is the result. No image, no golden: the script's own
  // expectations are the verdict (*.expect_fail.amber applied here, never to a rule broken).
  void attemptScript(CaseState& c, bool rerun) {
    const std::string& path = scripts_.at(c.key.scene);
    std::vector<std::string> args = {selfExecutable(), "test",   "--in-process", "--debug",   "--backend",
                                     c.key.backend,    "--platform", c.key.platform, path};
    auto start = std::chrono::steady_clock::now();
    ProcessResult p = runProcess(args, o_.timeout);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    CaseResult r = CaseResult::Fail;
    std::string reason;
    nlohmann::json worker = nlohmann::json::object();
    nlohmann::json line;
    std::istringstream lines(p.out);
    for (std::string l; line.is_null() && std::getline(lines, l);)
      if (!l.empty() && l[0] == '{') line = nlohmann::json::parse(l, nullptr, false);
    if (childDied(p, &r, &reason)) {
      // r and reason say how
    } else if (!line.is_object() || !line.contains("result") || !line["result"].is_string()) {
      reason = "the script's child printed no result (exit " + std::to_string(p.exitCode) + "): " + oneLine(p.err);
    } else {
      script::RunResult s;
      std::string v = line["result"];
      s.verdict = v == "PASS" ? script::Verdict::Pass : v == "SKIP" ? script::Verdict::Skip : script::Verdict::Fail;
      s.reason = line.value("reason", "");
      s = script::applyExpectFail(s, script::isExpectFail(path) && !line.value("invalid", false));
      r = s.verdict == script::Verdict::Pass ? CaseResult::Pass
          : s.verdict == script::Verdict::Skip ? CaseResult::Skip
                                               : CaseResult::Fail;
      reason = oneLine(s.reason);
      worker = {{"script", path}, {"expects", line.value("expects", nlohmann::json::array())}};
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
    finishAttempt(c, rerun, r, reason, seconds, p, worker, nlohmann::json::object(), false);
  }

  // A child that could not start, ran past the timeout or died from a signal: Crash or Timeout.
  bool childDied(const ProcessResult& p, CaseResult* r, std::string* reason) const {
    if (!p.startError.empty()) {
      *r = CaseResult::Crash;
      *reason = "cannot start the child process: " + p.startError;
    } else if (p.timedOut) {
      *r = CaseResult::Timeout;
      *reason = "no result after " + std::to_string(static_cast<int>(o_.timeout)) + " s; the child was killed";
    } else if (p.crashed) {
      *r = CaseResult::Crash;
      *reason = "the child died from signal " + std::to_string(p.signal) + " (" + strsignal(p.signal) + ")";
    } else {
      return false;
    }
    return true;
  }

  void finishAttempt(CaseState& c, bool rerun, CaseResult r, const std::string& reason, double seconds,
                     const ProcessResult& p, const nlohmann::json& worker, const nlohmann::json& golden, bool image) {
    std::lock_guard<std::mutex> lock(mutex_);
    c.childSeconds += seconds;
    c.attempts.push_back({{"result", resultName(r)}, {"seconds", seconds}, {"reason", reason}});
    if (!p.err.empty()) c.stderrText = oneLine(p.err);
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

  CaseResult compareGolden(CaseState& c, const std::string& image, const nlohmann::json& worker, nlohmann::json* out,
                           std::string* reason) {
    std::string golden = goldenPath(goldenDir_, c.key.technique, c.key.scene, c.key.platform);
    fs::path dir = caseDir(c.key);
    nlohmann::json& j = *out;
    j["golden"] = goldenKey(c.key.technique, c.key.scene, c.key.platform) + ".png";
    j["tolerance"] = {{"fail", c.tolerance.golden.fail}, {"fail_percent", c.tolerance.golden.failPercent},
                      {"hard_fail", std::isfinite(c.tolerance.golden.hardFail) ? nlohmann::json(c.tolerance.golden.hardFail)
                                                                                 : nlohmann::json("inf")},
                      {"flip_mean", c.tolerance.flipMean},
                      {"source", c.tolerance.source}};
    compareTargets(c, worker, &j);
    std::error_code ec;
    if (!fs::exists(golden, ec)) {
      j["missing"] = true;
      *reason = "no golden golden/" + j["golden"].get<std::string>() + ": check the images of this run, then create it with "
                "`parity bless --technique " + c.key.technique + " --scene " + c.key.scene + " --platform " +
                c.key.platform + " --from " + o_.outDir + "`";
      return CaseResult::Fail;
    }
    std::string copy = (dir / "golden.png").string();
    {
      std::lock_guard<std::mutex> lock(mutex_);  // both backends of a group copy the same golden
      std::string err;
      if (!fs::exists(copy, ec) && !copyFileAtomic(golden, copy, &err)) {
        *reason = err;
        return CaseResult::Fail;
      }
    }
    j["golden_copy"] = rel(copy);
    DiffResult d = diffFiles(image, golden, c.tolerance.golden);
    j["metrics"] = toJson(d);
    OIIO::ImageBuf a, b;
    std::string err;
    bool images = d.verdict != DiffVerdict::SizeMismatch && d.verdict != DiffVerdict::FileError &&
                  readImage(image, &a, &err) && readImage(golden, &b, &err);
    if (images && d.maxError > 0) {
      std::string heat = (dir / ("diff-golden-" + c.key.backend + ".png")).string();
      if (writeHeatmap(a, b, heat, &err)) j["heatmap"] = rel(heat);
    }
    bool flipFails = false;
    if (images) {
      FlipResult flip = d.maxError > 0 ? computeLdrFlip(b, a) : FlipResult{};
      if (d.maxError == 0) {  // identical: FLIP is zero by definition, no need to filter
        flip.ok = true;
        flip.pixelsPerDegree = flipDefaultPixelsPerDegree();
      }
      j["flip"] = toJson(flip);
      std::string map = (dir / ("flip-golden-" + c.key.backend + ".png")).string();
      if (flip.ok && flip.max > 0 && writeFlipMap(flip, map, &err)) j["flip_map"] = rel(map);
      flipFails = flip.ok && flip.mean > c.tolerance.flipMean;
    }
    bool fails = d.verdict == DiffVerdict::Fail || d.verdict == DiffVerdict::SizeMismatch ||
                 d.verdict == DiffVerdict::FileError || flipFails;
    if (!fails && !j.contains("first_diverging_pass")) return CaseResult::Pass;
    if (!fails) {
      // The image passes, an intermediate target does not: a regression the final image hides.
      *reason = "pass " + j["first_diverging_pass"]["pass"].get<std::string>() + ": " +
                j["first_diverging_pass"]["detail"].get<std::string>();
      return CaseResult::Fail;
    }
    *reason = "differs from golden/" + j["golden"].get<std::string>() + ": " + summaryLine(d);
    if (j.contains("flip") && j["flip"].contains("mean")) {
      std::ostringstream f;
      f << "; FLIP mean " << j["flip"]["mean"].get<double>() << " (tolerance " << c.tolerance.flipMean << ")";
      *reason += f.str();
    }
    if (images)
      if (std::optional<Diagnosis> dx = diagnose(b, a)) {
        j["diagnosis"] = toJson(*dx);
        *reason += "; likely cause: " + dx->cause;
      }
    if (j.contains("first_diverging_pass"))
      *reason += "; first diverging pass: " + j["first_diverging_pass"]["pass"].get<std::string>() + " (target " +
                 j["first_diverging_pass"]["target"].get<std::string>() + ")";
    return CaseResult::Fail;
  }

  // The platform layer's diagnostics of the case's real targets and resolves reach the verdict:
  // an error-level one fails a case whose image passed, unless golden/expectations.json expects
  // its code for the case ({"case", "diagnostic", "reason"}): then the case is an ExpectedFail.
  // An expected diagnostic that no longer fires makes a passing case an UnexpectedPass. Each
  // diagnostic is kept in the case's golden comparison, marked with its expectation.
  CaseResult judgeDiagnostics(const CaseState& c, CaseResult r, const nlohmann::json& worker, nlohmann::json* golden,
                              std::string* reason) const {
    nlohmann::json diagnostics = worker.value("diagnostics", nlohmann::json::array());
    std::string device = worker.value("renderer", "") + " | " + worker.value("driver", "");
    std::vector<const Expectation*> expected = findDiagnosticExpectations(expectations_, c.key.id(), device);
    std::vector<std::string> unexpected, expectedFired;
    std::set<const Expectation*> used;
    for (nlohmann::json& d : diagnostics) {
      if (d.value("severity", "") != "error") continue;
      const std::string code = d.value("code", "");
      auto e = std::find_if(expected.begin(), expected.end(),
                            [&](const Expectation* x) { return globMatch(x->diagnosticPattern, code); });
      if (e != expected.end()) {
        d["expected"] = (*e)->reason;
        used.insert(*e);
        const std::string fired = code + " (" + (*e)->reason + ")";
        if (std::find(expectedFired.begin(), expectedFired.end(), fired) == expectedFired.end()) expectedFired.push_back(fired);
      } else {
        unexpected.push_back(code + ": " + d.value("message", ""));
      }
    }
    (*golden)["diagnostics"] = diagnostics;
    (*golden)["image_matches"] = r == CaseResult::Pass;  // the group verdict is about images
    auto joined = [](const std::vector<std::string>& v) {
      std::string s;
      for (const std::string& x : v) s += (s.empty() ? "" : "; ") + x;
      return s;
    };
    if (r != CaseResult::Pass) {
      if (!unexpected.empty()) *reason += "; platform diagnostics: " + joined(unexpected);
      return r;
    }
    if (!unexpected.empty()) {
      *reason = "platform diagnostic " + joined(unexpected);
      return CaseResult::Fail;
    }
    if (!expectedFired.empty()) {
      *reason = "expected platform diagnostic " + joined(expectedFired) + "; the image matches its golden";
      return CaseResult::ExpectedFail;
    }
    for (const Expectation* e : expected)
      if (!used.count(e)) {
        *reason = "expected platform diagnostic " + e->diagnosticPattern + " (" + e->reason +
                  ") did not fire: remove the expectation";
        return CaseResult::UnexpectedPass;
      }
    return r;
  }

  // Each target the child wrote against golden/<technique>/<scene>/<platform>/<file>, with the
  // metric of its kind; the first pass (in the technique's order) writing a differing target is
  // where the case starts to diverge.
  void compareTargets(CaseState& c, const nlohmann::json& worker, nlohmann::json* out) {
    fs::path dir = caseDir(c.key);
    fs::path goldenTargets = fs::path(goldenDir_) / c.key.technique / c.key.scene / c.key.platform;
    std::map<std::string, bool> targetPass;
    std::map<std::string, std::string> targetDetail;
    for (const auto& t : worker.value("targets", nlohmann::json::array())) {
      std::string name = t.value("name", ""), file = t.value("file", "");
      nlohmann::json e{{"name", name}, {"format", t.value("format", "")}, {"image", rel(dir / file)}};
      AttachmentClass cls = classifyAttachment(name, t.value("format", ""), t.value("logical", ""), c.key.platform);
      e["kind"] = attachmentKindName(cls.kind);
      // Read once: compared with its golden, and EXR data also shown as a PNG with the mapping stated.
      OIIO::ImageBuf image;
      std::string readError;
      const bool readable = readImage((dir / file).string(), &image, &readError);
      if (readable && fs::path(file).extension() == ".exr") {
        OIIO::ImageBuf preview;
        std::string err;
        const fs::path png = dir / (fs::path(file).replace_extension(".preview.png"));
        const std::string mapping = previewOf(cls, image, &preview);
        if (writeImage(png.string(), preview, &err)) e["preview"] = {{"image", rel(png)}, {"mapping", mapping}};
      }
      fs::path golden = goldenTargets / fs::path(file).filename();
      std::error_code ec;
      if (fs::exists(golden, ec)) {
        OIIO::ImageBuf g;
        std::string err = readError;
        AttachmentMetrics m;
        const TargetTolerance* relaxed = c.tolerance.forTarget(name);
        if (readable && readImage(golden.string(), &g, &err))
          m = compareAttachment(cls, g, image, relaxed ? relaxed->attachments : c.tolerance.attachments);
        else
          m.error = err;
        e["golden"] = (fs::path(c.key.technique) / c.key.scene / c.key.platform / fs::path(file).filename()).string();
        e["metrics"] = toJson(m);
        if (relaxed) e["tolerance"] = {{"source", relaxed->source}, {"reason", relaxed->reason}};
        targetPass[name] = m.ok && m.pass;
        std::ostringstream detail;
        if (!m.ok)
          detail << "target " << name << " not compared with its golden: " << m.error;
        else
          detail << "target " << name << " differs from golden/" << e["golden"].get<std::string>() << ": " << m.metric
                 << " max " << m.max << " over " << m.threshold << " in " << m.differing << " of " << m.pixels
                 << " pixels";
        targetDetail[name] = detail.str();
      } else {
        e["golden"] = nullptr;  // the technique declares it, no per-pass golden blessed yet
      }
      (*out)["targets"].push_back(e);
    }
    for (const auto& p : worker.value("passes", nlohmann::json::array()))
      for (const auto& t : p.value("targets", nlohmann::json::array())) {
        auto it = targetPass.find(t.get<std::string>());
        if (it != targetPass.end() && !it->second) {
          (*out)["first_diverging_pass"] = {
              {"pass", p.value("name", "")}, {"target", it->first}, {"detail", targetDetail[it->first]}};
          return;
        }
      }
    // A differing target no pass lists still fails the case.
    for (const auto& [name, pass] : targetPass)
      if (!pass) {
        (*out)["first_diverging_pass"] = {{"pass", "(not in the technique's pass list)"}, {"target", name},
                                          {"detail", targetDetail[name]}};
        return;
      }
  }

  void progress(const CaseState& c, CaseResult r) {
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

  // GL↔Vulkan per group, the triangulated verdict, and ParityWarning.
  void compareGroups() {
    std::map<std::string, std::vector<CaseState*>> groups;
    for (CaseState& c : cases_) groups[c.key.group()].push_back(&c);
    for (auto& [name, members] : groups) {
      nlohmann::json g{{"group", name}};
      if (members.front()->key.technique == kScriptTechnique) {
        for (CaseState* c : members) g["results"][c->key.backend] = resultName(c->result);
        g["verdict"] = "script (each backend checks the script's own expectations)";
        groups_.push_back(g);
        continue;
      }
      CaseState* gl = nullptr;
      CaseState* vk = nullptr;
      for (CaseState* c : members) {
        if (c->key.backend == "gl") gl = c;
        if (c->key.backend == "vk") vk = c;
        g["results"][c->key.backend] = resultName(c->result);
      }
      bool both = gl && vk && gl->rendered && vk->rendered;
      if (both) {
        fs::path dir = caseDir(gl->key);
        std::string a = (dir / "gl.png").string(), b = (dir / "vk.png").string();
        DiffResult d = diffFiles(a, b, gl->tolerance.parity);
        g["parity"] = toJson(d);
        if (d.maxError > 0) {
          OIIO::ImageBuf ia, ib;
          std::string err;
          std::string heat = (dir / "diff-gl-vk.png").string();
          if (readImage(a, &ia, &err) && readImage(b, &ib, &err) && d.verdict != DiffVerdict::SizeMismatch &&
              writeHeatmap(ia, ib, heat, &err))
            g["parity"]["heatmap"] = rel(heat);
        }
        bool parityOk = d.verdict == DiffVerdict::Pass || d.verdict == DiffVerdict::Warn;
        auto goldenOk = [](const CaseState* c) {
          return c->raw == CaseResult::Pass || c->raw == CaseResult::Flake || c->golden.value("image_matches", false);
        };
        auto goldenMissing = [](const CaseState* c) { return c->golden.value("missing", false); };
        std::string verdict;
        if (goldenMissing(gl)) verdict = parityOk ? "no golden (backends agree)" : "no golden (backends differ)";
        else if (goldenOk(gl) && goldenOk(vk)) verdict = parityOk ? "pass" : "parity warning";
        else if (goldenOk(gl) && !goldenOk(vk)) verdict = "vk regression";
        else if (!goldenOk(gl) && goldenOk(vk)) verdict = "gl regression";
        else if (parityOk) verdict = staleGolden(*gl) ? "stale golden" : "technique regression";
        else verdict = "gl and vk regression";
        g["verdict"] = verdict;
        if (verdict == "parity warning")
          for (CaseState* c : {gl, vk})
            if (c->result == CaseResult::Pass) {
              c->result = c->raw = CaseResult::ParityWarning;
              c->reason = "matches the golden, but GL and Vulkan differ beyond the parity budget: " + summaryLine(d);
            }
        for (CaseState* c : {gl, vk}) c->golden["verdict"] = verdict;
      } else {
        g["verdict"] = "no comparison (fewer than two backends rendered)";
      }
      groups_.push_back(g);
    }
  }

  // Both backends differ from the golden the same way: the golden is stale when it was made on
  // another driver than the one this run used; otherwise the technique changed.
  bool staleGolden(const CaseState& c) const {
    const std::string key = c.key.group();
    if (!manifest_["goldens"].contains(key)) return false;
    const nlohmann::json prov = manifest_["goldens"][key].value("backends", nlohmann::json::object());
    if (!prov.is_object()) return false;
    if (!prov.contains(c.key.backend)) return false;
    return prov[c.key.backend].value("renderer", "") != c.device.value("renderer", "") ||
           prov[c.key.backend].value("driver", "") != c.device.value("driver", "");
  }

  void applyExpectation(CaseState& c) {
    const Expectation* e = expectedFor(c);
    if (!e) return;
    c.expectation = e->reason;
    c.expected = resultName(e->result);
    if (c.raw == e->result && c.result != CaseResult::Flake) {
      if (c.result != CaseResult::Skip) {
        c.reason = "expected " + c.expected + " (" + e->reason + "): " + c.reason;
        c.result = CaseResult::ExpectedFail;
      }
    } else if (c.result == CaseResult::Pass) {
      c.result = CaseResult::UnexpectedPass;
      c.reason = "expected " + c.expected + " (" + e->reason + ") but it passed: remove the expectation";
    } else if (c.result != CaseResult::Skip) {
      c.reason = "expected " + c.expected + " (" + e->reason + "), got " + resultName(c.raw) + ": " + c.reason;
    }
  }

  nlohmann::json caseJson(const CaseState& c) const {
    nlohmann::json j{{"id", c.key.id()},          {"technique", c.key.technique}, {"scene", c.key.scene},
                     {"platform", c.key.platform}, {"backend", c.key.backend},     {"result", resultName(c.result)}};
    if (!c.reason.empty()) j["reason"] = c.reason;
    if (c.rendered) {
      j["image"] = rel(caseDir(c.key) / (c.key.backend + ".png"));
      j["deterministic"] = c.worker.value("deterministic", false);
      j["render_ms"] = c.worker.value("render_ms", nlohmann::json::array());
    }
    if (!c.device.empty()) j.update(c.device);
    if (!c.golden.empty()) j["golden"] = c.golden;
    if (c.golden.contains("targets")) j["targets"] = c.golden["targets"];
    if (c.worker.contains("passes")) j["passes"] = c.worker["passes"];
    if (c.worker.contains("pass_ms")) j["pass_ms"] = c.worker["pass_ms"];
    if (c.worker.contains("lost_light")) j["lost_light"] = c.worker["lost_light"];
    if (c.worker.contains("script")) j["script"] = c.worker["script"];
    if (c.worker.contains("external")) j["external"] = c.worker["external"];
    if (c.worker.contains("expects")) j["expects"] = c.worker["expects"];
    if (!c.attempts.empty()) j["attempts"] = c.attempts;
    if (!c.stderrText.empty()) j["stderr"] = c.stderrText;
    if (!c.expectation.empty()) j["expectation"] = {{"result", c.expected}, {"reason", c.expectation}};
    j["child_s"] = c.childSeconds;
    return j;
  }

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

}  // namespace

int runMatrix(const RunOptions& options) {
  Runner runner(options);
  return runner.run();
}

int listCases(const RunFilters& filters, const Shard& shard, bool ctest, const std::string& binary,
              const std::string& outRoot) {
  std::string error;
  std::vector<CaseKey> keys = enumerateCases(filters, shard, &error);
  if (!error.empty()) return reportError(error);
  for (const CaseKey& k : keys) {
    if (!ctest) {
      std::printf("%s\n", k.id().c_str());
      continue;
    }
    std::string name = "parity." + k.technique + "." + k.scene + "." + k.platform + "." + k.backend;
    std::string out = (fs::path(outRoot) / (k.technique + "." + k.scene + "." + k.platform + "." + k.backend)).string();
    std::printf("add_test([==[%s]==] [==[%s]==] run --case [==[%s]==] --out [==[%s]==] --jobs 1 --no-progress)\n",
                name.c_str(), binary.c_str(), k.id().c_str(), out.c_str());
    // A case that would render but has no checked-in golden is registered disabled (CTest lists
    // it as "Not Run (Disabled)"): `parity run` reports it as a Fail saying how to bless it.
    std::error_code ec;
    bool noGolden = k.technique != kScriptTechnique && platformHasRenderPath(k.platform) &&
                    !fs::exists(goldenPath(defaultGoldenDir(), k.technique, k.scene, k.platform), ec);
    std::printf("set_tests_properties([==[%s]==] PROPERTIES LABELS \"%s;%s;%s;%s\" SKIP_RETURN_CODE 77 TIMEOUT 300%s)\n",
                name.c_str(), k.backend.c_str(), k.platform.c_str(), k.technique.c_str(), k.scene.c_str(),
                noGolden ? " DISABLED TRUE" : "");
  }
  return 0;
}

namespace {

// What `parity merge` and the reports read from a results.json, which may come from another
// machine or an older version: a field of the wrong type is refused up front, naming the file
// and the field, instead of throwing halfway through writing the merged output.
enum class JsonKind { String, Number, Metric, Bool, Object, Array };

bool kindMatches(const nlohmann::json& v, JsonKind kind) {
  switch (kind) {
    case JsonKind::String: return v.is_string();
    case JsonKind::Number: return v.is_number();
    case JsonKind::Metric: return v.is_number() || (v.is_string() && v.get<std::string>() == "inf");  // "inf": not finite
    case JsonKind::Bool: return v.is_boolean();
    case JsonKind::Object: return v.is_object();
    case JsonKind::Array: return v.is_array();
  }
  return false;
}

const char* kindName(JsonKind kind) {
  switch (kind) {
    case JsonKind::String: return "a string";
    case JsonKind::Number: return "a number";
    case JsonKind::Metric: return "a number";
    case JsonKind::Bool: return "true or false";
    case JsonKind::Object: return "an object";
    case JsonKind::Array: return "an array";
  }
  return "?";
}

using FieldKinds = std::initializer_list<std::pair<const char*, JsonKind>>;

class ResultsChecker {
 public:
  ResultsChecker(std::string file, std::string* error) : file_(std::move(file)), error_(error) {}

  bool check(const nlohmann::json& r) {
    if (!r.is_object()) return fail("", std::string("must be an object, not ") + r.type_name());
    if (!fields(r, "", {{"cases", JsonKind::Array}, {"groups", JsonKind::Array}, {"backends", JsonKind::Array},
                        {"timing", JsonKind::Object}, {"run_id", JsonKind::String}, {"shard", JsonKind::String},
                        {"project_commit", JsonKind::String}, {"size", JsonKind::String}, {"started", JsonKind::String},
                        {"finished", JsonKind::String}, {"gl_provider", JsonKind::String}, {"golden_dir", JsonKind::String},
                        {"repeat", JsonKind::Number}, {"retries", JsonKind::Number}, {"policy", JsonKind::Object}}))
      return false;
    if (r.contains("timing") &&
        !fields(r["timing"], "timing", {{"wall_s", JsonKind::Number}, {"child_process_s", JsonKind::Number},
                                        {"render_s", JsonKind::Number}, {"compare_s", JsonKind::Number},
                                        {"jobs", JsonKind::Number}}))
      return false;
    if (r.contains("cases") && !eachObject(r["cases"], "cases", [&](const nlohmann::json& c, const std::string& at) {
          return checkCase(c, at);
        }))
      return false;
    if (r.contains("groups") && !eachObject(r["groups"], "groups", [&](const nlohmann::json& g, const std::string& at) {
          return fields(g, at, {{"group", JsonKind::String}, {"verdict", JsonKind::String}, {"parity", JsonKind::Object},
                                {"results", JsonKind::Object}}) &&
                 (!g.contains("parity") || diffMetrics(g["parity"], at + ".parity"));
        }))
      return false;
    if (r.contains("backends") && !eachObject(r["backends"], "backends", [&](const nlohmann::json& b, const std::string& at) {
          return fields(b, at, {{"name", JsonKind::String}, {"available", JsonKind::Bool}, {"renderer", JsonKind::String},
                                {"driver", JsonKind::String}, {"api", JsonKind::String}, {"reason", JsonKind::String}});
        }))
      return false;
    return true;
  }

 private:
  bool fail(const std::string& where, const std::string& what) {
    *error_ = file_ + ": " + (where.empty() ? "" : where + " ") + what;
    return false;
  }

  bool fields(const nlohmann::json& j, const std::string& where, FieldKinds kinds) {
    for (const auto& [key, kind] : kinds) {
      if (!j.contains(key)) continue;
      const nlohmann::json& v = j[key];
      if (!kindMatches(v, kind))
        return fail("", (where.empty() ? "" : where + ".") + key + " must be " + kindName(kind) + ", not " +
                            (v.is_string() ? "\"" + oneLine(v.get<std::string>()).substr(0, 40) + "\"" : v.type_name()));
    }
    return true;
  }

  template <typename Check>
  bool eachObject(const nlohmann::json& list, const std::string& where, Check check) {
    for (size_t i = 0; i < list.size(); ++i) {
      std::string at = where + "[" + std::to_string(i) + "]";
      if (!list[i].is_object()) return fail("", at + " must be an object, not " + std::string(list[i].type_name()));
      if (!check(list[i], at)) return false;
    }
    return true;
  }

  bool numbers(const nlohmann::json& list, const std::string& where) {
    for (size_t i = 0; i < list.size(); ++i)
      if (!list[i].is_number())
        return fail("", where + "[" + std::to_string(i) + "] must be a number, not " + list[i].type_name());
    return true;
  }

  bool diffMetrics(const nlohmann::json& m, const std::string& where) {
    return fields(m, where, {{"verdict", JsonKind::String}, {"message", JsonKind::String}, {"exit_code", JsonKind::Number},
                             {"width", JsonKind::Number}, {"height", JsonKind::Number}, {"channels", JsonKind::Number},
                             {"max_error", JsonKind::Metric}, {"mean_error", JsonKind::Metric},
                             {"rms_error", JsonKind::Metric}, {"psnr", JsonKind::Metric}, {"pixels", JsonKind::Number},
                             {"pixels_over_fail", JsonKind::Number}, {"share_over_fail", JsonKind::Metric},
                             {"pixels_over_warn", JsonKind::Number}, {"share_over_warn", JsonKind::Metric}});
  }

  bool checkCase(const nlohmann::json& c, const std::string& at) {
    if (!c.contains("id")) return fail("", at + " has no id");
    if (!c.contains("result")) return fail("", at + " has no result");
    if (!fields(c, at, {{"id", JsonKind::String}, {"result", JsonKind::String}, {"technique", JsonKind::String},
                        {"scene", JsonKind::String}, {"platform", JsonKind::String}, {"backend", JsonKind::String},
                        {"reason", JsonKind::String}, {"image", JsonKind::String}, {"renderer", JsonKind::String},
                        {"driver", JsonKind::String}, {"api", JsonKind::String}, {"stderr", JsonKind::String},
                        {"child_s", JsonKind::Number}, {"deterministic", JsonKind::Bool}, {"render_ms", JsonKind::Array},
                        {"pass_ms", JsonKind::Array}, {"targets", JsonKind::Array}, {"golden", JsonKind::Object},
                        {"attempts", JsonKind::Array}, {"passes", JsonKind::Array}}))
      return false;
    if (c.contains("render_ms") && !numbers(c["render_ms"], at + ".render_ms")) return false;
    if (c.contains("pass_ms") && !eachObject(c["pass_ms"], at + ".pass_ms", [&](const nlohmann::json& t, const std::string& in) {
          return fields(t, in, {{"pass", JsonKind::String}, {"ms", JsonKind::Number}});
        }))
      return false;
    if (c.contains("targets") && !eachObject(c["targets"], at + ".targets", [&](const nlohmann::json& t, const std::string& in) {
          return fields(t, in, {{"name", JsonKind::String}, {"format", JsonKind::String}, {"kind", JsonKind::String},
                                {"image", JsonKind::String}, {"metrics", JsonKind::Object},
                                {"preview", JsonKind::Object}}) &&
                 (!t.contains("metrics") ||
                  fields(t["metrics"], in + ".metrics", {{"metric", JsonKind::String}, {"max", JsonKind::Metric},
                                                         {"mean", JsonKind::Metric}, {"pass", JsonKind::Bool}}));
        }))
      return false;
    if (c.contains("golden")) {
      const nlohmann::json& g = c["golden"];
      std::string in = at + ".golden";
      if (!fields(g, in, {{"golden", JsonKind::String}, {"golden_copy", JsonKind::String}, {"heatmap", JsonKind::String},
                          {"flip_map", JsonKind::String}, {"verdict", JsonKind::String}, {"missing", JsonKind::Bool},
                          {"metrics", JsonKind::Object}, {"flip", JsonKind::Object}, {"diagnosis", JsonKind::Object},
                          {"first_diverging_pass", JsonKind::Object}}))
        return false;
      if (g.contains("metrics") && !diffMetrics(g["metrics"], in + ".metrics")) return false;
      if (g.contains("flip") &&
          !fields(g["flip"], in + ".flip", {{"mean", JsonKind::Metric}, {"weighted_median", JsonKind::Metric},
                                            {"weighted_quartile_1", JsonKind::Metric}, {"weighted_quartile_3", JsonKind::Metric},
                                            {"min", JsonKind::Metric}, {"max", JsonKind::Metric}}))
        return false;
      if (g.contains("diagnosis") &&
          !fields(g["diagnosis"], in + ".diagnosis", {{"cause", JsonKind::String}, {"detail", JsonKind::String}}))
        return false;
      if (g.contains("first_diverging_pass") &&
          !fields(g["first_diverging_pass"], in + ".first_diverging_pass",
                  {{"pass", JsonKind::String}, {"target", JsonKind::String}}))
        return false;
    }
    return true;
  }

  std::string file_;
  std::string* error_;
};

}  // namespace

int mergeRuns(const std::vector<std::string>& inputs, const std::string& outDir) {
  // Every input is read and checked before the output folder is created, so a bad input fails
  // the merge with one line and leaves nothing behind.
  std::vector<nlohmann::json> runs;
  std::set<std::string> ids;
  for (const std::string& in : inputs) {
    std::string file = (fs::path(in) / "results.json").string();
    std::ifstream f(file);
    if (!f) return reportError(in + ": no results.json (not a `parity run` output folder)");
    nlohmann::json r;
    try {
      f >> r;
    } catch (const std::exception& e) {
      return reportError(file + ": not valid JSON: " + e.what());
    }
    std::string error;
    if (!ResultsChecker(file, &error).check(r)) return reportError(error);
    for (const auto& c : r.value("cases", nlohmann::json::array()))
      if (!ids.insert(c["id"].get<std::string>()).second)
        return reportError(file + ": case " + c["id"].get<std::string>() + " appears in more than one input");
    runs.push_back(std::move(r));
  }

  std::error_code ec;
  bool existed = fs::exists(outDir, ec);
  // Output this merge created is removed again when the merge fails partway.
  auto failMerge = [&](const std::string& message) {
    if (!existed) fs::remove_all(outDir, ec);
    return reportError(message);
  };
  fs::create_directories(fs::path(outDir) / "cases", ec);
  if (ec) return failMerge(outDir + ": cannot create output folder: " + ec.message());
  nlohmann::json merged{{"schema", "parity-results/1"}, {"merged_from", nlohmann::json::array()}};
  std::map<std::string, nlohmann::json> backends;
  std::set<std::string> required;  // the inputs' exit policies, joined
  bool strict = false;
  double wall = 0, child = 0, render = 0, compare = 0;
  for (size_t i = 0; i < inputs.size(); ++i) {
    const std::string& in = inputs[i];
    const nlohmann::json& r = runs[i];
    for (const char* field : {"project_commit", "size", "gl_provider", "repeat", "retries", "golden_dir", "run_id", "started"})
      if (!merged.contains(field) && r.contains(field)) merged[field] = r[field];
    merged["merged_from"].push_back({{"folder", in}, {"run_id", r.value("run_id", "")}, {"shard", r.value("shard", "")}});
    for (const auto& c : r.value("cases", nlohmann::json::array())) merged["cases"].push_back(c);
    for (const auto& g : r.value("groups", nlohmann::json::array())) merged["groups"].push_back(g);
    const nlohmann::json policy = r.value("policy", nlohmann::json::object());
    for (const auto& b : policy.value("require_backends", nlohmann::json::array()))
      if (b.is_string()) required.insert(b.get<std::string>());
    strict = strict || policy.value("strict", false) == true;
    for (const auto& b : r.value("backends", nlohmann::json::array())) {
      std::string name = b.value("name", "");
      if (!backends.count(name) || b.value("available", false)) backends[name] = b;
    }
    const nlohmann::json& t = r.value("timing", nlohmann::json::object());
    wall = std::max(wall, t.value("wall_s", 0.0));
    child += t.value("child_process_s", 0.0);
    render += t.value("render_s", 0.0);
    compare += t.value("compare_s", 0.0);
    // Image by image, each replaced whole: a merge killed midway leaves every image old or new.
    // Links are not followed (an input's link could point anywhere), and an input's own
    // temporaries are not copied.
    const fs::path cases = fs::path(in) / "cases";
    if (fs::is_directory(cases, ec)) {
      for (fs::recursive_directory_iterator it(cases, ec), end; !ec && it != end; it.increment(ec)) {
        if (it->is_symlink() || !it->is_regular_file() || it->path().filename().string().rfind(".parity-tmp-", 0) == 0)
          continue;
        std::string copyError;
        if (!copyFileAtomic(it->path().string(), (fs::path(outDir) / "cases" / fs::relative(it->path(), cases)).string(),
                            &copyError))
          return failMerge(in + ": cannot copy its images: " + copyError);
      }
    }
    if (ec) return failMerge(in + ": cannot copy its images: " + ec.message());
  }
  for (auto& [name, b] : backends) merged["backends"].push_back(b);
  // A required backend fails the merge unless some input rendered with it.
  merged["policy"] = {{"require_backends", std::vector<std::string>(required.begin(), required.end())}, {"strict", strict}};
  for (const std::string& b : required)
    if (!backends.count(b) || !backends[b].value("available", false))
      merged["policy"]["unavailable"][b] = backends.count(b) ? backends[b].value("reason", "unavailable") : "no case of it rendered";
  merged["timing"] = {{"wall_s", wall}, {"child_process_s", child}, {"render_s", render}, {"compare_s", compare}};
  merged["finished"] = nowIso();
  std::string error;
  try {
    if (!writeReports(outDir, merged, &error)) return failMerge(error);
  } catch (const std::exception& e) {
    // The checks above cover what the reports read; this keeps anything they missed one line.
    return failMerge(outDir + ": cannot write the merged report: " + e.what());
  }
  bool bad = merged["policy"].contains("unavailable");
  std::map<std::string, int> counts;
  for (const auto& c : merged.value("cases", nlohmann::json::array())) {
    CaseResult r = CaseResult::Fail;
    parseResultName(c.value("result", ""), &r);
    bad = bad || isBadResult(r, strict);
    counts[c.value("result", "?")]++;
  }
  std::string line;
  for (const auto& [name, n] : counts) line += (line.empty() ? "" : ", ") + std::to_string(n) + " " + name;
  std::printf("parity merge: %zu inputs, %s; report %s\n", inputs.size(), line.c_str(),
              (fs::path(outDir) / "report" / "index.html").c_str());
  return bad ? 2 : 0;
}

}  // namespace parity::harness
