// `parity explain`: how a platform maps a technique's logical targets to real formats, where
// they sit in EDRAM (x360), what the resolves do and how precise they are, which diagnostics
// fire, the port's paths the technique takes there and the platform's capabilities
// (explain_capabilities.h), and the open-question parameters the answer depends on.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "harness/cli/commands.h"
#include "harness/cli/explain_capabilities.h"
#include "platforms/common/capabilities.h"
#include "platforms/platform_layer.h"
#include "platforms/x360/edram.h"
#include "platforms/x360/resolve.h"
#include "techniques/technique.h"

namespace parity::harness {

namespace {

using platforms::LogicalFormat;
using platforms::LogicalTarget;
using platforms::TargetRole;

struct ExplainOptions {
  std::string platform;
  std::string technique = "forward";
  std::string size = "1280x720";
  std::string targetsFile;
  bool json = false;
  std::vector<std::string> params;
};

// A registered technique's own logical targets for this output size and platform, and the size
// it allocates them at (smaller than the output for inferred lighting).
std::vector<LogicalTarget> techniqueTargets(const std::string& name, platforms::PlatformId platform,
                                            const platforms::PlatformParams& params, uint32_t w, uint32_t h,
                                            techniques::TargetExtent* extent) {
  *extent = {w, h};
  std::unique_ptr<techniques::Technique> t = techniques::createTechnique(name);
  if (!t) return {};
  techniques::RenderSettings settings;
  settings.width = w;
  settings.height = h;
  settings.platform = platform;
  settings.platformParams = params;
  settings.capabilities = platforms::publishedCapabilities(platform, rhi::Capabilities{});
  std::vector<LogicalTarget> targets = t->logicalTargets(settings);
  if (!targets.empty()) *extent = t->logicalTargetExtent(settings);
  return targets;
}

// A registered technique's plans at sizes of their own (shadow maps, bloom levels, ...), planned.
std::vector<std::pair<techniques::Technique::SizedTargets, platforms::TargetPlan>> techniqueFurtherPlans(
    const std::string& name, platforms::PlatformId platform, const platforms::PlatformParams& params, uint32_t w,
    uint32_t h) {
  std::vector<std::pair<techniques::Technique::SizedTargets, platforms::TargetPlan>> out;
  std::unique_ptr<techniques::Technique> t = techniques::createTechnique(name);
  if (!t) return out;
  techniques::RenderSettings settings;
  settings.width = w;
  settings.height = h;
  settings.platform = platform;
  settings.platformParams = params;
  settings.capabilities = platforms::publishedCapabilities(platform, rhi::Capabilities{});
  for (techniques::Technique::SizedTargets& s : t->furtherTargetPlans(settings)) {
    platforms::TargetPlan plan = platforms::planTargets(platform, s.targets, s.extent.width, s.extent.height, params);
    out.emplace_back(std::move(s), std::move(plan));
  }
  return out;
}

// The inferred-lighting paper's EDRAM budget (X1, X4) at this size: two 32-bpp G-buffers plus
// D24S8, placed contiguously from tile 0 as the layer places them. At 1280x720 that is
// 3 x 720 = 2160 tiles > 2048, so the surfaces overlap modulo 2048.
struct GBufferBudget {
  uint32_t tiles = 0;
  bool fits = true;
  std::vector<std::string> codes;  // diagnostics of that placement
};
GBufferBudget gbufferBudget(uint32_t w, uint32_t h, const platforms::PlatformParams& params) {
  const std::vector<LogicalTarget> targets = {
      {"gbuffer0", LogicalFormat::Rgba8Unorm, true, TargetRole::GBuffer, "geometry"},
      {"gbuffer1_dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"},
      {"depth", LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer, "geometry"}};
  platforms::TargetPlan plan = platforms::planTargets(platforms::PlatformId::X360, targets, w, h, params);
  GBufferBudget b;
  for (const auto& t : plan.targets) b.tiles += t.edramTiles;
  b.fits = b.tiles <= platforms::x360::kEdramTileCount;
  for (const auto& d : plan.diagnostics.all())
    if (d.code.rfind("E_EDRAM", 0) == 0 || d.code.rfind("E_GBUF", 0) == 0) b.codes.push_back(d.code);
  return b;
}

// Built-in target descriptions, usable before the techniques themselves exist.
bool builtinTargets(const std::string& technique, std::vector<LogicalTarget>* out) {
  if (technique == "gbuffer-test") {
    // The inferred lighting paper's geometry pass: two 32-bpp G-buffers (normals/depth-ID in
    // RGBA8, DSF data in two 16-bit channels) plus D24S8.
    *out = {{"gbuffer0", LogicalFormat::Rgba8Unorm, true, TargetRole::GBuffer, "geometry"},
            {"gbuffer1_dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"},
            {"depth", LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer, "geometry"}};
    return true;
  }
  return false;
}

std::optional<LogicalFormat> logicalFromName(const std::string& name) {
  for (LogicalFormat f : {LogicalFormat::Rgba8Unorm, LogicalFormat::Rg16Unorm, LogicalFormat::Rgba16Hdr,
                          LogicalFormat::Depth24Stencil8, LogicalFormat::Output, LogicalFormat::Rgba8Bits,
                          LogicalFormat::R8Unorm, LogicalFormat::R32Float})
    if (platforms::logicalFormatName(f) == name) return f;
  return std::nullopt;
}

// {"targets": [{"name": "g0", "format": "rg16_unorm", "read_later": true, "role": "gbuffer",
//   "pass": "geometry"}, ...]}
bool targetsFromFile(const std::string& path, std::vector<LogicalTarget>* out, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot read targets file " + path;
    return false;
  }
  try {
    nlohmann::json j = nlohmann::json::parse(in);
    for (const auto& t : j.at("targets")) {
      LogicalTarget l;
      l.name = t.at("name").get<std::string>();
      std::string format = t.at("format").get<std::string>();
      auto f = logicalFromName(format);
      if (!f) {
        *error = path + ": target " + l.name + ": unknown format " + format +
                 " (rgba8_unorm, rg16_unorm, rgba16_hdr, depth24_stencil8, output, rgba8_bits)";
        return false;
      }
      l.format = *f;
      l.readLater = t.value("read_later", true);
      std::string role = t.value("role", "plain");
      l.role = role == "gbuffer" ? TargetRole::GBuffer : role == "lbuffer" ? TargetRole::LBuffer : TargetRole::Plain;
      l.pass = t.value("pass", "main");
      l.stencil = t.value("stencil", false);
      out->push_back(l);
    }
  } catch (const std::exception& e) {
    *error = path + ": " + e.what();
    return false;
  }
  if (out->empty()) {
    *error = path + ": no targets";
    return false;
  }
  return true;
}

std::string formatName(rhi::Format f) { return f == rhi::Format::Undefined ? "-" : rhi::formatInfo(f).name; }

// Each target of `plan` as `parity explain --json` lists it.
nlohmann::json targetsJson(const platforms::TargetPlan& plan) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& t : plan.targets) {
    nlohmann::json e{{"name", t.logical.name},
                     {"logical", platforms::logicalFormatName(t.logical.format)},
                     {"pass", t.logical.pass},
                     {"console_format", t.mapping.consoleFormat},
                     {"console_bytes_per_pixel", t.mapping.consoleBytesPerPixel},
                     {"attachment_format", formatName(t.attachmentFormat)},
                     {"read_format", formatName(t.readFormat)},
                     {"read_view_format", formatName(t.readViewFormat)},
                     {"write", t.mapping.write},
                     {"read", t.mapping.read},
                     {"resolve", {{"needed", t.resolve.needed},
                                  {"description", t.resolve.description},
                                  {"effective_bits", t.resolve.effectiveBits}}},
                     {"source", t.mapping.source}};
    if (t.inEdram) {
      platforms::x360::TileRange r{t.edramBase, t.edramTiles};
      e["edram"] = {{"base", t.edramBase}, {"tiles", t.edramTiles}, {"range", platforms::x360::formatTileRange(r)}};
    }
    out.push_back(e);
  }
  return out;
}

// Each target of `plan`: its console and host formats, write and read rules, resolve.
void printTargets(const platforms::TargetPlan& plan) {
  for (const auto& t : plan.targets) {
    std::printf("  %s (%s, pass %s)\n", t.logical.name.c_str(), std::string(platforms::logicalFormatName(t.logical.format)).c_str(),
                t.logical.pass.c_str());
    std::printf("    console:    %s, %u B/px\n", t.mapping.consoleFormat.c_str(), t.mapping.consoleBytesPerPixel);
    std::printf("    host:       render %s, read %s%s%s\n", formatName(t.attachmentFormat).c_str(),
                formatName(t.readFormat).c_str(), t.readViewFormat != rhi::Format::Undefined ? " via view " : "",
                t.readViewFormat != rhi::Format::Undefined ? formatName(t.readViewFormat).c_str() : "");
    std::printf("    write:      %s\n", t.mapping.write.c_str());
    std::printf("    read:       %s\n", t.mapping.read.c_str());
    std::printf("    resolve:    %s%s (effective precision %.0f bits)\n", t.resolve.needed ? "" : "(not needed) ",
                t.resolve.description.c_str(), t.resolve.effectiveBits);
    std::printf("    pack:       %s\n", t.mapping.source.c_str());
  }
}

// Where each target of `plan` sits in EDRAM (x360), and the rectangle its resolves copy.
void printTileMap(const platforms::TargetPlan& plan) {
  for (const auto& t : plan.targets) {
    platforms::x360::TileRange r{t.edramBase, t.edramTiles};
    std::printf("  %-14s base %4u  tiles %4u  %s\n", t.logical.name.c_str(), t.edramBase, t.edramTiles,
                platforms::x360::formatTileRange(r).c_str());
  }
  const platforms::x360::ResolveRequest whole = platforms::x360::wholeSurfaceResolve(plan.width, plan.height);
  std::printf("  resolves: the %ux%u surfaces padded to %ux%u (the 8-pixel resolve granularity); a resolve copies "
              "(0, 0) %ux%u into a texture of %ux%u, later passes use the visible %ux%u\n",
              plan.width, plan.height, whole.rect.width, whole.rect.height, whole.rect.width, whole.rect.height,
              whole.destMipWidth, whole.destMipHeight, plan.width, plan.height);
}

// The rectangle a whole-surface resolve of `plan` copies and the texture it lands in (x360).
nlohmann::json resolveJson(const platforms::TargetPlan& plan) {
  const platforms::x360::ResolveRequest whole = platforms::x360::wholeSurfaceResolve(plan.width, plan.height);
  return {{"rectangle", {whole.rect.width, whole.rect.height}},
          {"destination", {whole.destMipWidth, whole.destMipHeight}}};
}

int runExplain(const ExplainOptions& o) {
  auto platform = platforms::platformFromName(o.platform);
  if (!platform) return reportError("unknown platform '" + o.platform + "' (reference, dx10, ps3, x360)");
  unsigned w = 0, h = 0;
  char extra = 0;
  if (std::sscanf(o.size.c_str(), "%ux%u%c", &w, &h, &extra) != 2 || w == 0 || h == 0 || w > 16384 || h > 16384)
    return reportError("invalid --size '" + o.size + "' (expected WxH, e.g. 1280x720)");
  platforms::PlatformParams params;
  for (const std::string& p : o.params) {
    size_t eq = p.find('=');
    if (eq == std::string::npos) return reportError("invalid --param '" + p + "' (expected name=value)");
    std::string error;
    if (!platforms::setParameter(params, p.substr(0, eq), p.substr(eq + 1), &error)) return reportError(error);
  }
  std::vector<LogicalTarget> targets;
  techniques::TargetExtent extent{w, h};  // where the targets are planned
  std::string source = o.technique;
  if (!o.targetsFile.empty()) {
    std::string error;
    if (!targetsFromFile(o.targetsFile, &targets, &error)) return reportError(error);
    source = o.targetsFile;
  } else {
    // A registered technique shows its own plan; the built-in paper layout (gbuffer-test) is
    // there for planning before a technique exists.
    targets = techniqueTargets(o.technique, *platform, params, w, h, &extent);
    if (!targets.empty()) {
      source = o.technique + " (its logical targets)";
    } else if (!builtinTargets(o.technique, &targets)) {
      std::string known;
      for (const auto& e : techniques::techniqueRegistry()) known += e.name + ", ";
      return reportError("no target description for technique '" + o.technique + "' (registered: " + known +
                         "built in: gbuffer-test; or give --targets FILE)");
    }
  }
  platforms::TargetPlan plan = platforms::planTargets(*platform, targets, extent.width, extent.height, params);
  // A targets file is one plan; a technique may plan more at sizes of their own.
  const auto further = techniqueFurtherPlans(o.targetsFile.empty() ? o.technique : "", *platform, params, w, h);
  const bool x360 = *platform == platforms::PlatformId::X360;
  uint32_t tilesTotal = 0;
  for (const auto& t : plan.targets) tilesTotal += t.edramTiles;

  if (o.json) {
    nlohmann::json j;
    j["platform"] = o.platform;
    j["technique"] = source;
    j["size"] = {w, h};
    j["target_size"] = {extent.width, extent.height};
    j["targets"] = targetsJson(plan);
    j["further_plans"] = nlohmann::json::array();
    for (const auto& [sized, p] : further) {
      nlohmann::json diagnostics = nlohmann::json::array();
      for (const auto& d : p.diagnostics.all()) diagnostics.push_back({{"code", d.code}, {"message", d.message}});
      j["further_plans"].push_back({{"role", sized.role},
                                    {"size", {sized.extent.width, sized.extent.height}},
                                    {"targets", targetsJson(p)},
                                    {"diagnostics", diagnostics}});
      if (x360) j["further_plans"].back()["resolve"] = resolveJson(p);
    }
    if (x360) {
      j["resolve"] = resolveJson(plan);
      j["edram"] = {{"tiles_total", tilesTotal}, {"tiles_available", platforms::x360::kEdramTileCount},
                    {"fits", tilesTotal <= platforms::x360::kEdramTileCount}};
      GBufferBudget b = gbufferBudget(w, h, params);
      j["edram"]["gbuffer_budget"] = {{"targets", "two 32-bpp G-buffers + D24S8"},
                                      {"tiles_total", b.tiles},
                                      {"fits", b.fits},
                                      {"diagnostics", b.codes}};
    }
    j["diagnostics"] = nlohmann::json::array();
    for (const auto& d : plan.diagnostics.all())
      j["diagnostics"].push_back({{"code", d.code},
                                  {"severity", platforms::severityName(d.severity)},
                                  {"section", d.section},
                                  {"targets", d.targets},
                                  {"message", d.message}});
    for (const auto& p : platforms::parameterCatalogue()) {
      std::string value = platforms::parameterValue(params, p.name);
      j["parameters"].push_back({{"name", p.name},
                                 {"value", value},
                                 {"default", p.defaultValue},
                                 {"is_default", value == p.defaultValue},
                                 {"open_question", p.openQuestion},
                                 {"section", p.section},
                                 {"values", p.values},
                                 {"explanation", p.explanation}});
    }
    const nlohmann::json capabilities = capabilitiesJson(*platform, o.targetsFile.empty() ? o.technique : "");
    for (auto& [k, v] : capabilities.items()) j[k] = v;
    j["shader_defines"] = nlohmann::json::object();
    for (const auto& [k, v] : plan.shaderDefines) j["shader_defines"][k] = v;
    std::cout << j.dump(2) << std::endl;
    return 0;
  }

  std::printf("platform %s, technique %s, %ux%u\n", o.platform.c_str(), source.c_str(), w, h);
  if (extent != techniques::TargetExtent{w, h})
    std::printf("targets planned at %ux%u (the technique's reduced resolution)\n", extent.width, extent.height);
  std::printf("\n");
  std::printf("targets:\n");
  printTargets(plan);
  if (x360) {
    std::printf("\nEDRAM tile map (2048 tiles of 80x16 samples, 5120 B; placed contiguously from tile 0):\n");
    printTileMap(plan);
    std::printf("  total %u of %u tiles: %s\n", tilesTotal, platforms::x360::kEdramTileCount,
                tilesTotal <= platforms::x360::kEdramTileCount ? "fits" : "DOES NOT FIT");
    GBufferBudget b = gbufferBudget(w, h, params);
    std::string codes;
    for (const std::string& c : b.codes) codes += (codes.empty() ? " (" : ", ") + c;
    if (!codes.empty()) codes += ")";
    std::printf("  inferred-lighting budget at %ux%u: two 32-bpp G-buffers + D24S8 = %u of %u tiles: %s%s\n", w, h,
                b.tiles, platforms::x360::kEdramTileCount, b.fits ? "fits" : "DOES NOT FIT", codes.c_str());
  }
  for (const auto& [sized, p] : further) {
    std::printf("\nplanned apart at %ux%u (%s):\n", sized.extent.width, sized.extent.height, sized.role.c_str());
    printTargets(p);
    if (x360) printTileMap(p);
    for (const auto& d : p.diagnostics.all()) std::printf("  %s\n", d.format().c_str());
  }
  std::printf("\ndiagnostics:\n");
  if (plan.diagnostics.empty()) std::printf("  none\n");
  for (const auto& d : plan.diagnostics.all()) std::printf("  %s\n", d.format().c_str());
  std::printf("  (the rules about what passes bind, draw, sample and resolve fire on the technique's calls: "
              "`parity render --platform %s`)\n",
              o.platform.c_str());
  printCapabilities(*platform, o.targetsFile.empty() ? o.technique : "");
  std::printf("\nparameters (open questions of the reference pack marked OQn):\n");
  for (const auto& p : platforms::parameterCatalogue()) {
    std::string value = platforms::parameterValue(params, p.name);
    std::string oq = p.openQuestion ? "OQ" + std::to_string(p.openQuestion) : "";
    std::printf("  %-34s = %-24s default %-24s %-4s %s\n", std::string(p.name).c_str(), value.c_str(),
                std::string(p.defaultValue).c_str(), oq.c_str(), std::string(p.explanation).c_str());
  }
  std::printf("\nshader defines:");
  for (const auto& [k, v] : plan.shaderDefines) std::printf(" %s=%s", k.c_str(), v.c_str());
  std::printf("\n");
  return 0;
}

}  // namespace

void registerExplainCommand(CLI::App& app, CommandSet& commands) {
  auto o = std::make_shared<ExplainOptions>();
  CLI::App* cmd = app.add_subcommand("explain", "show how a platform maps a technique's logical targets, EDRAM "
                                                "placement, resolves, diagnostics and parameters");
  cmd->add_option("--platform,-p", o->platform, "reference, dx10, ps3 or x360")->required();
  cmd->add_option("--technique,-t", o->technique, "a registered technique (its logical targets) or the built-in "
                                                    "paper layout gbuffer-test")
      ->capture_default_str();
  cmd->add_option("--size", o->size, "WxH")->capture_default_str();
  cmd->add_option("--targets", o->targetsFile, "JSON file describing the logical targets");
  cmd->add_option("--param", o->params, "platform parameter name=value (see the parameter list)");
  cmd->add_flag("--json", o->json, "machine-readable output");
  commands.add(cmd, [o] { return runExplain(*o); });
}

}  // namespace parity::harness
