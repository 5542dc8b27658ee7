// `parity render`: one frame of a technique on one backend and platform, to an image, and with
// --passes every target of the frame.
#include <cstdio>
#include <filesystem>
#include <optional>

#include "harness/cli/commands.h"
#include "harness/io/image_io.h"
#include "harness/run/diagnostic_groups.h"
#include "harness/run/render.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "rhi/rhi.h"
#include "scene/scene.h"
#include "techniques/technique.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

int fail(const std::string& message, int code = 2) { return reportError(message, code); }

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
  // A technique that needs what its platform lacks, with no port path for it, ran a shader or a
  // pass the console cannot run: its image is no image of the platform, and nothing is written.
  std::string lacking;
  for (const platforms::Diagnostic& d : r.diagnostics)
    if (d.severity == platforms::Severity::Error && d.code.rfind("E_CAP_", 0) == 0 && lacking.find(d.code) == std::string::npos)
      lacking += (lacking.empty() ? "" : ", ") + d.code;
  if (!lacking.empty()) {
    for (const DiagnosticGroup& g : groupDiagnostics(toJson(r.diagnostics)))
      std::fprintf(stderr, "parity: platform %s\n", g.line().c_str());
    return fail(o.request.frame.technique + " cannot run on " + o.platform + ": it needs what the platform lacks (" + lacking +
                ", capability table: `parity explain --platform " + o.platform + "`) and has no port path for it; " +
                output + " not written");
  }
  if (!writeImage(output, r.image, &error)) return fail(error);
  std::vector<std::string> written;
  if (!passesDir.empty() && !writeTargets(r, passesDir, &written, &error)) return fail(error);
  // With the host format the platform planned it in (written[i] is r.targets[i]).
  for (size_t i = 0; i < written.size() && i < r.targets.size(); ++i)
    std::fprintf(stderr, "parity: wrote pass target %s (%s)\n", written[i].c_str(), rhi::formatInfo(r.targets[i].format).name);
  // The platform's diagnostics, a line per code as the report shows them (diagnostic_groups.h).
  for (const DiagnosticGroup& g : groupDiagnostics(toJson(r.diagnostics)))
    std::fprintf(stderr, "parity: platform %s\n", g.line().c_str());
  for (const std::string& p : r.portPaths) std::fprintf(stderr, "parity: note: %s\n", p.c_str());
  if (o.request.frame.platform != platforms::PlatformId::Reference)
    for (const std::string& t : r.unplannedTargets)
      std::fprintf(stderr, "parity: note: %s: rendered outside the platform's targets (host format, no %s rule)\n",
                   t.c_str(), std::string(platforms::platformName(o.request.frame.platform)).c_str());
  std::fprintf(stderr, "parity: rendered %s on %s (%s) to %s\n", o.request.frame.technique.c_str(), o.request.backend.c_str(),
               r.device.renderer.c_str(), output.c_str());
  return 0;
}

}  // namespace

void registerRenderCommand(CLI::App& app, CommandSet& commands) {
  struct RenderState {
    RenderOptions options;
    std::string output;
    std::string passesDir;
  };
  auto renderState = std::make_shared<RenderState>();
  CLI::App* render = app.add_subcommand("render", "render one frame to an image (PNG or EXR)");
  addRenderOptions(render, renderState->options);
  render->add_option("--backend,-b", renderState->options.request.backend, "gl, vk, or a device of `parity list` (gl-zink)")->required();
  render->add_option("-o,--output", renderState->output, "output image (.png or .exr)")->required();
  render->add_option("--passes", renderState->passesDir,
                     "also write every target of the frame into this folder (PNG for 8-bit data, EXR for float and depth)");
  commands.add(render, [renderState] {
    return cmdRender(renderState->options, renderState->output, renderState->passesDir);
  });
}

}  // namespace parity::harness
