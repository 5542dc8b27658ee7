// Xbox 360 platform layer: every render target lives in EDRAM (X1), placed contiguously from
// tile 0 in the order the technique lists them (sizes per X1 from the pitch, the MSAA mode and
// the bits per sample); two 16-bit channels become k_16_16 brought out
// by the DSF resolve path the parameters choose (X2, X3); depth is resolved raw.
#include <algorithm>
#include <cstdio>

#include "platforms/platform_layer.h"
#include "platforms/platforms.h"
#include "platforms/x360/edram.h"
#include "platforms/x360/fixed16.h"
#include "platforms/x360/resolve.h"
#include "platforms/x360/x360_platform.h"

namespace parity::platforms::x360 {

namespace {

std::string num(float v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f", v);
  return b;
}

constexpr TargetRow kRgba8 = {.format = LogicalFormat::Rgba8Unorm,
                              .consoleFormat = "k_8_8_8_8 in EDRAM, resolved to k_8_8_8_8", .consoleBytesPerPixel = 4,
                              .hostFormat = rhi::Format::RGBA8, .write = "unorm8",
                              .read = "sample the resolved texture", .source = "X1, X3", .resolvedWhenRead = true,
                              .resolve = "resolve k_8_8_8_8 -> k_8_8_8_8, no bias (bit copy)", .effectiveBits = 8};

constexpr TargetTable kTargets = {
    kRgba8,
    // Two 16-bit channels: k_16_16 is fixed point -32...32 in EDRAM (X2); the path that brings
    // [0, 1] values out of it is a parameter (X3 paths A, B, C): applyDsfPath writes the row's
    // write, read, read format and resolve. Host bits = guest int16 (kGpuK16HostStorage); resolves
    // read the bits (Xenia's UINT transfer), exact writes store the int16 the shader encodes.
    TargetRow{.format = LogicalFormat::Rg16Unorm,
              .consoleFormat = "k_16_16 (fixed point -32...32) in EDRAM, resolved to k_16_16",
              .consoleBytesPerPixel = 4, .hostFormat = rhi::Format::RG16_SNORM, .source = "X2, X3",
              .rawViewFormat = rhi::Format::RG16_UINT, .writeFormat = rhi::Format::RG16_UINT,
              .resolvedWhenRead = true},
    // k_16_16_16_16 (64 bpp, X2). The host has no RGBA16_SNORM/UINT formats: RGBA32F holds
    // s * 2^-15 for the guest int16 s, exact in fp32, and sums of such values stay exact, so
    // additive blending adds int16 steps exactly as the EDRAM blender does (see
    // shaders/platforms/x360/targets.glsl). The resolve keeps the raw int16 in a signed
    // k_16_16_16_16 texture, held as RGBA32F float(s). Precision: steps of 32/32767 = 9.766e-4
    // over [-32, 32]; 32767 levels over [0, 32), log2 = 15 bits.
    TargetRow{.format = LogicalFormat::Rgba16Hdr,
              .consoleFormat = "k_16_16_16_16 (fixed point -32...32, 64 bpp) in EDRAM", .consoleBytesPerPixel = 8,
              .hostFormat = rhi::Format::RGBA32F,
              .write = "fixed point -32...32 (s = round-half-away(v * 32767/32), NaN -> 0), host stores s * 2^-15",
              .read = "resolve into a signed k_16_16_16_16 texture (raw int16 kept), signed fetch with exp_adjust +5: "
                      "max(s/32767, -1) * 32",
              .source = "X2, X4", .resolvedWhenRead = true,
              .resolve = "resolve k_16_16_16_16 -> signed k_16_16_16_16 (raw int16 kept), signed fetch, exp_adjust +5: "
                         "steps of 32/32767 over [-32, 32]",
              .effectiveBits = 15},
    TargetRow{.format = LogicalFormat::Depth24Stencil8,
              .consoleFormat = "D24S8 in EDRAM (40x16-sample tile halves swapped)", .consoleBytesPerPixel = 4,
              .hostFormat = rhi::Format::D24S8, .write = "depth test",
              .read = "resolve (raw copy, no conversion), then sample", .source = "X1, X3",
              .readFormat = rhi::Format::R32_UINT, .resolvedWhenRead = true,
              .resolve = "resolve D24S8 raw (no conversion, averaging or bias), read D24 / 16777215",
              .effectiveBits = 24},
    withFormat(kRgba8, LogicalFormat::Rgba8Bits),
    withFormat(kRgba8, LogicalFormat::Output),
    // No 8-bit colour render-target format (ColorRenderTargetFormat): the red of a 32-bpp surface.
    TargetRow{.format = LogicalFormat::R8Unorm, .consoleFormat = "k_8_8_8_8 in EDRAM (red written), resolved to k_8",
              .consoleBytesPerPixel = 4, .hostFormat = rhi::Format::R8, .write = "unorm8 into red",
              .read = "sample the resolved k_8 texture", .source = "X1, X3", .resolvedWhenRead = true,
              .resolve = "resolve k_8_8_8_8 -> k_8, no bias (bit copy of red)", .effectiveBits = 8},
    TargetRow{.format = LogicalFormat::R32Float, .consoleFormat = "k_32_FLOAT in EDRAM, resolved to k_32_FLOAT",
              .consoleBytesPerPixel = 4, .hostFormat = rhi::Format::R32F, .write = "fp32",
              .read = "sample the resolved texture", .source = "X1, X3", .resolvedWhenRead = true,
              .resolve = "resolve k_32_FLOAT -> k_32_FLOAT, no bias (bit copy)", .effectiveBits = 24},
};
static_assert(hasOneRowPerFormat(kTargets), "one row per LogicalFormat, in the enum's order");

// Rgba16Hdr under x360.hdr_format = k_2_10_10_10_float: k_2_10_10_10_FLOAT (32 bpp, X2). Host:
// RGBA32F holding 7e3 values (exact; the sums a blend leaves are rounded to 7e3 after the pass);
// the resolve copies them.
constexpr TargetRow kFloat7e3Hdr = {
    .format = LogicalFormat::Rgba16Hdr, .consoleFormat = "k_2_10_10_10_FLOAT (7e3 RGB, 2-bit alpha, 32 bpp) in EDRAM",
    .consoleBytesPerPixel = 4, .hostFormat = rhi::Format::RGBA32F,
    .write = "float; stored as 7e3 (3-bit exponent, 7-bit mantissa, [0, 31.875], negatives 0), rounded to nearest "
             "even after each pass",
    .read = "resolve into k_2_10_10_10_FLOAT (bit copy), fetched as the 7e3 values", .source = "X2",
    .resolvedWhenRead = true,
    .resolve = "resolve k_2_10_10_10_FLOAT -> k_2_10_10_10_FLOAT (bit copy): 7e3 over [0, 31.875], 8 significant bits",
    .effectiveBits = 8};

// X3: how a Rg16Unorm target is written, resolved and fetched: the DSF path the parameters choose.
void applyDsfPath(PhysicalTarget& t, const PlatformParams& params) {
  DsfPathSpec path = dsfPath(params.dsfResolvePath);
  t.mapping.write = "path " + std::string(path.name) + ": " + std::string(path.description);
  t.mapping.read = path.fetchSigned ? "signed k_16_16 fetch max(s/32767, -1), then (t + 1) / 2"
                                    : "unsigned k_16_16 fetch word / 65535";
  t.readFormat = path.fetchSigned ? rhi::Format::RG16_SNORM : rhi::Format::RG16_UNORM;
  t.resolve.description = "resolve path " + std::string(path.name) + " (" + std::string(path.description) +
                          "): copy_dest_exp_bias " + std::to_string(path.destExpBias) + ", " +
                          (path.destNumber == SurfaceNumberFormat::kSignedRepeatingFraction ? "signed" : "unsigned") +
                          " k_16_16 destination, " + (path.fetchSigned ? "signed" : "unsigned") + " fetch";
  t.resolve.effectiveBits = dsfPathPrecision(path, params).roundedBits;
}

}  // namespace

EdramSurface edramSurface(const PhysicalTarget& t, uint32_t width, uint32_t height, const PlatformParams& params) {
  EdramSurface s;
  s.name = t.logical.name;
  s.isDepth = t.logical.format == LogicalFormat::Depth24Stencil8;
  s.colorFormat = t.logical.format == LogicalFormat::Rg16Unorm   ? ColorRenderTargetFormat::k_16_16
                  : t.logical.format == LogicalFormat::Rgba16Hdr && params.hdrFormat == X360HdrFormat::Float7e3
                      ? ColorRenderTargetFormat::k_2_10_10_10_FLOAT
                  : t.logical.format == LogicalFormat::Rgba16Hdr ? ColorRenderTargetFormat::k_16_16_16_16
                  : t.logical.format == LogicalFormat::R32Float  ? ColorRenderTargetFormat::k_32_FLOAT
                                                                 : ColorRenderTargetFormat::k_8_8_8_8;
  s.pitchPx = width;
  s.heightPx = height;
  s.msaa = t.samples == 4 ? MsaaSamples::k4X : MsaaSamples::k1X;
  s.baseTile = t.edramBase;
  s.role = t.logical.role == TargetRole::GBuffer   ? SurfaceRole::GBuffer
           : t.logical.role == TargetRole::LBuffer ? SurfaceRole::LBuffer
                                                   : SurfaceRole::Plain;
  return s;
}

namespace {
// X3 rules of one resolve of the whole surface `t`, padded as the port allocates it.
void checkResolve(const PhysicalTarget& t, uint32_t width, uint32_t height, const PlatformParams& params,
                  DiagnosticList& out) {
  checkResolveRequest(edramSurface(t, width, height, params), wholeSurfaceResolve(width, height), out);
}
}  // namespace

void planTarget(PhysicalTarget& t, const PlatformParams& params) {
  const bool float7e3 = t.logical.format == LogicalFormat::Rgba16Hdr && params.hdrFormat == X360HdrFormat::Float7e3;
  applyTargetRow(float7e3 ? kFloat7e3Hdr : rowOf(kTargets, t.logical.format), t);
  // Every render target lives in EDRAM (X1). RB_SURFACE_INFO.msaa_samples: 4x is a host MSAA
  // attachment (planSamples; the RHI offers 1 or 4 samples, Xenos 2x has no host equivalent, see
  // GpuTargets::resolve).
  t.inEdram = true;
  if (t.logical.format == LogicalFormat::Rg16Unorm) applyDsfPath(t, params);
}

TargetMapping mapTarget(LogicalFormat logical, const PlatformParams& params) {
  return platforms::mapTarget(PlatformId::X360, logical, params);
}

void shaderDefines(const PlatformParams& params, std::vector<std::pair<std::string, std::string>>& out) {
  DsfPathSpec path = dsfPath(params.dsfResolvePath);
  out.push_back({"PARITY_PLATFORM_X360", "1"});
  out.push_back({"PARITY_DSF_SCALE", num(path.shaderScale)});
  out.push_back({"PARITY_DSF_OFFSET", num(path.shaderOffset)});
  out.push_back({"PARITY_COLOR_EXP_BIAS", std::to_string(path.colorExpBias)});
  out.push_back({"PARITY_DSF_SAMPLE_ADD", num(path.sampleAdd)});
  out.push_back({"PARITY_DSF_SAMPLE_MUL", num(path.sampleMul)});
  if (params.hdrFormat == X360HdrFormat::Float7e3) out.push_back({"PARITY_X360_HDR_7E3", "1"});
}

// The passes in which a target's contents are live (LogicalTarget::livePasses, else its pass).
static std::vector<std::string> livePassesOf(const LogicalTarget& t) {
  return t.livePasses.empty() ? std::vector<std::string>{t.pass} : t.livePasses;
}

void checkPlan(TargetPlan& plan) {
  // Placement in the technique's order: after one another from tile 0 (bases wrap modulo 2048);
  // a target that declares its live passes takes the lowest tiles no target live with it holds.
  std::vector<EdramSurface> surfaces;
  std::vector<std::vector<std::string>> live;
  for (PhysicalTarget& t : plan.targets) {
    surfaces.push_back(edramSurface(t, plan.width, plan.height, plan.params));
    live.push_back(livePassesOf(t.logical));
  }
  auto liveTogether = [&](size_t i, size_t j) {
    for (const std::string& p : live[i])
      if (std::find(live[j].begin(), live[j].end(), p) != live[j].end()) return true;
    return false;
  };
  placeReusingDeadTiles(surfaces, [&](size_t i) { return !plan.targets[i].logical.livePasses.empty(); }, liveTogether);
  for (size_t i = 0; i < surfaces.size(); ++i) {
    plan.targets[i].edramBase = surfaces[i].baseTile;
    plan.targets[i].edramTiles = surfaces[i].sizeTiles();
  }
  // Every pass: none of the targets live in it (bound, or surviving it) may overlap another, and
  // together they must fit (X1, X4). What a pass really binds together (one RB_SURFACE_INFO,
  // distinct bases) is checked on the technique's passes (x360_rules.cpp).
  std::vector<std::string> passes;
  for (const std::vector<std::string>& l : live)
    for (const std::string& p : l)
      if (std::find(passes.begin(), passes.end(), p) == passes.end()) passes.push_back(p);
  for (const std::string& pass : passes) {
    std::vector<EdramSurface> together;
    for (size_t i = 0; i < surfaces.size(); ++i)
      if (std::find(live[i].begin(), live[i].end(), pass) != live[i].end()) together.push_back(surfaces[i]);
    checkLiveSurfaces(pass.empty() ? "the pass" : pass, together, plan.diagnostics);
  }
  // X3 rules of the whole-surface resolve of every target a later pass reads: the same check
  // GpuTargets::resolve() runs, so that `parity explain` shows what a run will report.
  for (const PhysicalTarget& t : plan.targets)
    if (t.resolve.needed) checkResolve(t, plan.width, plan.height, plan.params, plan.diagnostics);
  // Resolve precision and the fixed-point range of DSF targets (X2, X3).
  DsfPathSpec path = dsfPath(plan.params.dsfResolvePath);
  for (const PhysicalTarget& t : plan.targets) {
    if (t.logical.format != LogicalFormat::Rg16Unorm) continue;
    float lo = path.shaderOffset, hi = path.shaderScale + path.shaderOffset;
    checkFixed16OutputRange(t.logical.name, std::min(lo, hi), std::max(lo, hi), path.colorExpBias, plan.diagnostics);
    if (t.logical.readLater) checkDsfPathPrecision(t.logical.name, path, plan.diagnostics, plan.params);
  }
}

}  // namespace parity::platforms::x360
