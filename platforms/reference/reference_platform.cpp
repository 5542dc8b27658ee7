#include "platforms/reference/reference_platform.h"

namespace parity::platforms::reference {

TargetMapping mapTarget(LogicalFormat logical, const PlatformParams&) {
  TargetMapping m;
  m.logical = logical;
  m.write = "float, unchanged";
  m.read = "float, unchanged";
  m.source = "none (reference)";
  switch (logical) {
    case LogicalFormat::Rgba8Unorm:
    case LogicalFormat::Rgba16Hdr:
      m.consoleFormat = "RGBA32F";
      m.consoleBytesPerPixel = 16;
      m.hostFormat = rhi::Format::RGBA32F;
      break;
    case LogicalFormat::Rg16Unorm:
      m.consoleFormat = "RG32F";
      m.consoleBytesPerPixel = 8;
      m.hostFormat = rhi::Format::RG32F;
      break;
    case LogicalFormat::Rgba8Bits:
      m.consoleFormat = "RGBA8 (the bits are the data)";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::RGBA8;
      break;
    case LogicalFormat::Output:
      // Planned in the format the harness asks for (planTargets sets it from the target).
      m.consoleFormat = "the requested output format";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::RGBA8;
      break;
    case LogicalFormat::Depth24Stencil8:
      m.consoleFormat = "D32F";
      m.consoleBytesPerPixel = 4;
      m.hostFormat = rhi::Format::D32F;
      break;
  }
  return m;
}

}  // namespace parity::platforms::reference
