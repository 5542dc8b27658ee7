#include "platforms/common/platform.h"

namespace parity::platforms {

std::string_view platformName(PlatformId id) {
  switch (id) {
    case PlatformId::Reference: return "reference";
    case PlatformId::Dx10: return "dx10";
    case PlatformId::Ps3: return "ps3";
    case PlatformId::X360: return "x360";
  }
  return "?";
}

std::optional<PlatformId> platformFromName(std::string_view name) {
  for (PlatformId id : {PlatformId::Reference, PlatformId::Dx10, PlatformId::Ps3, PlatformId::X360})
    if (platformName(id) == name) return id;
  return std::nullopt;
}

std::string_view logicalFormatName(LogicalFormat format) {
  switch (format) {
    case LogicalFormat::Rgba8Unorm: return "rgba8_unorm";
    case LogicalFormat::Rg16Unorm: return "rg16_unorm";
    case LogicalFormat::Rgba16Hdr: return "rgba16_hdr";
    case LogicalFormat::Depth24Stencil8: return "depth24_stencil8";
    case LogicalFormat::Output: return "output";
    case LogicalFormat::Rgba8Bits: return "rgba8_bits";
    case LogicalFormat::R8Unorm: return "r8_unorm";
    case LogicalFormat::R32Float: return "r32_float";
  }
  return "?";
}

std::string_view filterName(Filter filter) {
  switch (filter) {
    case Filter::Nearest: return "nearest";
    case Filter::Linear: return "linear";
    case Filter::Anisotropic: return "anisotropic";
  }
  return "?";
}

}  // namespace parity::platforms
