// The child process of one rendered case (hidden `parity run-case`): renders, repeats, writes
// the image and targets, prints its JSON.
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
// The child: one case, rendered `repeat` times in one process

// Milliseconds since `start`.
static double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

int runCaseWorker(const CaseWorkerOptions& o) {
  const auto workerStart = std::chrono::steady_clock::now();
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
  const double setupMs = msSince(workerStart);
  const auto deviceStart = std::chrono::steady_clock::now();
  std::unique_ptr<rhi::Device> device = rhi::createDevice(desc, &error);
  const double deviceMs = msSince(deviceStart);
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
    double ms = msSince(start);
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
  const auto writeStart = std::chrono::steady_clock::now();
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
  // Where the child's time went besides render_ms (the parent adds up each over the run).
  j["setup_ms"] = setupMs;
  j["device_ms"] = deviceMs;
  j["write_ms"] = msSince(writeStart);
  j["worker_ms"] = msSince(workerStart);
  std::cout << j.dump() << std::endl;
  return 0;
}

// ---------------------------------------------------------------------------------------------
// The parent: the matrix


}  // namespace parity::harness
