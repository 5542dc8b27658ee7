// PS3 platform layer: packed16x2 for two 16-bit channels (P1, P2), one MRT format per pass
// (P1), depth read as ARGB8 through the BARG remap (P4).
#include <set>

#include "platforms/platform_layer.h"
#include "platforms/ps3/depth_read.h"
#include "platforms/ps3/packed16.h"
#include "platforms/ps3/ps3_platform.h"
#include "platforms/ps3/surface.h"

namespace parity::platforms::ps3 {

void planTarget(PhysicalTarget& t, const PlatformParams& params) {
  t.mapping = mapTarget(t.logical.format, params);
  t.attachmentFormat = t.mapping.hostFormat;
  t.readFormat = t.attachmentFormat;
  switch (t.logical.format) {
    case LogicalFormat::Rgba8Unorm:
    case LogicalFormat::Output:
    case LogicalFormat::Rgba8Bits:
      t.resolve = {false, "none: A8R8G8B8 sampled directly", 8};
      break;
    case LogicalFormat::Rg16Unorm:
      t.readViewFormat = rhi::Format::RG16_UNORM;
      // Exact writes store the two little-endian 16-bit words through an RG16_UINT view of the
      // RGBA8 storage: the same bytes the ROP would store from the shader's byte outputs.
      t.rawViewFormat = rhi::Format::RG16_UINT;
      t.writeFormat = rhi::Format::RG16_UINT;
      t.resolve = {false, "none: the A8R8G8B8 surface is sampled through a Y16_X16 view (host: RG16_UNORM view)",
                   rg16EffectiveBits(PlatformId::Ps3, params)};
      break;
    case LogicalFormat::Rgba16Hdr:
      t.resolve = {false, "none: F_W16Z16Y16X16 sampled directly", 11};
      break;
    case LogicalFormat::R8Unorm:
      t.resolve = {false, "none: B8 sampled directly", 8};
      break;
    case LogicalFormat::R32Float:
      t.resolve = {false, "none: F_X32 sampled directly", 24};
      break;
    case LogicalFormat::Depth24Stencil8:
      t.readFormat = rhi::Format::RGBA8;
      t.resolve = {t.logical.readLater,
                   "depth surface viewed as A8R8G8B8 (host: bitcast pass to RGBA8 in memory byte order), remap 0xAA93, "
                   "texDepth2D_precise, NEAREST enforced",
                   depthEffectiveBits(PlatformId::Ps3)};
      break;
  }
}

void shaderDefines(const PlatformParams& params, std::vector<std::pair<std::string, std::string>>& out) {
  out.push_back({"PARITY_PLATFORM_PS3", "1"});
  out.push_back({"PARITY_PS3_DEPTH_REMAP", "0xAA93u"});
  out.push_back({"PARITY_PS3_DEPTH_PRECISE_DP3",
                 params.texDepth2DPrecise == TexDepth2DPrecise::Fp32PreciseFactorsDp3 ? "1" : "0"});
}

void checkPlan(TargetPlan& plan) {
  std::vector<std::string> passes;
  std::map<std::string, std::vector<ColorSurface>> byPass;
  for (const PhysicalTarget& t : plan.targets) {
    if (t.logical.format == LogicalFormat::Depth24Stencil8) {
      if (t.logical.readLater) {
        DepthAsColorRead read;
        read.surface = t.logical.name;
        checkDepthAsColorRead(read, plan.diagnostics);
      }
      continue;
    }
    SurfaceRequest req;
    req.name = t.logical.name;
    if (t.logical.format == LogicalFormat::Rg16Unorm) {
      req.channels = 2;
      req.bitsPerChannel = 16;
    } else if (t.logical.format == LogicalFormat::Rgba16Hdr) {
      req.bitsPerChannel = 16;
      req.isFloat = true;
    } else if (t.logical.format == LogicalFormat::R8Unorm) {
      req.channels = 1;
    } else if (t.logical.format == LogicalFormat::R32Float) {
      req.channels = 1;
      req.bitsPerChannel = 32;
      req.isFloat = true;
    }
    std::optional<ColorSurface> s = requestColorSurface(req, plan.diagnostics);
    if (!s) continue;
    if (std::find(passes.begin(), passes.end(), t.logical.pass) == passes.end()) passes.push_back(t.logical.pass);
    byPass[t.logical.pass].push_back(*s);
    if (s->packed16x2 && t.logical.readLater) {
      PackedTextureRead read;
      read.texture = t.logical.name;
      checkPackedTextureRead(read, plan.diagnostics);
    }
  }
  for (const std::string& pass : passes)
    checkMrt(pass.empty() ? "the pass" : pass, byPass[pass], plan.params.ps3MrtRule, plan.diagnostics);
}

}  // namespace parity::platforms::ps3
