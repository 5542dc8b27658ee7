#include "platforms/x360/x360_platform.h"

#include "platforms/x360/resolve.h"

namespace parity::platforms::x360 {

TargetMapping mapTarget(LogicalFormat logical, const PlatformParams& params) {
  TargetMapping m;
  m.logical = logical;
  switch (logical) {
    case LogicalFormat::Rgba8Unorm:
    case LogicalFormat::Output:
    case LogicalFormat::Rgba8Bits:
      m.consoleFormat = "k_8_8_8_8 in EDRAM, resolved to k_8_8_8_8";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::RGBA8;
      m.write = "unorm8";
      m.read = "sample the resolved texture";
      m.source = "X1, X3";
      break;
    case LogicalFormat::Rg16Unorm: {
      // Two 16-bit channels: k_16_16 is fixed point -32...32 in EDRAM (X2); the path that brings
      // [0, 1] values out of it is a parameter (X3 paths A, B, C).
      DsfPathSpec path = dsfPath(params.dsfResolvePath);
      m.consoleFormat = "k_16_16 (fixed point -32...32) in EDRAM, resolved to k_16_16";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::RG16_SNORM;  // host bits = guest int16 (kGpuK16HostStorage)
      m.write = "path " + std::string(path.name) + ": " + std::string(path.description);
      m.read = path.fetchSigned ? "signed k_16_16 fetch max(s/32767, -1), then (t + 1) / 2"
                                : "unsigned k_16_16 fetch word / 65535";
      m.source = "X2, X3";
      break;
    }
    case LogicalFormat::Rgba16Hdr:
      if (params.hdrFormat == X360HdrFormat::Float7e3) {
        m.consoleFormat = "k_2_10_10_10_FLOAT (7e3 RGB, 2-bit alpha, 32 bpp) in EDRAM";
        m.consoleBytesPerPixel = 4;
        m.hostFormat = rhi::Format::RGBA32F;
        m.write = "float; stored as 7e3 (3-bit exponent, 7-bit mantissa, [0, 31.875], negatives 0), rounded to "
                  "nearest even after each pass";
        m.read = "resolve into k_2_10_10_10_FLOAT (bit copy), fetched as the 7e3 values";
        m.source = "X2";
        break;
      }
      m.consoleFormat = "k_16_16_16_16 (fixed point -32...32, 64 bpp) in EDRAM";
      m.consoleBytesPerPixel = 8;
      // The host has no RGBA16_SNORM/UINT formats: RGBA32F holds s * 2^-15 for the guest int16 s,
      // exact in fp32, and sums of such values stay exact, so additive blending adds int16
      // steps exactly as the EDRAM blender does (see shaders/platforms/x360/targets.glsl).
      m.hostFormat = rhi::Format::RGBA32F;
      m.write = "fixed point -32...32 (s = round-half-away(v * 32767/32), NaN -> 0), host stores s * 2^-15";
      m.read = "resolve into a signed k_16_16_16_16 texture (raw int16 kept), signed fetch with exp_adjust +5: "
               "max(s/32767, -1) * 32";
      m.source = "X2, X4";
      break;
    case LogicalFormat::R8Unorm:
      // No 8-bit colour render-target format (ColorRenderTargetFormat): the red of a 32-bpp surface.
      m.consoleFormat = "k_8_8_8_8 in EDRAM (red written), resolved to k_8";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::R8;
      m.write = "unorm8 into red";
      m.read = "sample the resolved k_8 texture";
      m.source = "X1, X3";
      break;
    case LogicalFormat::R32Float:
      m.consoleFormat = "k_32_FLOAT in EDRAM, resolved to k_32_FLOAT";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::R32F;
      m.write = "fp32";
      m.read = "sample the resolved texture";
      m.source = "X1, X3";
      break;
    case LogicalFormat::Depth24Stencil8:
      m.consoleFormat = "D24S8 in EDRAM (40x16-sample tile halves swapped)";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::D24S8;
      m.write = "depth test";
      m.read = "resolve (raw copy, no conversion), then sample";
      m.source = "X1, X3";
      break;
  }
  return m;
}

}  // namespace parity::platforms::x360
