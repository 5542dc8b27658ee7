#include "platforms/x360/x360_platform.h"

#include "platforms/x360/resolve.h"

namespace parity::platforms::x360 {

TargetMapping mapTarget(LogicalFormat logical, const PlatformParams& params) {
  switch (logical) {
    case LogicalFormat::Rgba8Unorm:
    case LogicalFormat::Output:
    case LogicalFormat::Rgba8Bits:
      return {logical, "k_8_8_8_8 in EDRAM, resolved to k_8_8_8_8", 4, rhi::Format::RGBA8, "unorm8",
              "sample the resolved texture", "X1, X3"};
    case LogicalFormat::Rg16Unorm: {
      // Two 16-bit channels: k_16_16 is fixed point -32...32 in EDRAM (X2); the path that brings
      // [0, 1] values out of it is a parameter (X3 paths A, B, C). Host bits = guest int16
      // (kGpuK16HostStorage).
      DsfPathSpec path = dsfPath(params.dsfResolvePath);
      return {logical, "k_16_16 (fixed point -32...32) in EDRAM, resolved to k_16_16", 4, rhi::Format::RG16_SNORM,
              "path " + std::string(path.name) + ": " + std::string(path.description),
              path.fetchSigned ? "signed k_16_16 fetch max(s/32767, -1), then (t + 1) / 2"
                               : "unsigned k_16_16 fetch word / 65535",
              "X2, X3"};
    }
    case LogicalFormat::Rgba16Hdr:
      if (params.hdrFormat == X360HdrFormat::Float7e3)
        return {logical, "k_2_10_10_10_FLOAT (7e3 RGB, 2-bit alpha, 32 bpp) in EDRAM", 4, rhi::Format::RGBA32F,
                "float; stored as 7e3 (3-bit exponent, 7-bit mantissa, [0, 31.875], negatives 0), rounded to "
                "nearest even after each pass",
                "resolve into k_2_10_10_10_FLOAT (bit copy), fetched as the 7e3 values", "X2"};
      // The host has no RGBA16_SNORM/UINT formats: RGBA32F holds s * 2^-15 for the guest int16 s,
      // exact in fp32, and sums of such values stay exact, so additive blending adds int16
      // steps exactly as the EDRAM blender does (see shaders/platforms/x360/targets.glsl).
      return {logical, "k_16_16_16_16 (fixed point -32...32, 64 bpp) in EDRAM", 8, rhi::Format::RGBA32F,
              "fixed point -32...32 (s = round-half-away(v * 32767/32), NaN -> 0), host stores s * 2^-15",
              "resolve into a signed k_16_16_16_16 texture (raw int16 kept), signed fetch with exp_adjust +5: "
              "max(s/32767, -1) * 32",
              "X2, X4"};
    case LogicalFormat::R8Unorm:
      // No 8-bit colour render-target format (ColorRenderTargetFormat): the red of a 32-bpp surface.
      return {logical, "k_8_8_8_8 in EDRAM (red written), resolved to k_8", 4, rhi::Format::R8, "unorm8 into red",
              "sample the resolved k_8 texture", "X1, X3"};
    case LogicalFormat::R32Float:
      return {logical, "k_32_FLOAT in EDRAM, resolved to k_32_FLOAT", 4, rhi::Format::R32F, "fp32",
              "sample the resolved texture", "X1, X3"};
    case LogicalFormat::Depth24Stencil8:
      return {logical, "D24S8 in EDRAM (40x16-sample tile halves swapped)", 4, rhi::Format::D24S8, "depth test",
              "resolve (raw copy, no conversion), then sample", "X1, X3"};
  }
  return {logical};
}

}  // namespace parity::platforms::x360
