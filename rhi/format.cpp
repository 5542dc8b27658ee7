// The format table: names, size classes and kinds. Part of the portable core, so that every
// backend and tool can use it without linking the device factory.
#include <array>
#include <cstring>

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
    {"D16", 2, 1, FormatKind::Depth},
    {"RG8_UINT", 2, 2, FormatKind::Uint},
    {"RG8_SNORM", 2, 2, FormatKind::Snorm},
    {"R16_SNORM", 2, 1, FormatKind::Snorm},
    {"RGBA8_SNORM", 4, 4, FormatKind::Snorm},
    {"RGBA16_SNORM", 8, 4, FormatKind::Snorm},
    {"B10G11R11_UFLOAT", 4, 3, FormatKind::Float},
    {"R32_SINT", 4, 1, FormatKind::Sint},
    {"RGBA32_UINT", 16, 4, FormatKind::Uint},
    {"RGBA32_SINT", 16, 4, FormatKind::Sint},
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

std::vector<uint8_t> unorm16DepthToFloat(const std::vector<uint8_t>& texels) {
  std::vector<uint8_t> out(texels.size() * 2);
  for (size_t i = 0; i + 1 < texels.size(); i += 2) {
    uint16_t q;
    std::memcpy(&q, texels.data() + i, 2);
    const float d = static_cast<float>(static_cast<double>(q) / 65535.0);
    std::memcpy(out.data() + i * 2, &d, 4);
  }
  return out;
}

}  // namespace parity::rhi
