#include "platforms/ps3/ps3_platform.h"

namespace parity::platforms::ps3 {

TargetMapping mapTarget(LogicalFormat logical, const PlatformParams& params) {
  switch (logical) {
    case LogicalFormat::Rgba8Unorm:
    case LogicalFormat::Output:
    case LogicalFormat::Rgba8Bits:
      return {logical, "A8R8G8B8", 4, rhi::Format::RGBA8, "unorm8", "A8R8G8B8 texture", "P1"};
    case LogicalFormat::Rg16Unorm:
      // P1: no two-channel 16-bit surface; P2: pack into ARGB8, read as Y16_X16.
      return {logical, "A8R8G8B8 (packed16x2: X16 in A,R; Y16 in G,B)", 4, rhi::Format::RGBA8,
              "X16 = round(x * 65535); A = hi/255, R = lo/255 (same for y into G, B); ROP round(c * 255)",
              "Y16_X16 view (remap 0xAAE4): .r = (A*256 + R)/65535, .g = (G*256 + B)/65535; point or Y16_X16 filtering",
              "P1, P2, P3"};
    case LogicalFormat::Rgba16Hdr:
      return {logical, "F_W16Z16Y16X16 (FP16 x4, 64 bpp; cannot share an MRT pass with 32-bpp targets)", 8,
              rhi::Format::RGBA16F, "fp16", "fp16 texture", "P1"};
    case LogicalFormat::R8Unorm:
      return {logical, "B8", 1, rhi::Format::R8, "unorm8", "B8 texture", "P1"};
    case LogicalFormat::R32Float:
      return {logical, "F_X32", 4, rhi::Format::R32F, "fp32", "X32_FLOAT texture", "P1"};
    case LogicalFormat::Depth24Stencil8:
      return {logical, "Z24S8, read as A8R8G8B8 with remap 0xAA93 (BARG)", 4, rhi::Format::D24S8, "depth test",
              params.texDepth2DPrecise == TexDepth2DPrecise::ExactD24Over16777215
                  ? "texDepth2D_precise: round bytes of .rgb, D24 / 16777215; NEAREST enforced"
                  : "texDepth2D_precise: fp32 DP3 of the bytes with _depth_factor_precise; NEAREST enforced",
              "P4"};
  }
  return {logical};
}

}  // namespace parity::platforms::ps3
