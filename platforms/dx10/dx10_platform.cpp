#include "platforms/dx10/dx10_platform.h"

namespace parity::platforms::dx10 {

TargetMapping mapTarget(LogicalFormat logical, const PlatformParams&) {
  switch (logical) {
    case LogicalFormat::Rgba8Unorm:
    case LogicalFormat::Output:
    case LogicalFormat::Rgba8Bits:
      return {logical, "R8G8B8A8_UNORM", 4, rhi::Format::RGBA8, "unorm8", "sample directly", "D1"};
    case LogicalFormat::Rg16Unorm:
      return {logical, "R16G16_UNORM", 4, rhi::Format::RG16_UNORM, "unorm16", "sample directly", "D1"};
    case LogicalFormat::Rgba16Hdr:
      return {logical, "R16G16B16A16_FLOAT", 8, rhi::Format::RGBA16F, "fp16", "sample directly", "D1"};
    case LogicalFormat::R8Unorm:
      return {logical, "R8_UNORM", 1, rhi::Format::R8, "unorm8", "sample directly", "D1"};
    case LogicalFormat::R32Float:
      return {logical, "R32_FLOAT", 4, rhi::Format::R32F, "fp32", "sample directly", "D1"};
    case LogicalFormat::Depth24Stencil8:
      return {logical, "R24G8_TYPELESS (DSV D24_UNORM_S8_UINT, SRV R24_UNORM_X8_TYPELESS)", 4, rhi::Format::D24S8,
              "depth test",
              "copy/resolve to single-sample R24X8, D24 = round(d * 16777215), read D24 / 16777215; never MSAA, "
              "never while bound as DSV",
              "D1"};
  }
  return {logical};
}

}  // namespace parity::platforms::dx10
