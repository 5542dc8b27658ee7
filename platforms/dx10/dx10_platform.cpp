#include "platforms/dx10/dx10_platform.h"

namespace parity::platforms::dx10 {

TargetMapping mapTarget(LogicalFormat logical, const PlatformParams&) {
  TargetMapping m;
  m.logical = logical;
  m.source = "D1";
  switch (logical) {
    case LogicalFormat::Rgba8Unorm:
    case LogicalFormat::Output:
    case LogicalFormat::Rgba8Bits:
      m.consoleFormat = "R8G8B8A8_UNORM";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::RGBA8;
      m.write = "unorm8";
      m.read = "sample directly";
      break;
    case LogicalFormat::Rg16Unorm:
      m.consoleFormat = "R16G16_UNORM";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::RG16_UNORM;
      m.write = "unorm16";
      m.read = "sample directly";
      break;
    case LogicalFormat::Rgba16Hdr:
      m.consoleFormat = "R16G16B16A16_FLOAT";
      m.consoleBytesPerPixel = 8;
      m.hostFormat = rhi::Format::RGBA16F;
      m.write = "fp16";
      m.read = "sample directly";
      break;
    case LogicalFormat::R8Unorm:
      m.consoleFormat = "R8_UNORM";
      m.consoleBytesPerPixel = 1;
      m.hostFormat = rhi::Format::R8;
      m.write = "unorm8";
      m.read = "sample directly";
      break;
    case LogicalFormat::R32Float:
      m.consoleFormat = "R32_FLOAT";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::R32F;
      m.write = "fp32";
      m.read = "sample directly";
      break;
    case LogicalFormat::Depth24Stencil8:
      m.consoleFormat = "R24G8_TYPELESS (DSV D24_UNORM_S8_UINT, SRV R24_UNORM_X8_TYPELESS)";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::D24S8;
      m.write = "depth test";
      m.read = "copy/resolve to single-sample R24X8, D24 = round(d * 16777215), read D24 / 16777215; never MSAA, "
               "never while bound as DSV";
      break;
  }
  return m;
}

}  // namespace parity::platforms::dx10
