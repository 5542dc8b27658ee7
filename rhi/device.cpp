#include <array>
#include <cstdio>

#include "rhi/backends.h"
#include "rhi/rhi.h"
#include "rhi/validation.h"

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

std::vector<std::string> compiledBackends() { return {"gl", "vk"}; }

std::unique_ptr<Device> createDevice(const DeviceDesc& desc, std::string* whyNot) {
  std::string reason;
  std::unique_ptr<Device> device;
  if (desc.backend == "gl") {
    device = createGlDevice(desc, &reason);
  } else if (desc.backend == "vk") {
    device = createVkDevice(desc, &reason);
  } else {
    reason = "unknown backend '" + desc.backend + "' (known: gl, vk)";
  }
  if (!device) {
    if (whyNot) *whyNot = reason;
    return nullptr;
  }
  if (!desc.validation) return device;
  ValidationCallback onError = desc.onValidationError;
  if (!onError)
    onError = [](const std::string& id, const std::string& message) {
      std::fprintf(stderr, "parity: rhi validation %s: %s\n", id.c_str(), message.c_str());
    };
  return wrapWithValidation(std::move(device), std::move(onError));
}

}  // namespace parity::rhi
