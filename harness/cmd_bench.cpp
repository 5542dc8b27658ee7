// `parity bench STUDY`: the seeds' performance studies (docs/BENCH.md). The parent plans the
// study, measures it on each backend in a child process (`bench-child`, so GL and Vulkan never
// share a process and a driver crash costs one backend, not the run), then writes the CSV,
// plots, summary and index.html.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>

#include "bench/bench.h"
#include "bench/csv.h"
#include "bench/report.h"
#include "harness/atomic_file.h"
#include "harness/commands.h"
#include "harness/expectations.h"
#include "harness/process.h"
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
};

struct ChildState {
  std::string plan, backend, result;
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
  std::vector<bench::Measurement> rows = bench::measurePlan(plan, c.backend, [](const std::string& line) {
    std::fprintf(stderr, "%s\n", line.c_str());
  });
  // The device line for the report, from a device of our own (cheap next to the measurement).
  std::string device;
  {
    rhi::DeviceDesc d;
    d.backend = c.backend;
    d.validation = false;
    std::string why;
    if (auto dev = rhi::createDevice(d, &why)) device = dev->info().renderer + " | " + dev->info().api;
    else device = why;
  }
  nlohmann::json out{{"device", device}, {"rows", nlohmann::json::array()}};
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
  {
    // A scene that does not exist or does not load fails here, before any child starts.
    scene::SceneParams params;
    params.lightCount = 0;
    scene::Scene probe;
    if (!scene::makeScene(plan.scene, params, &probe, &error)) return reportError(error);
  }
  std::vector<std::string> backends;
  if (s.backend == "both") backends = {"gl", "vk"};
  else backends = {s.backend};

  std::error_code ec;
  fs::create_directories(s.out, ec);
  if (ec || !fs::is_directory(s.out)) return reportError(s.out + ": cannot create the output folder (" + ec.message() + ")");
  const std::string tag = std::to_string(::getpid());
  const fs::path planFile = fs::path(s.out) / (".bench-plan-" + tag + ".json");
  if (!harness::writeFileAtomic(planFile.string(), bench::toJson(plan).dump(), &error)) return reportError(error);

  std::fprintf(stderr, "parity bench %s: %zu points x %zu techniques at %ux%u, %u+%u frames, backends:", plan.study.c_str(),
               plan.points.size(), plan.techniques.size(), plan.width, plan.height, plan.warmup, plan.frames);
  for (const std::string& b : backends) std::fprintf(stderr, " %s", b.c_str());
  std::fprintf(stderr, "\n");
  for (const auto& [t, why] : plan.skipped) std::fprintf(stderr, "parity bench: skipping %s: %s\n", t.c_str(), why.c_str());

  std::vector<bench::Measurement> rows;
  std::vector<bench::BackendRun> runs;
  for (const std::string& backend : backends) {
    const fs::path resultFile = fs::path(s.out) / (".bench-result-" + backend + "-" + tag + ".json");
    auto t0 = std::chrono::steady_clock::now();
    ProcessResult p = runProcess({selfExecutable(), "bench-child", "--plan", planFile.string(), "--backend", backend, "--result",
                                  resultFile.string()},
                                 s.timeoutSeconds);
    bench::BackendRun run;
    run.backend = backend;
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fputs(p.err.c_str(), stderr);
    std::string text;
    nlohmann::json result;
    if (p.timedOut) run.device = "timed out after " + std::to_string(static_cast<int>(s.timeoutSeconds)) + " s";
    else if (p.crashed) run.device = "crashed (signal " + std::to_string(p.signal) + ")";
    else if (!p.startError.empty()) run.device = p.startError;
    else if (p.exitCode != 0) run.device = "exit code " + std::to_string(p.exitCode);
    else if (!harness::readTextFile(resultFile.string(), &text, &error)) run.device = error;
    else if ((result = nlohmann::json::parse(text, nullptr, false)).is_discarded()) run.device = resultFile.string() + ": not JSON";
    else {
      run.ran = true;
      run.device = result.value("device", "");
      for (const auto& r : result.at("rows")) rows.push_back(bench::measurementFromJson(r));
    }
    fs::remove(resultFile, ec);
    if (!run.ran) {
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
  bench->add_option("--platform,-p", o.platform, "platform layer: reference, dx10, ps3 or x360")->capture_default_str();
  bench->add_option("--techniques,-t", state->techniques,
                    "comma-separated technique names (prefix-* for every registered prefix-...); default: the study's");
  bench->add_option("--size", o.size, "image size WIDTHxHEIGHT (default 320x180, --quick 160x90)");
  bench->add_option("--frames", o.frames, "measured frames per point and technique (default 7, --quick 3)");
  bench->add_option("--warmup", o.warmup, "unmeasured frames before them (default 1)");
  bench->add_option("--seed", o.seed, "seed of the light placement")->capture_default_str();
  bench->add_option("--scene", o.scene, "scene name (`parity list`) or file")->capture_default_str();
  bench->add_option("--out,-o", state->out, "output folder")->capture_default_str();
  bench->add_option("--lights", state->lights,
                    "comma-separated light counts replacing the study's sweep (lights: also the mixed multipliers <= 10; "
                    "inferred-scale, lidr-overlap: the first is the fixed count)");
  bench->add_flag("--quick", o.quick, "reduced sweep and size (lights: under 5 minutes on 2 cores with llvmpipe/lavapipe)");
  bench->add_option("--timeout", state->timeoutSeconds, "seconds per backend process")->capture_default_str();
  commands.add(bench, [state] { return runBench(*state); });

  auto child = std::make_shared<ChildState>();
  CLI::App* c = app.add_subcommand("bench-child", "");  // hidden: one backend of `parity bench`
  c->group("");
  c->add_option("--plan", child->plan)->required();
  c->add_option("--backend", child->backend)->required();
  c->add_option("--result", child->result)->required();
  commands.add(c, [child] { return runBenchChild(*child); });
}

}  // namespace parity::harness
