// PS3 platform layer: packed16x2 for two 16-bit channels (P1, P2), depth read as ARGB8 through
// the BARG remap (P4). The rules about what a pass binds, draws and samples (one MRT format,
// packed targets blended, filtered or read through the wrong view, depth filtered or read while
// written) are evaluated on the technique's real calls: ps3_rules.cpp.

#include "platforms/platform_layer.h"
#include "platforms/platforms.h"
#include "platforms/ps3/depth_read.h"
#include "platforms/ps3/packed16.h"
#include "platforms/ps3/ps3_platform.h"
#include "platforms/ps3/surface.h"

namespace parity::platforms::ps3 {

namespace {

constexpr TargetRow kArgb8 = {.format = LogicalFormat::Rgba8Unorm, .consoleFormat = "A8R8G8B8",
                              .consoleBytesPerPixel = 4, .hostFormat = rhi::Format::RGBA8, .write = "unorm8",
                              .read = "A8R8G8B8 texture", .source = "P1",
                              .resolve = "none: A8R8G8B8 sampled directly", .effectiveBits = 8};

constexpr TargetTable kTargets = {
    kArgb8,
    // P1: no two-channel 16-bit surface; P2: pack into ARGB8, read as Y16_X16. Exact writes store
    // the two little-endian 16-bit words through an RG16_UINT view of the RGBA8 storage: the same
    // bytes the ROP would store from the shader's byte outputs.
    TargetRow{.format = LogicalFormat::Rg16Unorm, .consoleFormat = "A8R8G8B8 (packed16x2: X16 in A,R; Y16 in G,B)",
              .consoleBytesPerPixel = 4, .hostFormat = rhi::Format::RGBA8,
              .write = "X16 = round(x * 65535); A = hi/255, R = lo/255 (same for y into G, B); ROP round(c * 255)",
              .read = "Y16_X16 view (remap 0xAAE4): .r = (A*256 + R)/65535, .g = (G*256 + B)/65535; point or "
                      "Y16_X16 filtering",
              .source = "P1, P2, P3", .readViewFormat = rhi::Format::RG16_UNORM,
              .rawViewFormat = rhi::Format::RG16_UINT, .writeFormat = rhi::Format::RG16_UINT,
              .resolve = "none: the A8R8G8B8 surface is sampled through a Y16_X16 view (host: RG16_UNORM view)",
              .effectiveBits = 16},
    TargetRow{.format = LogicalFormat::Rgba16Hdr,
              .consoleFormat = "F_W16Z16Y16X16 (FP16 x4, 64 bpp; cannot share an MRT pass with 32-bpp targets)",
              .consoleBytesPerPixel = 8, .hostFormat = rhi::Format::RGBA16F, .write = "fp16", .read = "fp16 texture",
              .source = "P1", .resolve = "none: F_W16Z16Y16X16 sampled directly", .effectiveBits = 11},
    TargetRow{.format = LogicalFormat::Depth24Stencil8,
              .consoleFormat = "Z24S8, read as A8R8G8B8 with remap 0xAA93 (BARG)", .consoleBytesPerPixel = 4, .hostFormat = rhi::Format::D24S8, .write = "depth test",
              .read = "texDepth2D_precise: round bytes of .rgb, D24 / 16777215; NEAREST enforced", .source = "P4",
              .readFormat = rhi::Format::RGBA8, .resolvedWhenRead = true,
              .resolve = "depth surface viewed as A8R8G8B8 (host: bitcast pass to RGBA8 in memory byte order), remap "
                         "0xAA93, texDepth2D_precise, NEAREST enforced",
              .effectiveBits = 24},
    withFormat(kArgb8, LogicalFormat::Rgba8Bits),
    withFormat(kArgb8, LogicalFormat::Output),
    TargetRow{.format = LogicalFormat::R8Unorm, .consoleFormat = "B8", .consoleBytesPerPixel = 1,
              .hostFormat = rhi::Format::R8, .write = "unorm8", .read = "B8 texture", .source = "P1",
              .resolve = "none: B8 sampled directly", .effectiveBits = 8},
    TargetRow{.format = LogicalFormat::R32Float, .consoleFormat = "F_X32", .consoleBytesPerPixel = 4,
              .hostFormat = rhi::Format::R32F, .write = "fp32", .read = "X32_FLOAT texture", .source = "P1",
              .resolve = "none: F_X32 sampled directly", .effectiveBits = 24},
};
static_assert(hasOneRowPerFormat(kTargets), "one row per LogicalFormat, in the enum's order");

// ps3.texdepth2d_precise = fp32-precise-factors-dp3: the depth decoded by the Cg DP3 instead.
constexpr TargetRow kDepthDecodedByDp3 = [] {
  TargetRow row = rowOf(kTargets, LogicalFormat::Depth24Stencil8);
  row.read = "texDepth2D_precise: fp32 DP3 of the bytes with _depth_factor_precise; NEAREST enforced";
  return row;
}();

}  // namespace

void planTarget(PhysicalTarget& t, const PlatformParams& params) {
  const bool dp3 = t.logical.format == LogicalFormat::Depth24Stencil8 &&
                   params.texDepth2DPrecise == TexDepth2DPrecise::Fp32PreciseFactorsDp3;
  applyTargetRow(dp3 ? kDepthDecodedByDp3 : rowOf(kTargets, t.logical.format), t);
}

TargetMapping mapTarget(LogicalFormat logical, const PlatformParams& params) {
  return platforms::mapTarget(PlatformId::Ps3, logical, params);
}

void shaderDefines(const PlatformParams& params, std::vector<std::pair<std::string, std::string>>& out) {
  out.push_back({"PARITY_PLATFORM_PS3", "1"});
  out.push_back({"PARITY_PS3_DEPTH_REMAP", "0xAA93u"});
  out.push_back({"PARITY_PS3_DEPTH_PRECISE_DP3",
                 params.texDepth2DPrecise == TexDepth2DPrecise::Fp32PreciseFactorsDp3 ? "1" : "0"});
}

}  // namespace parity::platforms::ps3
