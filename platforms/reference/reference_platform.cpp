#include "platforms/reference/reference_platform.h"

namespace parity::platforms::reference {

TargetMapping mapTarget(LogicalFormat logical, const PlatformParams&) {
  TargetMapping m;
  m.logical = logical;
  m.write = "float, unchanged";
  m.read = "float, unchanged";
  m.source = "none (reference)";
  auto store = [&m](const char* format, uint32_t bytes, rhi::Format host) {
    m.consoleFormat = format;
    m.consoleBytesPerPixel = bytes;
    m.hostFormat = host;
  };
  switch (logical) {
    case LogicalFormat::Rgba8Unorm:
    case LogicalFormat::Rgba16Hdr: store("RGBA32F", 16, rhi::Format::RGBA32F); break;
    case LogicalFormat::Rg16Unorm: store("RG32F", 8, rhi::Format::RG32F); break;
    case LogicalFormat::Rgba8Bits: store("RGBA8 (the bits are the data)", 4, rhi::Format::RGBA8); break;
    // Planned in the format the harness asks for (planTargets sets it from the target).
    case LogicalFormat::Output: store("the requested output format", 4, rhi::Format::RGBA8); break;
    case LogicalFormat::Depth24Stencil8: store("D32F", 4, rhi::Format::D32F); break;
    case LogicalFormat::R8Unorm: store("R8 (8 bits on every platform)", 1, rhi::Format::R8); break;
    case LogicalFormat::R32Float: store("R32F", 4, rhi::Format::R32F); break;
  }
  return m;
}

}  // namespace parity::platforms::reference
