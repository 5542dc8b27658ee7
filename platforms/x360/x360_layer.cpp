// Xbox 360 platform layer: every render target lives in EDRAM (X1), placed contiguously from
// tile 0 in the order the technique lists them (sizes per X1 from the pitch, the MSAA mode and
// the bits per sample); two 16-bit channels become k_16_16 brought out
// by the DSF resolve path the parameters choose (X2, X3); depth is resolved raw.
#include <algorithm>
#include <cstdio>

#include "platforms/platform_layer.h"
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

EdramSurface surfaceOf(const PhysicalTarget& t, uint32_t width, uint32_t height, const PlatformParams& params) {
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

// X3 rules of one resolve of the whole surface `t` (width x height pixels): E_RESOLVE_ALIGNMENT, ...
void checkResolve(const PhysicalTarget& t, uint32_t width, uint32_t height, const PlatformParams& params,
                  DiagnosticList& out) {
  ResolveRequest request;
  request.rect = {0, 0, width, height};  // GpuTargets resolves whole surfaces
  checkResolveRequest(surfaceOf(t, width, height, params), request, out);
}

}  // namespace

void planTarget(PhysicalTarget& t, const PlatformParams& params) {
  t.mapping = mapTarget(t.logical.format, params);
  t.inEdram = true;
  // RB_SURFACE_INFO.msaa_samples: 4x is a host MSAA attachment (planSamples; the RHI offers 1 or
  // 4 samples, Xenos 2x has no host equivalent, see GpuTargets::resolve).
  switch (t.logical.format) {
    case LogicalFormat::Rgba8Unorm:
    case LogicalFormat::Output:
    case LogicalFormat::Rgba8Bits:
      t.attachmentFormat = rhi::Format::RGBA8;
      t.readFormat = rhi::Format::RGBA8;
      t.resolve = {t.logical.readLater, "resolve k_8_8_8_8 -> k_8_8_8_8, no bias (bit copy)", 8};
      break;
    case LogicalFormat::Rg16Unorm: {
      DsfPathSpec path = dsfPath(params.dsfResolvePath);
      t.attachmentFormat = rhi::Format::RG16_SNORM;  // host bits = guest int16
      t.rawViewFormat = rhi::Format::RG16_UINT;      // resolves read the bits (Xenia's UINT transfer)
      t.writeFormat = rhi::Format::RG16_UINT;        // exact writes store the int16 the shader encodes
      t.readFormat = path.fetchSigned ? rhi::Format::RG16_SNORM : rhi::Format::RG16_UNORM;
      t.resolve = {t.logical.readLater,
                   "resolve path " + std::string(path.name) + " (" + std::string(path.description) +
                       "): copy_dest_exp_bias " + std::to_string(path.destExpBias) + ", " +
                       (path.destNumber == SurfaceNumberFormat::kSignedRepeatingFraction ? "signed" : "unsigned") +
                       " k_16_16 destination, " + (path.fetchSigned ? "signed" : "unsigned") + " fetch",
                   rg16EffectiveBits(PlatformId::X360, params)};
      break;
    }
    case LogicalFormat::Rgba16Hdr:
      if (params.hdrFormat == X360HdrFormat::Float7e3) {
        // k_2_10_10_10_FLOAT (32 bpp, X2). Host: RGBA32F holding 7e3 values (exact; the sums a
        // blend leaves are rounded to 7e3 after the pass); the resolve copies them.
        t.attachmentFormat = rhi::Format::RGBA32F;
        t.readFormat = rhi::Format::RGBA32F;
        t.resolve = {t.logical.readLater,
                     "resolve k_2_10_10_10_FLOAT -> k_2_10_10_10_FLOAT (bit copy): 7e3 over [0, 31.875], "
                     "8 significant bits",
                     8};
        break;
      }
      // k_16_16_16_16 (64 bpp, X2). Host: RGBA32F holding s * 2^-15 (exact, blendable); the
      // resolve keeps the raw int16 in a signed k_16_16_16_16 texture, held as RGBA32F float(s)
      // because the host has no 16-bit integer or snorm RGBA format. Precision: steps of
      // 32/32767 = 9.766e-4 over [-32, 32]; 32767 levels over [0, 32), log2 = 15 bits.
      t.attachmentFormat = rhi::Format::RGBA32F;
      t.readFormat = rhi::Format::RGBA32F;
      t.resolve = {t.logical.readLater,
                   "resolve k_16_16_16_16 -> signed k_16_16_16_16 (raw int16 kept), signed fetch, exp_adjust +5: "
                   "steps of 32/32767 over [-32, 32]",
                   15};
      break;
    case LogicalFormat::R8Unorm:
      t.attachmentFormat = t.readFormat = rhi::Format::R8;
      t.resolve = {t.logical.readLater, "resolve k_8_8_8_8 -> k_8, no bias (bit copy of red)", 8};
      break;
    case LogicalFormat::R32Float:
      t.attachmentFormat = t.readFormat = rhi::Format::R32F;
      t.resolve = {t.logical.readLater, "resolve k_32_FLOAT -> k_32_FLOAT, no bias (bit copy)", 24};
      break;
    case LogicalFormat::Depth24Stencil8:
      t.attachmentFormat = rhi::Format::D24S8;
      t.readFormat = rhi::Format::R32_UINT;
      t.resolve = {t.logical.readLater, "resolve D24S8 raw (no conversion, averaging or bias), read D24 / 16777215",
                   depthEffectiveBits(PlatformId::X360)};
      break;
  }
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
    surfaces.push_back(surfaceOf(t, plan.width, plan.height, plan.params));
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
  // Every pass: the targets live in it are bound together or must survive it, so they share
  // RB_SURFACE_INFO and none may overlap another (X1, X4).
  std::vector<std::string> passes;
  for (const std::vector<std::string>& l : live)
    for (const std::string& p : l)
      if (std::find(passes.begin(), passes.end(), p) == passes.end()) passes.push_back(p);
  for (const std::string& pass : passes) {
    std::vector<EdramSurface> together;
    for (size_t i = 0; i < surfaces.size(); ++i)
      if (std::find(live[i].begin(), live[i].end(), pass) != live[i].end()) together.push_back(surfaces[i]);
    checkBoundTargets(pass.empty() ? "the pass" : pass, together, plan.diagnostics);
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
