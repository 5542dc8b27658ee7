// The format table: names, size classes and kinds. Part of the portable core, so that every
// backend and tool can use it without linking the device factory.
#include <array>

#include "rhi/rhi.h"

namespace parity::rhi {

namespace {
constexpr std::array<FormatInfo, static_cast<size_t>(Format::Count)> kFormats{{
    {"Undefined", 0, 0, FormatKind::Unorm},
    {"RGBA8", 4, 4, FormatKind::Unorm},
    {"RGBA8_SRGB", 4, 4, FormatKind::Srgb},
    {"RGBA8_UINT", 4, 4, FormatKind::Uint},
    {"R8", 1, 1, FormatKind::Unorm},
    {"RG16_UNORM", 4, 2, FormatKind::Unorm},
    {"RG16_SNORM", 4, 2, FormatKind::Snorm},
    {"RG16_FLOAT", 4, 2, FormatKind::Float},
    {"RG16_UINT", 4, 2, FormatKind::Uint},
    {"R32_UINT", 4, 1, FormatKind::Uint},
    {"R32F", 4, 1, FormatKind::Float},
    {"RGBA16F", 8, 4, FormatKind::Float},
    {"RG32F", 8, 2, FormatKind::Float},
    {"RGBA32F", 16, 4, FormatKind::Float},
    {"D24S8", 4, 1, FormatKind::DepthStencil},
    {"D32F", 4, 1, FormatKind::Depth},
}};
}  // namespace

const FormatInfo& formatInfo(Format f) {
  size_t i = static_cast<size_t>(f);
  return kFormats[i < kFormats.size() ? i : 0];
}

std::optional<Format> formatFromName(std::string_view name) {
  for (size_t i = 1; i < kFormats.size(); ++i)
    if (name == kFormats[i].name) return static_cast<Format>(i);
  return std::nullopt;
}

}  // namespace parity::rhi
