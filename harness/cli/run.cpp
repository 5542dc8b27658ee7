// `parity run`, `parity bless`, `parity merge` and the hidden child command `run-case`.
#include <cstdlib>
#include <memory>

#include "harness/cli/commands.h"
#include "harness/run/process.h"
#include "harness/run/golden.h"
#include "harness/run/run.h"

namespace parity::harness {

namespace {

void addFilters(CLI::App* app, RunFilters& f) {
  app->add_option("--technique,--techniques", f.techniques, "techniques (repeat or comma-separate; default: all)")
      ->delimiter(',');
  app->add_option("--scene,--scenes", f.scenes, "scenes (default: the default scene and every scene with goldens; all: every available scene)")->delimiter(',');
  app->add_option("--platform,--platforms", f.platforms, "platforms: reference, dx10, ps3, x360 (default: all)")
      ->delimiter(',');
}

}  // namespace

void registerRunCommands(CLI::App& app, CommandSet& commands) {
  struct RunState {
    RunOptions options;
    std::string shard;
    bool noProgress = false, list = false, ctest = false;
    std::string ctestOutRoot = "parity-ctest";
  };
  auto runState = std::make_shared<RunState>();
  RunOptions& o = runState->options;
  CLI::App* run = app.add_subcommand(
      "run", "the matrix technique x scene x platform x backend: each case in a child process, compared with its golden "
             "and across backends; writes DIR/results.json, DIR/junit.xml, DIR/report/index.html");
  addFilters(run, o.filters);
  run->add_option("--backend,--backends", o.filters.backends, "backends (default: all available)")->delimiter(',');
  run->add_option("--devices", o.filters.devices,
                  "devices to run on, each a backend of the matrix (`parity list`: gl-llvmpipe, gl-zink, vk-lavapipe); each "
                  "is required")
      ->delimiter(',');
  run->add_option("--case", o.filters.cases, "exact case ids technique/scene/platform/backend")->delimiter(',');
  run->add_option("--scripts", o.filters.scripts,
                  "shader-test scripts or folders run as cases of technique 'script' (default: the project's tests/scripts)");
  run->add_option("--out", o.outDir, "output folder")->capture_default_str();
  run->add_option("--jobs,-j", o.jobs, "child processes at once (default: number of CPUs)");
  run->add_option("--shard", runState->shard,
                  "run shard INDEX/COUNT (0-based; default from GTEST_SHARD_INDEX/GTEST_TOTAL_SHARDS)");
  run->add_option("--size", o.size, "image size WIDTHxHEIGHT")->capture_default_str();
  run->add_option("--gl-provider", o.glProvider, "GL context provider")
      ->check(CLI::IsMember({"egl", "osmesa"}))->capture_default_str();
  run->add_option("--timeout", o.timeout, "seconds per child process before the case is a Timeout")->capture_default_str();
  run->add_option("--retries", o.retries, "reruns of an unexpected failure (a pass on rerun is a Flake)")
      ->capture_default_str();
  run->add_option("--repeat", o.repeat, "renders per case, compared bit-exactly (Nondeterministic otherwise)")
      ->capture_default_str();
  run->add_option("--golden", o.goldenDir, "golden folder (default: the project's golden/)");
  run->add_option("--images", o.imagesDir,
                  "judge another program's renders instead of rendering: DIR/<technique>/<scene>/<platform>/<backend>.png "
                  "(docs/HARNESS.md, External images)");
  run->add_option("--baseline", o.baselineDir,
                  "an earlier run's output folder: list regressions, fixes, new and vanished cases against its results.json");
  run->add_option("--expectations", o.expectationsFile, "expectations file (default: GOLDEN/expectations.json)");
  run->add_option("--tolerances", o.tolerancesFile, "tolerances file (default: GOLDEN/tolerances.json)");
  run->add_option("--require-backends", o.requireBackends,
                  "backends that must be available, or the run fails (default: $PARITY_REQUIRE_BACKENDS)")
      ->delimiter(',');
  run->add_flag("--strict", o.strict, "ParityWarning and Flake fail the run too");
  run->add_flag("--no-progress", runState->noProgress, "no progress line even on a terminal");
  run->add_flag("--list-cases", runState->list, "print the selected case ids and exit");
  run->add_flag("--ctest", runState->ctest, "")->group("");  // with --list-cases: CTest script lines
  run->add_option("--ctest-out-root", runState->ctestOutRoot, "")->group("");
  run->add_option("--inject-fault", o.faults, "")->group("");  // tests only: CASE=crash|abort|oom|hang|fail|flaky|nondeterministic|perturb|subtle
  commands.add(run, [runState] {
    RunOptions& o = runState->options;
    std::string error;
    if (!shardFromEnvironment(&o.shard, &error)) return reportError(error);
    if (!runState->shard.empty() && !parseShard(runState->shard, &o.shard, &error)) return reportError(error);
    o.progress = !runState->noProgress;
    o.requireBackendsFromCommandLine = !o.requireBackends.empty();
    if (!o.requireBackendsFromCommandLine)
      if (const char* env = std::getenv("PARITY_REQUIRE_BACKENDS"))
        for (std::string rest = env; !rest.empty();) {
          const size_t comma = rest.find(',');
          const std::string name = rest.substr(0, comma);
          if (!name.empty()) o.requireBackends.push_back(name);
          rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
        }
    if (runState->list)
      return listCases(o.filters, o.shard, runState->ctest, selfExecutable(), runState->ctestOutRoot);
    return runMatrix(o);
  });

  auto worker = std::make_shared<CaseWorkerOptions>();
  auto workerCases = std::make_shared<std::vector<std::string>>();
  CLI::App* runCase = app.add_subcommand("run-case", "");  // hidden: the child of `parity run`
  runCase->group("");
  runCase->add_option("--case", *workerCases)->required();  // repeated: the cases, in order
  runCase->add_option("--size", worker->size);
  runCase->add_option("--gl-provider", worker->glProvider);
  runCase->add_option("--repeat", worker->repeat);
  runCase->add_option("-o", worker->outputs)->required();  // repeated: each case's image
  runCase->add_option("--fault", worker->fault);
  runCase->add_option("--fault-case", worker->faultCase);
  runCase->add_option("--fault-state", worker->faultState);
  commands.add(runCase, [worker, workerCases] {
    worker->keys.clear();
    for (const std::string& id : *workerCases) {
      std::string error;
      if (!CaseKey::parse(id, &worker->keys.emplace_back(), &error)) return reportError(error);
    }
    return runCaseWorker(*worker);
  });

  auto bless = std::make_shared<BlessOptions>();
  CLI::App* blessCmd = app.add_subcommand(
      "bless", "copy a run's images into golden/ (atomically, with provenance in golden/manifest.json); only where GL and "
               "Vulkan rendered bit-identical, deterministic images in that run (unless --backend and --reason are given) and the "
               "evidence a claim of evidence.json names holds");
  addFilters(blessCmd, bless->filters);
  blessCmd->add_option("--from", bless->from, "output folder of a `parity run`")->required();
  blessCmd->add_option("--golden", bless->goldenDir, "golden folder (default: the project's golden/)");
  blessCmd->add_option("--backend", bless->backend, "bless this backend's image without GL/Vulkan agreement (needs --reason)");
  blessCmd->add_option("--device", bless->device,
                       "accept this device's images beside the primary goldens, never over them (needs --reason)");
  blessCmd->add_option("--reason", bless->reason, "why the image is right; recorded in the manifest");
  blessCmd->add_option("--evidence", bless->evidenceFile,
                       "the claims each golden needs (default: GOLDEN/evidence.json); a golden no claim covers is refused");
  blessCmd->add_flag("--dry-run", bless->dryRun, "say what would be blessed, write nothing");
  commands.add(blessCmd, [bless] { return blessGoldens(*bless); });

  struct MergeState {
    std::vector<std::string> inputs;
    std::string out, baseline;
  };
  auto merge = std::make_shared<MergeState>();
  CLI::App* mergeCmd = app.add_subcommand("merge", "join the output folders of several runs (shards) into one report");
  mergeCmd->add_option("inputs", merge->inputs, "output folders of `parity run`")->required();
  mergeCmd->add_option("--out", merge->out, "merged output folder")->required();
  mergeCmd->add_option("--baseline", merge->baseline,
                       "an earlier run's output folder: list regressions, fixes, new and vanished cases against it");
  commands.add(mergeCmd, [merge] { return mergeRuns(merge->inputs, merge->out, merge->baseline); });
}

}  // namespace parity::harness
