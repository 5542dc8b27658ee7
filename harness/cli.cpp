#include "harness/cli.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>

#include "harness/commands.h"
#include "harness/diagnosis.h"
#include "harness/diff.h"
#include "harness/flip.h"
#include "harness/image_io.h"
#include "harness/process.h"
#include "harness/render.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "rhi/rhi.h"
#include "scene/scene.h"
#include "techniques/technique.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

int fail(const std::string& message, int code = 2) { return reportError(message, code); }

struct BackendStatus {
  std::string name;
  bool available = false;
  std::string reason;  // when unavailable
  rhi::DeviceInfo info;
};

// Probes one backend in this process and prints its status as JSON (hidden `probe` command).
int probeBackend(const std::string& backend, const std::string& glProvider) {
  rhi::DeviceDesc desc;
  desc.backend = backend;
  desc.glContextProvider = glProvider;
  std::string why;
  auto device = rhi::createDevice(desc, &why);
  nlohmann::json j;
  j["name"] = backend;
  j["available"] = device != nullptr;
  if (device) {
    const rhi::DeviceInfo& i = device->info();
    j["api"] = i.api;
    j["renderer"] = i.renderer;
    j["driver"] = i.driver;
    j["context_provider"] = i.contextProvider;
  } else {
    j["reason"] = why;
  }
  std::cout << j.dump() << std::endl;
  return 0;
}

// Each backend is probed in a child process: GL and Vulkan never share a process, and a driver
// that crashes while loading makes its backend unavailable instead of ending the command.
BackendStatus queryBackend(const std::string& backend, const std::string& glProvider) {
  BackendStatus s;
  s.name = backend;
  ProcessResult p = runProcess({selfExecutable(), "probe", "--backend", backend, "--gl-provider", glProvider}, 60);
  if (!p.startError.empty() || p.timedOut || p.crashed || p.exitCode != 0) {
    s.reason = p.timedOut ? "probe timed out"
               : p.crashed ? "probe crashed (signal " + std::to_string(p.signal) + ")"
                           : "probe failed: " + p.startError + p.err;
    return s;
  }
  try {
    nlohmann::json j = nlohmann::json::parse(p.out);
    s.available = j.at("available").get<bool>();
    if (s.available) {
      s.info.backend = backend;
      s.info.api = j.value("api", "");
      s.info.renderer = j.value("renderer", "");
      s.info.driver = j.value("driver", "");
      s.info.contextProvider = j.value("context_provider", "");
    } else {
      s.reason = j.value("reason", "unknown reason");
    }
  } catch (const std::exception& e) {
    s.reason = std::string("probe printed no status: ") + e.what();
  }
  return s;
}

int cmdList(bool json, const std::string& glProvider) {
  std::vector<BackendStatus> backends;
  for (const std::string& b : rhi::compiledBackends()) backends.push_back(queryBackend(b, glProvider));
  if (json) {
    nlohmann::json j;
    for (const BackendStatus& b : backends) {
      nlohmann::json e{{"name", b.name}, {"available", b.available}};
      if (b.available) {
        e["api"] = b.info.api;
        e["renderer"] = b.info.renderer;
        e["driver"] = b.info.driver;
        if (!b.info.contextProvider.empty()) e["context_provider"] = b.info.contextProvider;
      } else {
        e["reason"] = b.reason;
      }
      j["backends"].push_back(e);
    }
    for (const auto& t : techniques::techniqueRegistry())
      j["techniques"].push_back({{"name", t.name}, {"description", t.description}});
    for (const std::string& s : scene::sceneNames()) j["scenes"].push_back({{"name", s}, {"cameras", scene::cameraNames(s)}});
    std::cout << j.dump(2) << std::endl;
    return 0;
  }
  std::printf("backends:\n");
  for (const BackendStatus& b : backends) {
    if (b.available)
      std::printf("  %-4s available    %s | %s | %s%s\n", b.name.c_str(), b.info.renderer.c_str(), b.info.api.c_str(),
                  b.info.driver.c_str(), b.info.contextProvider.empty() ? "" : (" | " + b.info.contextProvider).c_str());
    else
      std::printf("  %-4s unavailable  %s\n", b.name.c_str(), b.reason.c_str());
  }
  std::printf("techniques:\n");
  for (const auto& t : techniques::techniqueRegistry()) std::printf("  %-10s %s\n", t.name.c_str(), t.description.c_str());
  std::printf("scenes:\n");
  for (const std::string& s : scene::sceneNames()) {
    std::string cams;
    for (const std::string& c : scene::cameraNames(s)) cams += (cams.empty() ? "" : ", ") + c;
    std::printf("  %-10s cameras: %s\n", s.c_str(), cams.c_str());
  }
  return 0;
}

struct RenderOptions {
  RenderRequest request;
  std::string size = "320x180";
  std::string format = "rgba8";
  std::string lightSize = "small";
  std::string platform = "reference";
  std::vector<std::string> params;  // NAME=VALUE platform parameters
  bool plainBuiltins = false;
};

void addRenderOptions(CLI::App* app, RenderOptions& o) {
  app->add_option("--technique,-t", o.request.frame.technique, "technique name (see `parity list`)")->capture_default_str();
  app->add_option("--scene", o.request.frame.scene, "scene name")->capture_default_str();
  app->add_option("--camera", o.request.frame.camera, "camera of the scene")->capture_default_str();
  app->add_option("--size", o.size, "image size WIDTHxHEIGHT")->capture_default_str();
  app->add_option("--lights", o.request.frame.sceneParams.lightCount, "number of local lights")->capture_default_str();
  app->add_option("--light-size", o.lightSize, "small (0.25-5% of the screen) or big (20-100%)")
      ->check(CLI::IsMember({"small", "big"}))->capture_default_str();
  app->add_option("--seed", o.request.frame.sceneParams.seed, "seed for light placement")->capture_default_str();
  app->add_option("--format", o.format, "colour format of the render target")
      ->check(CLI::IsMember({"rgba8", "rgba32f"}))->capture_default_str();
  app->add_option("--platform,-p", o.platform, "platform layer: reference, dx10, ps3 or x360")->capture_default_str();
  app->add_option("--param", o.params,
                  "platform parameter NAME=VALUE (names: `parity explain --platform P`), e.g. x360.dsf_resolve_path=naive_a");
  app->add_option("--gl-provider", o.request.glProvider, "GL context provider")
      ->check(CLI::IsMember({"egl", "osmesa"}))->capture_default_str();
  app->add_flag("--debug", o.request.debug, "GL debug context / Vulkan validation layer");
  app->add_flag("--plain-builtins", o.plainBuiltins,
                "compile shaders with the GLSL built-ins instead of parity_math.glsl's explicit arithmetic "
                "(shows the GL/Vulkan difference the include removes)");
}

// Fills request fields that need parsing; returns false with a message.
bool finishRenderOptions(RenderOptions& o, std::string* error) {
  if (!parseSize(o.size, &o.request.frame.width, &o.request.frame.height, error)) return false;
  o.request.frame.colorFormat = o.format == "rgba32f" ? rhi::Format::RGBA32F : rhi::Format::RGBA8;
  o.request.frame.sceneParams.lightSize = o.lightSize == "big" ? scene::LightSize::Big : scene::LightSize::Small;
  std::optional<platforms::PlatformId> platform = platforms::platformFromName(o.platform);
  if (!platform) {
    *error = "unknown platform '" + o.platform + "' (" +
             scene::didYouMean(o.platform, {"reference", "dx10", "ps3", "x360"}) + "known: reference, dx10, ps3, x360)";
    return false;
  }
  o.request.frame.platform = *platform;
  for (const std::string& p : o.params) {
    size_t eq = p.find('=');
    if (eq == std::string::npos) {
      *error = "--param '" + p + "' is not NAME=VALUE";
      return false;
    }
    if (!platforms::setParameter(o.request.frame.platformParams, p.substr(0, eq), p.substr(eq + 1), error)) return false;
  }
  if (o.plainBuiltins) o.request.frame.shaderOptions.defines.push_back({"PARITY_PLAIN_BUILTINS", "1"});
  if (!techniques::createTechnique(o.request.frame.technique)) {
    std::string known;
    for (const auto& t : techniques::techniqueRegistry()) known += (known.empty() ? "" : ", ") + t.name;
    std::vector<std::string> names;
    for (const auto& t : techniques::techniqueRegistry()) names.push_back(t.name);
    *error = "unknown technique '" + o.request.frame.technique + "' (" +
             scene::didYouMean(o.request.frame.technique, names) + "known: " + known + ")";
    return false;
  }
  return true;
}

int cmdRender(RenderOptions& o, const std::string& output, const std::string& passesDir) {
  std::string error;
  if (!finishRenderOptions(o, &error)) return fail(error);
  std::string ext = fs::path(output).extension().string();
  if (ext != ".png" && ext != ".exr") return fail(output + ": unsupported image extension (use .png or .exr)");
  o.request.frame.readTargets = !passesDir.empty();
  RenderResult r = renderFrame(o.request);
  if (!r.ok) return fail(r.error);
  if (!writeImage(output, r.image, &error)) return fail(error);
  std::vector<std::string> written;
  if (!passesDir.empty() && !writeTargets(r, passesDir, &written, &error)) return fail(error);
  // With the host format the platform planned it in (written[i] is r.targets[i]).
  for (size_t i = 0; i < written.size() && i < r.targets.size(); ++i)
    std::fprintf(stderr, "parity: wrote pass target %s (%s)\n", written[i].c_str(), rhi::formatInfo(r.targets[i].format).name);
  for (const platforms::Diagnostic& d : r.diagnostics) std::fprintf(stderr, "parity: warning: %s\n", d.format().c_str());
  if (o.request.frame.platform != platforms::PlatformId::Reference)
    for (const std::string& t : r.unplannedTargets)
      std::fprintf(stderr, "parity: note: %s: rendered outside the platform's targets (host format, no %s rule)\n",
                   t.c_str(), std::string(platforms::platformName(o.request.frame.platform)).c_str());
  std::fprintf(stderr, "parity: rendered %s on %s (%s) to %s\n", o.request.frame.technique.c_str(), o.request.backend.c_str(),
               r.device.renderer.c_str(), output.c_str());
  return 0;
}

struct FlipOptions {
  bool enabled = false;
  std::string map;                                           // magma error map to write
  double fail = std::numeric_limits<double>::infinity();     // FLIP mean that fails
};

int cmdDiff(const std::string& a, const std::string& b, const DiffThresholds& t, const std::string& heatmap, bool json,
            const FlipOptions& flipOptions, bool explain) {
  DiffResult r = diffFiles(a, b, t);
  bool sizesMatch = r.verdict != DiffVerdict::FileError && r.verdict != DiffVerdict::SizeMismatch;
  // --explain: the run's diagnosis on any two images, A taken as the expected one.
  std::optional<Diagnosis> diagnosis;
  if (explain && sizesMatch && r.verdict != DiffVerdict::Pass) {
    OIIO::ImageBuf ia, ib;
    std::string error;
    if (!readImage(a, &ia, &error) || !readImage(b, &ib, &error)) return fail(error, static_cast<int>(DiffVerdict::FileError));
    diagnosis = diagnose(ia, ib);
  }
  FlipResult flip;
  bool wantFlip = flipOptions.enabled || !flipOptions.map.empty() || std::isfinite(flipOptions.fail);
  if (wantFlip && sizesMatch) {
    OIIO::ImageBuf ia, ib;
    std::string error;
    if (!readImage(a, &ia, &error) || !readImage(b, &ib, &error)) return fail(error, static_cast<int>(DiffVerdict::FileError));
    flip = computeLdrFlip(ia, ib);
    if (!flip.ok) return fail(a + ": FLIP: " + flip.error, static_cast<int>(DiffVerdict::FileError));
    // The FLIP mean is one more failing condition next to idiff's.
    if (flip.mean > flipOptions.fail && r.verdict != DiffVerdict::Fail) r.verdict = DiffVerdict::Fail;
    if (!flipOptions.map.empty() && !writeFlipMap(flip, flipOptions.map, &error))
      return fail(error, static_cast<int>(DiffVerdict::FileError));
  }
  if (json) {
    nlohmann::json j = toJson(r);
    j["a"] = a;
    j["b"] = b;
    if (flip.ok) j["flip"] = toJson(flip);
    if (explain) j["diagnosis"] = diagnosis ? toJson(*diagnosis) : nlohmann::json();
    std::cout << j.dump(2) << std::endl;
  } else {
    std::printf("%s\n", summaryLine(r).c_str());
    if (flip.ok)
      std::printf("FLIP mean %.6g, weighted quartiles %.6g / %.6g / %.6g, min %.6g, max %.6g (%.2f pixels per degree)\n",
                  flip.mean, flip.weightedQuartile1, flip.weightedMedian, flip.weightedQuartile3, flip.min, flip.max,
                  flip.pixelsPerDegree);
    if (explain && r.verdict != DiffVerdict::Pass)
      std::printf("explain: %s\n", diagnosis ? (diagnosis->cause + " (" + diagnosis->detail + ")").c_str()
                                            : "no known porting bug explains the difference");
  }
  if (!heatmap.empty() && sizesMatch) {
    OIIO::ImageBuf ia, ib;
    std::string error;
    if (!readImage(a, &ia, &error) || !readImage(b, &ib, &error) || !writeHeatmap(ia, ib, heatmap, &error))
      return fail(error, static_cast<int>(DiffVerdict::FileError));
  }
  return static_cast<int>(r.verdict);
}

}  // namespace

// Every error the user sees is one line: "parity: error: <what>".
int reportError(const std::string& message, int code) {
  std::string line = message;
  while (!line.empty() && line.back() == '\n') line.pop_back();
  for (char& c : line)
    if (c == '\n') c = ' ';
  std::fprintf(stderr, "parity: error: %s\n", line.c_str());
  return code;
}

void registerCoreCommands(CLI::App& app, CommandSet& commands) {
  struct ListState {
    bool json = false;
    std::string provider = "egl";
  };
  auto listState = std::make_shared<ListState>();
  CLI::App* list = app.add_subcommand("list", "backends with availability and renderer, techniques, scenes");
  list->add_flag("--json", listState->json, "machine-readable output");
  list->add_option("--gl-provider", listState->provider, "GL context provider to probe")
      ->check(CLI::IsMember({"egl", "osmesa"}));
  commands.add(list, [listState] { return cmdList(listState->json, listState->provider); });

  struct RenderState {
    RenderOptions options;
    std::string output;
    std::string passesDir;
  };
  auto renderState = std::make_shared<RenderState>();
  CLI::App* render = app.add_subcommand("render", "render one frame to an image (PNG or EXR)");
  addRenderOptions(render, renderState->options);
  render->add_option("--backend,-b", renderState->options.request.backend, "gl or vk")->required();
  render->add_option("-o,--output", renderState->output, "output image (.png or .exr)")->required();
  render->add_option("--passes", renderState->passesDir,
                     "also write every target of the frame into this folder (PNG for 8-bit data, EXR for float and depth)");
  commands.add(render, [renderState] {
    return cmdRender(renderState->options, renderState->output, renderState->passesDir);
  });

  struct DiffState {
    std::string a, b, heatmap;
    bool json = false, explain = false;
    DiffThresholds thresholds;
    FlipOptions flip;
  };
  auto diffState = std::make_shared<DiffState>();
  DiffThresholds& t = diffState->thresholds;
  CLI::App* diff = app.add_subcommand(
      "diff", "compare two images (idiff thresholds and exit codes: 0 pass, 1 warn, 2 fail, 3 size mismatch, 4 file error)");
  diff->add_option("a", diffState->a, "first image")->required();
  diff->add_option("b", diffState->b, "second image")->required();
  diff->add_option("--heatmap", diffState->heatmap, "write a heat map of the per-pixel difference");
  diff->add_flag("--json", diffState->json, "machine-readable output");
  diff->add_option("--fail", t.fail, "per-channel difference that fails")->capture_default_str();
  diff->add_option("--failpercent", t.failPercent, "percent of pixels allowed over --fail")->capture_default_str();
  diff->add_option("--hardfail", t.hardFail, "any pixel over this fails");
  diff->add_option("--warn", t.warn, "per-channel difference that warns")->capture_default_str();
  diff->add_option("--warnpercent", t.warnPercent, "percent of pixels allowed over --warn")->capture_default_str();
  diff->add_option("--hardwarn", t.hardWarn, "any pixel over this warns");
  diff->add_flag("--flip", diffState->flip.enabled,
                 "also compute LDR-FLIP (mean, weighted quartiles, min, max at 67 pixels per degree; inputs read as sRGB)");
  diff->add_option("--flip-map", diffState->flip.map, "write the FLIP error map (magma colours); implies --flip");
  diff->add_option("--flip-fail", diffState->flip.fail, "fail when the FLIP mean exceeds this; implies --flip");
  diff->add_flag("--explain", diffState->explain,
                 "name the porting bug that explains a difference (the run's diagnosis; A is the expected image)");
  commands.add(diff, [diffState] {
    return cmdDiff(diffState->a, diffState->b, diffState->thresholds, diffState->heatmap, diffState->json, diffState->flip,
                   diffState->explain);
  });

  struct ProbeState {
    std::string backend, provider = "egl";
  };
  auto probeState = std::make_shared<ProbeState>();
  CLI::App* probe = app.add_subcommand("probe", "");  // hidden: used by list in child processes
  probe->group("");
  probe->add_option("--backend", probeState->backend)->required();
  probe->add_option("--gl-provider", probeState->provider);
  commands.add(probe, [probeState] { return probeBackend(probeState->backend, probeState->provider); });
}

int runCli(int argc, char** argv) {
  CLI::App app{"parity: renders techniques on OpenGL and Vulkan (and emulated console platforms) and compares the images"};
  app.require_subcommand(1);
  CommandSet commands;
  registerCoreCommands(app, commands);
  registerExplainCommand(app, commands);
  registerRunCommands(app, commands);
  registerTestCommand(app, commands);
  void registerBenchCommand(CLI::App&, CommandSet&); registerBenchCommand(app, commands);  // cmd_bench.cpp
  void registerViewCommand(CLI::App&, CommandSet&); registerViewCommand(app, commands);  // cmd_view.cpp
  // Further commands register here, one line each.

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string what = e.what();
    return reportError(what.empty() ? "invalid command line" : what);
  }
  for (auto& [subcommand, run] : commands.commands)
    if (subcommand->parsed()) return run();
  return reportError("no command");
}

}  // namespace parity::harness
