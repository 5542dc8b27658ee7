// `parity bench STUDY`: the seeds' performance studies (docs/BENCH.md). The parent plans the
// study, measures it on each backend or device in a child process (`bench-child`, so GL and Vulkan never
// share a process and a driver crash costs one backend, not the run), then writes the CSV,
// plots, summary and index.html.
#include <unistd.h>

#include <thread>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>

#include "bench/bench.h"
#include "bench/csv.h"
#include "bench/report.h"
#include "harness/io/atomic_file.h"
#include "harness/cli/bench_lockstep.h"
#include "harness/cli/commands.h"
#include "harness/run/expectations.h"
#include "harness/run/devices.h"
#include "harness/run/process.h"
#include "rhi/rhi.h"
#include "scene/scene.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

struct BenchState {
  bench::StudyOptions options;
  std::string backend = "both";
  std::string techniques;
  std::string out = "bench-results";
  std::string lights;
  double timeoutSeconds = 4 * 3600;
  bool lockstep = true;
  std::string baseline;  // an earlier run's output folder to compare the ratios with
  std::string devices;   // comma-separated device names, instead of --backend
};

struct ChildState {
  std::string plan, backend, result;
  std::string go, done;  // lockstep: the FIFOs its turns come in by and go back by
  uint32_t process = 1;  // which of the device's processes (1-based)
};

int runBenchChild(const ChildState& c) {
  std::string text, error;
  if (!harness::readTextFile(c.plan, &text, &error)) return reportError(error);
  nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded()) return reportError(c.plan + ": not JSON");
  bench::StudyPlan plan;
  try {
    plan = bench::planFromJson(j);
  } catch (const std::exception& e) {
    return reportError(c.plan + ": not a bench plan (" + e.what() + ")");
  }
  // A device that cannot be created fails its part of the run; the parent reports why.
  rhi::DeviceDesc desc;
  if (!resolveDevice(c.backend, &desc, &error)) return reportError(error);
  desc.validation = false;  // parity's validation layer checks every call on the CPU; it would be measured too
  bench::MeasureHooks hooks;
  hooks.process = c.process;
  hooks.progress = [&c, &plan](const std::string& line) {
    if (plan.processes > 1)
      std::fprintf(stderr, "%s (process %u of %u)\n", line.c_str(), c.process, plan.processes);
    else
      std::fprintf(stderr, "%s\n", line.c_str());
  };
  if (const char* spec = std::getenv("PARITY_BENCH_PLANT_SLEEP"); spec && *spec)
    if (!bench::parsePlantedSleep(spec, &hooks.sleep, &error)) return reportError(error);
  // Before the device: llvmpipe and lavapipe read it when their screen is created.
  ::setenv("LP_NUM_THREADS", std::to_string(plan.rasterThreads).c_str(), 1);
  std::vector<bench::Measurement> rows;
  std::string device, deviceError;
  {
    ChildTurns turns(c.go, c.done);
    if (!c.go.empty() && !turns.active()) return reportError(c.go + ": cannot open the lockstep FIFOs");
    std::unique_ptr<rhi::Device> dev = rhi::createDevice(desc, &deviceError);
    if (dev) {
      device = dev->info().renderer + " | " + dev->info().api;
      if (const char* threads = std::getenv("LP_NUM_THREADS")) device += std::string(" | LP_NUM_THREADS=") + threads;
      if (turns.active()) hooks.turns = &turns;
      rows = bench::measurePlan(plan, *dev, c.backend, hooks);
    }
  }
  nlohmann::json out{{"device", device}, {"device_error", deviceError}, {"rows", nlohmann::json::array()}};
  for (const bench::Measurement& m : rows) out["rows"].push_back(bench::toJson(m));
  if (!harness::writeFileAtomic(c.result, out.dump(), &error)) return reportError(error);
  return 0;
}

int runBench(BenchState& s) {
  std::string error;
  s.options.techniques = bench::splitList(s.techniques);
  for (const std::string& n : bench::splitList(s.lights)) {
    char* end = nullptr;
    unsigned long v = std::strtoul(n.c_str(), &end, 10);
    if (!end || *end || v == 0 || v > 65536) return reportError("--lights: '" + n + "' is not a light count (1..65536)");
    s.options.lightCounts.push_back(static_cast<uint32_t>(v));
  }
  bench::StudyPlan plan;
  if (!bench::makeStudyPlan(s.options, &plan, &error)) return reportError(error);
  // The baseline is read before anything is measured: a wrong folder fails at once.
  bench::StudyPlan baselinePlan;
  std::vector<bench::Measurement> baselineRows;
  if (!s.baseline.empty() && !bench::readBaseline(s.baseline, plan.study, &baselinePlan, &baselineRows, &error))
    return reportError(error);
  {
    // A scene that does not exist or does not load fails here, before any child starts.
    scene::SceneParams params;
    params.lightCount = 0;
    scene::Scene probe;
    if (!scene::makeScene(plan.scene, params, &probe, &error)) return reportError(error);
  }
  // The children: backends, or devices by name (harness/run/devices.h), checked before anything is
  // written. Their labels name the rows.
  std::vector<std::string> backends;
  if (!s.devices.empty()) {
    backends = bench::splitList(s.devices);
    if (backends.empty()) return reportError("--devices: no device named");
    for (size_t i = 0; i < backends.size(); ++i) {
      rhi::DeviceDesc desc;
      if (!resolveDevice(backends[i], &desc, &error)) return reportError("--devices: " + error);
      if (std::count(backends.begin(), backends.begin() + i, backends[i]))
        return reportError("--devices: '" + backends[i] + "' named twice");
    }
  } else if (s.backend == "both") {
    backends = {"gl", "vk"};
  } else {
    backends = {s.backend};
  }
  plan.devices = backends;
  if (const char* spec = std::getenv("PARITY_BENCH_PLANT_SLEEP"); spec && *spec) {
    bench::PlantedSleep planted;
    if (!bench::parsePlantedSleep(spec, &planted, &error)) return reportError(error);
  }

  std::error_code ec;
  fs::create_directories(s.out, ec);
  if (ec || !fs::is_directory(s.out)) return reportError(s.out + ": cannot create the output folder (" + ec.message() + ")");
  const std::string tag = std::to_string(::getpid());
  const fs::path planFile = fs::path(s.out) / (".bench-plan-" + tag + ".json");
  if (!harness::writeFileAtomic(planFile.string(), bench::toJson(plan).dump(), &error)) return reportError(error);

  std::fprintf(stderr, "parity bench %s: %zu points x %zu techniques at %ux%u, %u+%u frames in %u processes a device, devices:",
               plan.study.c_str(), plan.points.size(), plan.techniques.size(), plan.width, plan.height, plan.warmup,
               bench::framesPerProcess(plan) * plan.processes, plan.processes);
  for (const std::string& b : backends) std::fprintf(stderr, " %s", b.c_str());
  std::fprintf(stderr, "\n");
  for (const auto& [t, why] : plan.skipped) std::fprintf(stderr, "parity bench: skipping %s: %s\n", t.c_str(), why.c_str());

  // Each device's children, plan.processes of them; with more than one device and lockstep on,
  // all run at once and take turns round by round (Lockstep), so that every ratio between devices
  // pairs rounds measured next to each other in time. Otherwise they run one after the other.
  // Child i is process i / devices of device i % devices.
  const size_t devices = backends.size(), n = devices * plan.processes;
  auto deviceOf = [&](size_t i) -> const std::string& { return backends[i % devices]; };
  auto childName = [&](size_t i) { return deviceOf(i) + "-" + std::to_string(i / devices + 1); };
  std::vector<ProcessResult> results(n);
  std::vector<double> seconds(n, 0);
  auto resultFile = [&](size_t i) { return fs::path(s.out) / (".bench-result-" + childName(i) + "-" + tag + ".json"); };
  std::vector<std::string> fifoPrefixes;
  for (size_t i = 0; i < n; ++i)
    fifoPrefixes.push_back((fs::path(s.out) / (".bench-turn-" + childName(i) + "-" + tag)).string());
  const bool lockstep = s.lockstep && devices > 1;
  plan.lockstep = lockstep;
  std::unique_ptr<Lockstep> turns;
  if (lockstep) {
    turns = std::make_unique<Lockstep>(fifoPrefixes, plan);
    if (!turns->ok()) return reportError(s.out + ": cannot create the lockstep FIFOs");
  }
  auto runChild = [&](size_t i) {
    std::vector<std::string> args = {selfExecutable(), "bench-child", "--plan", planFile.string(),
                                     "--backend", deviceOf(i), "--result", resultFile(i).string(),
                                     "--process", std::to_string(i / devices + 1)};
    if (lockstep) args.insert(args.end(), {"--go", turns->child(i).go, "--done", turns->child(i).done});
    auto t0 = std::chrono::steady_clock::now();
    results[i] = runProcess(args, s.timeoutSeconds);
    seconds[i] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (lockstep) turns->child(i).exited = true;
  };
  const auto started = std::chrono::steady_clock::now();
  if (lockstep) {
    std::vector<std::thread> threads;
    for (size_t i = 0; i < n; ++i) threads.emplace_back(runChild, i);
    turns->run();
    for (std::thread& t : threads) t.join();
  } else {
    for (size_t i = 0; i < n; ++i) runChild(i);
  }
  const double runSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  // A child's rows, or why it has none.
  auto childRows = [&](size_t i, std::string* device, std::vector<bench::Measurement>* out) {
    const ProcessResult& p = results[i];
    std::fputs(p.err.c_str(), stderr);
    std::string text;
    nlohmann::json result;
    bool ran = false;
    if (p.timedOut) *device = "timed out after " + std::to_string(static_cast<int>(s.timeoutSeconds)) + " s";
    else if (p.crashed) *device = "crashed (signal " + std::to_string(p.signal) + ")";
    else if (!p.startError.empty()) *device = p.startError;
    else if (p.exitCode != 0) {
      // Its one-line error (harness/cli/report_error.h) is the reason.
      std::string last = p.err.substr(0, p.err.find_last_not_of('\n') + 1);
      last = last.substr(last.find_last_of('\n') + 1);
      *device = "exit code " + std::to_string(p.exitCode) + (last.empty() ? "" : ": " + last);
    }
    else if (!harness::readTextFile(resultFile(i).string(), &text, &error)) *device = error;
    else if ((result = nlohmann::json::parse(text, nullptr, false)).is_discarded()) *device = resultFile(i).string() + ": not JSON";
    else {
      *device = result.value("device", "");
      ran = result.value("device_error", "").empty();
      if (!ran) *device = "device not created: " + result.value("device_error", "");
      for (const auto& r : result.at("rows")) out->push_back(bench::measurementFromJson(r));
    }
    fs::remove(resultFile(i), ec);
    if (!ran && plan.processes > 1)
      *device += " (process " + std::to_string(i / devices + 1) + " of " + std::to_string(plan.processes) + ")";
    return ran;
  };

  std::vector<bench::Measurement> rows;
  std::vector<bench::BackendRun> runs;
  for (size_t d = 0; d < devices; ++d) {
    const std::string& backend = backends[d];
    bench::BackendRun run;
    run.backend = backend;
    run.ran = true;
    std::vector<std::vector<bench::Measurement>> perProcess(plan.processes);
    for (uint32_t p = 0; p < plan.processes; ++p) {
      const size_t i = p * devices + d;
      std::string device;
      // A device counts as run only when every one of its processes ran: the first reason it did not.
      if (!childRows(i, &device, &perProcess[p]) && run.ran) {
        run.ran = false;
        run.device = device;
      } else if (run.ran && run.device.empty()) {
        run.device = device;
      }
      // Side by side, the device's processes took the whole run; one after the other, their sum.
      run.seconds = lockstep ? runSeconds : run.seconds + seconds[i];
    }
    if (run.ran) {
      for (const bench::Measurement& m : bench::mergeProcessRows(perProcess)) rows.push_back(m);
    } else {
      // Every technique of the backend is recorded as failed, with the reason.
      for (const bench::BenchPoint& pt : plan.points)
        for (const std::string& t : bench::techniquesAt(plan, pt)) {
          bench::Measurement m;
          m.backend = backend;
          m.technique = t;
          m.scenario = pt.scenario;
          m.x = pt.x;
          m.bigLights = pt.bigLights;
          m.smallLights = pt.smallLights;
          m.status = "failed";
          m.note = "backend " + backend + ": " + run.device;
          rows.push_back(m);
        }
      std::fprintf(stderr, "parity bench: %s did not run: %s\n", backend.c_str(), run.device.c_str());
    }
    for (const bench::Measurement& m : bench::unmeasuredRows(plan, backend)) rows.push_back(m);
    runs.push_back(run);
  }
  fs::remove(planFile, ec);

  std::vector<std::string> written;
  if (!bench::writeStudyOutputs(s.out, plan, rows, runs, &written, &error)) return reportError(error);
  bench::Summary summary = bench::summariseStudy(plan, rows);
  std::fputs(bench::summaryMarkdown(plan, summary, runs).c_str(), stdout);
  if (!s.baseline.empty()) {
    const std::vector<bench::RatioChange> changes =
        bench::compareRatios(bench::summariseStudy(baselinePlan, baselineRows), summary);
    std::fputs(bench::baselineMarkdown(s.baseline, changes).c_str(), stdout);
    for (const bench::RatioChange& c : changes)
      if (c.moved)
        std::fprintf(stderr, "parity bench: %s (%s) moved: %.2fx (%.2f-%.2f) against the baseline's %.2fx (%.2f-%.2f)\n",
                     c.name.c_str(), c.backend.c_str(), c.now.value, c.now.intervalLow, c.now.intervalHigh, c.before.value,
                     c.before.intervalLow, c.before.intervalHigh);
  }
  std::fprintf(stderr, "parity bench: wrote %zu files in %s (open index.html)\n", written.size(), s.out.c_str());
  for (const bench::BackendRun& r : runs)
    if (!r.ran) return 1;  // outputs written, but a backend is missing from them
  return 0;
}

}  // namespace

void registerBenchCommand(CLI::App& app, CommandSet& commands) {
  auto state = std::make_shared<BenchState>();
  bench::StudyOptions& o = state->options;
  CLI::App* bench = app.add_subcommand("bench", "performance studies of the seeds: frame time against light count etc. (docs/BENCH.md)");
  bench->add_option("study", o.study, "lights, inferred-scale, lidr-overlap or tiled")
      ->required()
      ->check(CLI::IsMember(bench::studyNames()));
  bench->add_option("--backend,-b", state->backend, "gl, vk or both (each in its own process)")
      ->check(CLI::IsMember({"gl", "vk", "both"}))
      ->capture_default_str();
  CLI::Option* backendOption = bench->get_option("--backend");
  bench->add_option("--platform,-p", o.platform, "platform layer: reference, dx10, ps3 or x360")->capture_default_str();
  bench->add_option("--techniques,-t", state->techniques,
                    "comma-separated technique names (prefix-* for every registered prefix-...); default: the study's");
  bench->add_option("--size", o.size, "image size WIDTHxHEIGHT (default 320x180, --quick 160x90)");
  bench->add_option("--frames", o.frames, "measured frames (rounds) per point and technique (default 12: the fewest whose 95% interval of a ratio leaves two rounds out at each end)");
  bench->add_option("--warmup", o.warmup, "unmeasured frames before them (default 1)");
  bench->add_option("--seed", o.seed, "seed of the light placement")->capture_default_str();
  bench->add_option("--scene", o.scene, "scene name (`parity list`) or file")->capture_default_str();
  bench->add_option("--out,-o", state->out, "output folder")->capture_default_str();
  bench->add_option("--lights", state->lights,
                    "comma-separated light counts replacing the study's sweep (lights: also the mixed multipliers <= 10; "
                    "inferred-scale, lidr-overlap: the first is the fixed count)");
  bench->add_flag("--quick", o.quick, "reduced sweep and size (lights: under 5 minutes on 2 cores with llvmpipe/lavapipe)");
  bench->add_option("--timeout", state->timeoutSeconds, "seconds per backend process")->capture_default_str();
  bench->add_option("--baseline", state->baseline,
                    "an earlier run's output folder: compare each ratio with its value there and flag those that moved "
                    "beyond both runs' spread over rounds");
  bench->add_option("--budget", o.budgetSeconds,
                    "seconds the run may spend on rounds added past --frames, shared equally by its points (default 60): "
                    "in lockstep, a point gets rounds until every cross ratio is within +-5%")
      ->check(CLI::Range(0.0, 86400.0));
  bench->add_option("--max-rounds", o.maxRounds,
                    "most measured rounds of a point over all of a device's processes, added ones included (default 200)")
      ->check(CLI::Range(1, 100000));
  bench->add_option("--processes", o.processes,
                    "processes each device is measured in, side by side; a ratio's interval reaches every process's "
                    "median (default 4, at most --frames)")
      ->check(CLI::Range(1, 64));
  bench->add_option("--raster-threads", o.rasterThreads,
                    "threads of the software rasterisers (LP_NUM_THREADS) in every child; 0: the rasteriser runs on the API's "
                    "thread (default: LP_NUM_THREADS when set, else 0)")
      ->check(CLI::Range(0, 1024));
  CLI::Option* devices = bench->add_option(
      "--devices", state->devices,
      "comma-separated devices (`parity list`: gl-llvmpipe, gl-zink, vk-lavapipe) measured side by side in lockstep; "
      "each one's frame time is also reported over the first one's");
  bench->add_flag("!--sequential", state->lockstep,
                  "run the backends one after the other instead of in lockstep (round by round, turn about)");
  devices->excludes(backendOption);
  commands.add(bench, [state] { return runBench(*state); });

  auto child = std::make_shared<ChildState>();
  CLI::App* c = app.add_subcommand("bench-child", "");  // hidden: one backend of `parity bench`
  c->group("");
  c->add_option("--plan", child->plan)->required();
  c->add_option("--backend", child->backend)->required();
  c->add_option("--result", child->result)->required();
  c->add_option("--go", child->go);
  c->add_option("--done", child->done);
  c->add_option("--process", child->process);
  commands.add(c, [child] { return runBenchChild(*child); });
}

}  // namespace parity::harness
