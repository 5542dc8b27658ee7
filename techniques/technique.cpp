#include "techniques/technique.h"

#include <algorithm>
#include <filesystem>

#include "techniques/forward/forward.h"
#include "techniques/forward_multipass/forward_multipass.h"
#include "techniques/inferred/inferred.h"
#include "techniques/light_indexed/light_indexed.h"
#include "techniques/tiled/tiled.h"
#include "techniques/deferred/deferred.h"
#include "techniques/light_prepass/light_prepass.h"
#include "techniques/forward_shadows/forward_shadows.h"
#include "techniques/ssao/deferred_ssao.h"
#include "techniques/hdr/hdr.h"
#include "techniques/abuffer/abuffer.h"

namespace parity::techniques {

namespace {

std::vector<TechniqueEntry>& registry() {
  static std::vector<TechniqueEntry> entries = {
      {"forward", "single-pass forward shading: ambient, one directional and N point/spot lights in one shader",
       [] { return std::make_unique<ForwardSinglePass>(); }},
      {"forward-multipass",
       "multi-pass forward shading (thesis 3.1.3): ambient + directional pass, then one additive pass per light "
       "over its light list",
       [] { return std::make_unique<ForwardMultiPass>(); }},
      {"inferred",
       "inferred lighting (Kircher & Lawrance 2009): G-buffer and L-buffer at reduced resolution, material pass with "
       "the discontinuity sensitive filter, stippled alpha polygons",
       [] { return std::make_unique<InferredLighting>(); }},
      {"lidr-sort",
       "light-indexed deferred (Trebilco 2008), CPU sorting: lights in four non-overlapping arrays, one RGBA8 "
       "channel each",
       [] { return std::make_unique<LightIndexedDeferred>(LidrPacking::Sort); }},
      {"lidr-max",
       "light-indexed deferred (Trebilco 2008), multi-pass MAX blend with the stencil limiting writes: up to 4 "
       "indices",
       [] { return std::make_unique<LightIndexedDeferred>(LidrPacking::Max); }},
      {"lidr-bits",
       "light-indexed deferred (Trebilco 2008), bit shifting with blend ONE, CONSTANT_COLOR 0.25: 4 overlaps of 255 "
       "lights (lidr-bits-OxN: the other rows of the paper's table)",
       [] { return std::make_unique<LightIndexedDeferred>(LidrPacking::Bits, *findBitPackingRow("4x255")); }},
      {"lidr-bits-1x255", "light-indexed deferred, bit shifting: 1 overlap of 255 lights",
       [] { return std::make_unique<LightIndexedDeferred>(LidrPacking::Bits, *findBitPackingRow("1x255")); }},
      {"lidr-bits-2x255", "light-indexed deferred, bit shifting: 2 overlaps of 255 lights",
       [] { return std::make_unique<LightIndexedDeferred>(LidrPacking::Bits, *findBitPackingRow("2x255")); }},
      {"lidr-bits-8x255", "light-indexed deferred, bit shifting: 8 overlaps of 255 lights",
       [] { return std::make_unique<LightIndexedDeferred>(LidrPacking::Bits, *findBitPackingRow("8x255")); }},
      {"lidr-bits-2x15", "light-indexed deferred, bit shifting: 2 overlaps of 15 lights",
       [] { return std::make_unique<LightIndexedDeferred>(LidrPacking::Bits, *findBitPackingRow("2x15")); }},
      {"lidr-bits-4x15", "light-indexed deferred, bit shifting: 4 overlaps of 15 lights",
       [] { return std::make_unique<LightIndexedDeferred>(LidrPacking::Bits, *findBitPackingRow("4x15")); }},
      {"lidr-bits-8x15", "light-indexed deferred, bit shifting: 8 overlaps of 15 lights",
       [] { return std::make_unique<LightIndexedDeferred>(LidrPacking::Bits, *findBitPackingRow("8x15")); }},
      {"lidr-msaa",
       "light-indexed deferred (Trebilco 2008), MSAA technique 2: light volume front faces into a single-sample "
       "index texture, 4x MSAA forward pass with translucent meshes (bit shifting, 8 overlaps of 255 lights)",
       [] {
         return std::make_unique<LightIndexedDeferred>(LidrPacking::Bits, *findBitPackingRow("8x255"),
                                                       LidrVolumes::FrontFacesMsaa);
       }},
      {"tiled-deferred",
       "tiled deferred shading: G-buffer, compute light lists per 16x16 tile from its depth bounds, one shading "
       "pass per pixel over its tile's list",
       [] { return std::make_unique<TiledShading>(TiledMode::Deferred); }},
      {"tiled-forward",
       "tiled forward shading: depth pre-pass, compute light lists per 16x16 tile, forward geometry pass over "
       "its tile's list",
       [] { return std::make_unique<TiledShading>(TiledMode::Forward); }},
      {"deferred",
       "deferred shading (thesis 3.1.4): G-buffer pass, full-screen ambient + directional, light volumes (spheres, "
       "cones) added into an HDR accumulation target",
       [] { return std::make_unique<DeferredShading>(); }},
      {"light-prepass",
       "deferred lighting / light pre-pass: n/m buffer, diffuse and specular light accumulated in 6 channels, second "
       "geometry pass applies the materials",
       [] { return std::make_unique<LightPrePass>(false); }},
      {"light-prepass-4ch",
       "deferred lighting / light pre-pass, 4 channels: specular luminance in alpha, its colour rebuilt from the "
       "diffuse chromaticity (RTR appendix A)",
       [] { return std::make_unique<LightPrePass>(true); }},
      {"forward-shadows",
       "multi-pass forward shading with shadow maps (thesis 3.1): directional, spot and point-cube maps with "
       "hardware PCF for lights that cast shadows, one local map reused from light to light",
       [] { return std::make_unique<ForwardShadows>(); }, true},
      {"deferred-shadows",
       "deferred shading with shadow maps (thesis 3.1, 4.1 'big lights with shadows'): the directional map before "
       "the G-buffer, each shadow-casting light's map rendered just before its light volume",
       [] { return std::make_unique<DeferredShading>(true); }, true},
      {"deferred-ssao",
       "deferred shading with screen-space ambient occlusion (Ferko 2012 5.1-5.2): hemisphere-corrected samples, "
       "half-resolution occlusion, separable cross-bilateral blur",
       [] { return std::make_unique<DeferredSsao>(); }},
      {"hdr",
       "HDR: forward shading into a 16-bit float target, log-average luminance by GPU reduction, Reinhard global "
       "tone mapping, bloom summed over a mip chain",
       [] { return std::make_unique<HdrToneMapping>(); }},
      {"abuffer",
       "order-independent transparency with the stencil-routed A-buffer (Ferko 2012 4.1): 4 fragments per pixel "
       "routed to MSAA samples, sorted and blended in a full-screen pass",
       [] { return std::make_unique<OrderIndependentTransparency>(TransparencyMode::StencilRouted); }},
      {"depth-peeling",
       "order-independent transparency by depth peeling, 4 layers: the A-buffer's reference",
       [] { return std::make_unique<OrderIndependentTransparency>(TransparencyMode::DepthPeeling); }},
  };
  return entries;
}

}  // namespace

const std::vector<TechniqueEntry>& techniqueRegistry() { return registry(); }

void registerTechnique(TechniqueEntry entry) {
  auto bad = [&](const std::string& why) { throw TechniqueError("registerTechnique: " + why); };
  if (entry.name.empty() || entry.name.find_first_of("/ \t") != std::string::npos)
    bad("name '" + entry.name + "' must be non-empty without '/' or spaces (it names golden folders)");
  if (!entry.create) bad("technique '" + entry.name + "' has no create function");
  for (const TechniqueEntry& e : registry())
    if (e.name == entry.name) bad("a technique named '" + entry.name + "' is registered already");
  registry().push_back(std::move(entry));
}

std::unique_ptr<Technique> createTechnique(const std::string& name) {
  for (const TechniqueEntry& e : techniqueRegistry())
    if (e.name == name) return e.create();
  return nullptr;
}

rhi::ShaderCompileOptions mergeShaderOptions(const rhi::ShaderCompileOptions& base, const rhi::ShaderCompileOptions& extra) {
  rhi::ShaderCompileOptions o = base;
  o.includeDirs.insert(o.includeDirs.end(), extra.includeDirs.begin(), extra.includeDirs.end());
  o.defines.insert(o.defines.end(), extra.defines.begin(), extra.defines.end());
  return o;
}

ShaderLibrary::~ShaderLibrary() {
  for (rhi::ShaderHandle h : shaders_) device_.destroy(h);
}

rhi::ShaderHandle ShaderLibrary::load(const std::string& path, const rhi::ShaderCompileOptions& options) {
  rhi::ShaderStage stage;
  if (!rhi::stageFromPath(path, &stage)) throw TechniqueError(path + ": error: unknown shader stage (extension)");
  std::string full = (std::filesystem::path(rhi::shaderDirectory()) / path).string();
  rhi::CompiledShader compiled = rhi::compileGlslFile(full, stage, options);
  if (!compiled.ok()) throw TechniqueError(compiled.error);
  rhi::ShaderDesc desc;
  desc.stage = stage;
  desc.spirv = std::move(compiled.spirv);
  desc.label = path;
  rhi::ShaderHandle h = device_.createShader(desc);
  if (!h) throw TechniqueError(path + ": error: the device rejected the shader");
  shaders_.push_back(h);
  return h;
}

rhi::Capabilities runnableCapabilities(rhi::Device& device, const RenderSettings& settings) {
  rhi::Capabilities caps = device.info().caps;
  caps.compute = caps.compute && settings.capabilities.compute;
  caps.maxSamples = std::min(caps.maxSamples, settings.capabilities.maxSamples);
  return caps;
}

std::string describePortPath(const PortPath& path, platforms::PlatformId platform) {
  const platforms::CapabilityRow& row = platforms::platformCapabilities(platform).row(path.capability);
  return path.pass + ": " + path.path + " (the port's path; capability " + std::string(platforms::capabilityName(path.capability)) +
         ": " + platforms::describeRow(platform, row) + ")";
}

}  // namespace parity::techniques
