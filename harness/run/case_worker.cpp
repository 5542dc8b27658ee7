// The child process of rendered cases (hidden `parity run-case`): renders each, repeats, writes
// the image and targets, prints its JSON.
#include "harness/run/devices.h"
#include "harness/run/run.h"

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

namespace fs = std::filesystem;

namespace parity::harness {

// ---------------------------------------------------------------------------------------------
// The child: its cases in turn on one device, each rendered `repeat` times

// Milliseconds since `start`.
static double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

namespace {

// A case's frame request from its key; false with the reason when the key names no scene or
// platform, or the size is not WIDTHxHEIGHT.
bool prepareRequest(const CaseKey& key, const CaseWorkerOptions& o, RenderRequest* request, std::string* error) {
  request->backend = key.backend;
  request->glProvider = o.glProvider;
  request->frame.technique = key.technique;
  request->frame.scene = key.scene;
  if (!parseSize(o.size, &request->frame.width, &request->frame.height, error)) return false;
  scene::Scene sc;
  if (!scene::makeScene(key.scene, {}, &sc, error)) return false;
  if (!sc.cameras.empty() &&
      std::none_of(sc.cameras.begin(), sc.cameras.end(), [](const auto& c) { return c.name == "default"; }))
    request->frame.camera = sc.cameras.front().name;
  std::optional<platforms::PlatformId> platform = platforms::platformFromName(key.platform);
  if (!platform) {
    *error = "unknown platform '" + key.platform + "'";
    return false;
  }
  request->frame.platform = *platform;
  request->frame.readTargets = true;
  return true;
}

// The faults that end the process once its device exists (test-only, `run-case --fault`).
void faultAfterDevice(const std::string& fault) {
  if (fault == "crash") ::raise(SIGSEGV);
  if (fault == "abort") {
    std::fprintf(stderr, "injected abort\n");
    std::abort();
  }
  if (fault == "oom") {
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
  if (fault == "hang")
    for (;;) ::pause();
}

// The faults that change a rendered result (test-only): a regression the comparisons must find.
void faultInResult(const std::string& fault, RenderResult& result) {
  if (fault == "perturb") {  // a regression: a dark block in the middle
    OIIO::ImageBuf& img = result.image;
    int w = img.spec().width, h = img.spec().height;
    OIIO::ROI roi(w / 3, w / 2, h / 3, h / 2, 0, 1, 0, 3);
    float black[4] = {0, 0, 0, 1};
    OIIO::ImageBufAlgo::fill(img, black, roi);
  }
  if (fault == "subtle") {  // within the golden tolerance, beyond the zero parity budget
    OIIO::ImageBuf& img = result.image;
    float px[4] = {0, 0, 0, 0};
    img.getpixel(0, 0, px, 4);
    px[0] = px[0] > 0.5f ? px[0] - 1.0f / 255.0f : px[0] + 1.0f / 255.0f;
    img.setpixel(0, 0, px, 4);
  }
  // A regression in an intermediate target that the final image does not show: the middle band
  // of the first target that is not the output zeroed.
  if (fault == "perturb-target")
    for (techniques::TargetTexels& t : result.targets) {
      if (t.name == "color" || t.height == 0) continue;
      const size_t row = t.texels.size() / t.height;
      std::fill(t.texels.begin() + row * (t.height / 3), t.texels.begin() + row * (t.height / 2), uint8_t{0});
      break;
    }
}

// Renders one prepared case `repeat` times on the device and writes its image and targets; the
// case's JSON (without the time fields) in *j.
bool renderCase(rhi::TimingDevice& timed, int repeatCount, const std::string& fault, const std::string& output,
                const RenderRequest& request, nlohmann::json* jOut, std::string* error) {
  nlohmann::json& j = *jOut;
  std::vector<uint8_t> first;
  RenderResult firstResult;
  size_t differing = 0;
  const int repeat = std::max(1, repeatCount);
  if (fault == "fail") {  // a render that fails, with the device made
    *error = "injected failure";
    return false;
  }
  for (int i = 0; i < repeat; ++i) {
    auto start = std::chrono::steady_clock::now();
    timed.beginFrame();
    RenderResult r = renderFrame(timed, request);
    double ms = msSince(start);
    if (!r.ok) {
      *error = r.error;
      return false;
    }
    j["render_ms"].push_back(ms);
    if (i == 0)  // device timestamps around each pass of the first render
      for (const rhi::PassTiming& p : timed.passTimings()) j["pass_ms"].push_back({{"pass", p.label}, {"ms", p.ms}});
    if (fault == "nondeterministic" && i == 1 && !r.texels.empty()) r.texels[r.texels.size() / 2] ^= 0x40;
    if (i == 0) {
      first = r.texels;
      firstResult = std::move(r);
    } else {
      size_t n = std::min(first.size(), r.texels.size());
      for (size_t k = 0; k < n; ++k) differing += first[k] != r.texels[k];
      differing += std::max(first.size(), r.texels.size()) - n;
    }
  }
  faultInResult(fault, firstResult);
  const auto writeStart = std::chrono::steady_clock::now();
  const std::string technique = request.frame.technique;
  // Every target the technique declares, next to the image: the per-pass comparison's input.
  if (!firstResult.targets.empty()) {
    fs::path out(output);
    fs::path targetsDir = out.parent_path() / (out.stem().string() + "-targets");
    std::vector<std::string> written;
    if (!writeTargets(firstResult, targetsDir.string(), &written, error)) return false;
    // The logical format the platform planned each target as: the parent decodes the stored
    // values with it (two 16-bit channels are packed on ps3 and fixed point on x360).
    std::map<std::string, std::string> logical;
    if (std::unique_ptr<techniques::Technique> t = techniques::createTechnique(technique)) {
      techniques::RenderSettings settings;
      settings.width = request.frame.width;
      settings.height = request.frame.height;
      settings.platform = request.frame.platform;
      settings.platformParams = request.frame.platformParams;
      settings.capabilities = platforms::publishedCapabilities(request.frame.platform, firstResult.device.caps);
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
  if (std::unique_ptr<techniques::Technique> t = techniques::createTechnique(technique))
    for (const techniques::PassInfo& p : t->passes()) j["passes"].push_back({{"name", p.name}, {"targets", p.targets}});
  j["diagnostics"] = toJson(firstResult.diagnostics);
  if (!firstResult.portPaths.empty()) j["port_paths"] = firstResult.portPaths;
  j["deterministic"] = differing == 0;
  j["differing_bytes"] = differing;
  j["renders"] = repeat;
  j["width"] = request.frame.width;
  j["height"] = request.frame.height;
  if (!writeImage(output, firstResult.image, error)) return false;
  j["write_ms"] = msSince(writeStart);
  return true;
}

}  // namespace

int runCaseWorker(const CaseWorkerOptions& o) {
  if (o.keys.empty() || o.keys.size() != o.outputs.size())
    return reportError("run-case: every --case needs its -o (" + std::to_string(o.keys.size()) + " cases, " +
                       std::to_string(o.outputs.size()) + " images)");
  std::unique_ptr<rhi::Device> device;
  std::optional<rhi::TimingDevice> timed;
  bool allRendered = true;
  for (size_t n = 0; n < o.keys.size(); ++n) {
    const CaseKey& key = o.keys[n];
    const auto caseStart = std::chrono::steady_clock::now();
    // What the drivers print goes to the case that was rendering (the parent splits here).
    if (o.keys.size() > 1) {
      std::fprintf(stderr, "%s%s\n", kCaseMarker, key.id().c_str());
      std::fflush(stderr);
    }
    // A case that cannot be rendered is its own error; one that fails before it reaches the
    // device leaves the child to go on with the next case.
    auto caseError = [&](const std::string& error) {
      std::printf("%s\n", nlohmann::json{{"case", key.id()}, {"error", error}}.dump().c_str());
      std::fflush(stdout);
      reportError(key.id() + ": " + error, 1);
      allRendered = false;
    };
    const std::string fault = o.faultCase.empty() || o.faultCase == key.id() ? o.fault : "";
    std::string error;
    RenderRequest request;
    if (key.backend != o.keys.front().backend) {
      caseError("backend " + key.backend + " is not this child's (" + o.keys.front().backend + ")");
      continue;
    }
    if (!prepareRequest(key, o, &request, &error)) {
      caseError(error);
      continue;
    }
    if (fault == "flaky") {
      std::error_code ec;
      if (!fs::exists(o.faultState, ec)) {
        std::ofstream(o.faultState) << "fired\n";
        caseError("injected flaky failure (first attempt)");
        continue;
      }
    }
    const double setupMs = msSince(caseStart);
    double deviceMs = 0;  // the case that created the child's device carries its time
    if (!device) {
      rhi::DeviceDesc desc;
      desc.glContextProvider = o.glProvider;
      if (!resolveDevice(key.backend, &desc, &error)) {
        std::printf("%s\n", nlohmann::json{{"unavailable", error}}.dump().c_str());
        std::fprintf(stderr, "parity: device %s unavailable: %s\n", key.backend.c_str(), error.c_str());
        return kExitBackendUnavailable;
      }
      const auto deviceStart = std::chrono::steady_clock::now();
      device = rhi::createDevice(desc, &error);
      deviceMs = msSince(deviceStart);
      if (!device) {  // not a failure of the cases: the parent makes each a Skip with this reason
        std::printf("%s\n", nlohmann::json{{"unavailable", error}}.dump().c_str());
        std::fprintf(stderr, "parity: backend %s unavailable: %s\n", key.backend.c_str(), error.c_str());
        return kExitBackendUnavailable;
      }
      timed.emplace(*device);
    }
    faultAfterDevice(fault);

    nlohmann::json j;
    j["case"] = key.id();
    const rhi::DeviceInfo& info = device->info();
    j["renderer"] = info.renderer;
    j["driver"] = info.driver;
    j["api"] = info.api;
    j["context_provider"] = info.contextProvider;
    if (!renderCase(*timed, o.repeat, fault, o.outputs[n], request, &j, &error)) {
      // The device may be left in any state: the cases after this one get no line, and the
      // parent renders each of them alone.
      caseError(error);
      return 1;
    }
    // Where the case's time went besides render_ms (the parent adds up each over the run).
    j["setup_ms"] = setupMs;
    j["device_ms"] = deviceMs;
    j["worker_ms"] = msSince(caseStart);
    std::cout << j.dump() << std::endl;
  }
  return allRendered ? 0 : 1;
}

// ---------------------------------------------------------------------------------------------
// The parent: the matrix


}  // namespace parity::harness
