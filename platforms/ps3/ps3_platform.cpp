#include "platforms/ps3/ps3_platform.h"

namespace parity::platforms::ps3 {

TargetMapping mapTarget(LogicalFormat logical, const PlatformParams& params) {
  TargetMapping m;
  m.logical = logical;
  switch (logical) {
    case LogicalFormat::Rgba8Unorm:
    case LogicalFormat::Output:
    case LogicalFormat::Rgba8Bits:
      m.consoleFormat = "A8R8G8B8";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::RGBA8;
      m.write = "unorm8";
      m.read = "A8R8G8B8 texture";
      m.source = "P1";
      break;
    case LogicalFormat::Rg16Unorm:
      // P1: no two-channel 16-bit surface; P2: pack into ARGB8, read as Y16_X16.
      m.consoleFormat = "A8R8G8B8 (packed16x2: X16 in A,R; Y16 in G,B)";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::RGBA8;
      m.write = "X16 = round(x * 65535); A = hi/255, R = lo/255 (same for y into G, B); ROP round(c * 255)";
      m.read = "Y16_X16 view (remap 0xAAE4): .r = (A*256 + R)/65535, .g = (G*256 + B)/65535; point or Y16_X16 filtering";
      m.source = "P1, P2, P3";
      break;
    case LogicalFormat::Rgba16Hdr:
      m.consoleFormat = "F_W16Z16Y16X16 (FP16 x4, 64 bpp; cannot share an MRT pass with 32-bpp targets)";
      m.consoleBytesPerPixel = 8;
      m.hostFormat = rhi::Format::RGBA16F;
      m.write = "fp16";
      m.read = "fp16 texture";
      m.source = "P1";
      break;
    case LogicalFormat::R8Unorm:
      m.consoleFormat = "B8";
      m.consoleBytesPerPixel = 1;
      m.hostFormat = rhi::Format::R8;
      m.write = "unorm8";
      m.read = "B8 texture";
      m.source = "P1";
      break;
    case LogicalFormat::R32Float:
      m.consoleFormat = "F_X32";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::R32F;
      m.write = "fp32";
      m.read = "X32_FLOAT texture";
      m.source = "P1";
      break;
    case LogicalFormat::Depth24Stencil8:
      m.consoleFormat = "Z24S8, read as A8R8G8B8 with remap 0xAA93 (BARG)";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::D24S8;
      m.write = "depth test";
      m.read = params.texDepth2DPrecise == TexDepth2DPrecise::ExactD24Over16777215
                   ? "texDepth2D_precise: round bytes of .rgb, D24 / 16777215; NEAREST enforced"
                   : "texDepth2D_precise: fp32 DP3 of the bytes with _depth_factor_precise; NEAREST enforced";
      m.source = "P4";
      break;
  }
  return m;
}

}  // namespace parity::platforms::ps3
