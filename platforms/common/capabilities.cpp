#include "platforms/common/capabilities.h"

#include <algorithm>
#include <cctype>

namespace parity::platforms {

namespace {

struct CapabilityText {
  std::string_view name, code;
};
constexpr std::array<CapabilityText, kCapabilityCount> kText = {{
    {"compute", "E_CAP_COMPUTE"},
    {"compute invocations", "E_CAP_COMPUTE_INVOCATIONS"},
    {"compute workgroup depth", "E_CAP_COMPUTE_WORKGROUP_DEPTH"},
    {"compute shared memory", "E_CAP_COMPUTE_SHARED_MEMORY"},
    {"compute atomics", "E_CAP_COMPUTE_ATOMICS"},
    {"compute storage buffers", "E_CAP_COMPUTE_STORAGE_BUFFERS"},
    {"compute storage images", "E_CAP_COMPUTE_STORAGE_IMAGES"},
    {"colour targets", "E_CAP_COLOR_TARGETS"},
    {"fragment textures", "E_CAP_FRAGMENT_TEXTURES"},
    {"vertex textures", "E_CAP_VERTEX_TEXTURES"},
    {"interpolators", "E_CAP_INTERPOLATORS"},
    {"multisampling", "E_CAP_MULTISAMPLING"},
    {"geometry shaders", "E_CAP_GEOMETRY_SHADERS"},
    {"tessellation shaders", "E_CAP_TESSELLATION_SHADERS"},
    {"graphics storage writes", "E_CAP_GRAPHICS_STORAGE_WRITES"},
    {"EDRAM bytes", "E_CAP_EDRAM_BYTES"},
}};

// The reference: the host, every capability and format as the host device has it.
constexpr CapabilityTable kReferenceRows = [] {
  CapabilityTable t{};
  for (std::size_t i = 0; i < t.size(); ++i)
    t[i] = {Capability(i), Support::Guaranteed, 0, "the host device (the reference has no console limits)"};
  return t;
}();
static_assert(hasOneRowPerCapability(kReferenceRows));

const PlatformCapabilities kReference{PlatformId::Reference, kReferenceRows, {}};

// The console's name of a platform target's format: the first word of its consoleFormat.
std::string_view consoleName(std::string_view consoleFormat) {
  const auto end = std::find_if(consoleFormat.begin(), consoleFormat.end(),
                                [](char c) { return !(std::isalnum(static_cast<unsigned char>(c)) || c == '_'); });
  return consoleFormat.substr(0, std::size_t(end - consoleFormat.begin()));
}

}  // namespace

std::string_view supportName(Support support) {
  switch (support) {
    case Support::None: return "none";
    case Support::Optional: return "optional";
    case Support::Guaranteed: return "guaranteed";
  }
  return "?";
}

std::string_view capabilityName(Capability capability) { return kText[std::size_t(capability)].name; }
std::string_view capabilityCode(Capability capability) { return kText[std::size_t(capability)].code; }

const FormatRow* PlatformCapabilities::format(std::string_view consoleFormat, rhi::Format host) const {
  if (!consoleFormat.empty()) {
    const std::string_view name = consoleName(consoleFormat);
    for (const FormatRow& r : formats)
      if (r.console == name) return &r;
    return nullptr;
  }
  for (const FormatRow& r : formats)
    if (r.host == host && host != rhi::Format::Undefined) return &r;
  return nullptr;
}

const PlatformCapabilities& platformCapabilities(PlatformId platform) {
  switch (platform) {
    case PlatformId::X360: return x360::capabilities();
    case PlatformId::Ps3: return ps3::capabilities();
    case PlatformId::Dx10: return dx10::capabilities();
    case PlatformId::Reference: break;
  }
  return kReference;
}

rhi::Capabilities publishedCapabilities(PlatformId platform, const rhi::Capabilities& host) {
  const PlatformCapabilities& caps = platformCapabilities(platform);
  rhi::Capabilities out = host;
  out.compute = host.compute && caps.row(Capability::Compute).support == Support::Guaranteed;
  const CapabilityRow& samples = caps.row(Capability::Multisampling);
  if (samples.support != Support::Guaranteed)
    out.maxSamples = 1;
  else if (samples.limit != 0)
    out.maxSamples = std::min(out.maxSamples, samples.limit);
  return out;
}

std::string rowValue(const CapabilityRow& row) {
  if (row.support == Support::None) return "none";
  const std::string v = row.limit != 0 ? std::to_string(row.limit) : isLimit(row.capability) ? "no limit" : "yes";
  return row.support == Support::Optional ? v + " (optional)" : v;
}

std::string describeRow(PlatformId platform, const CapabilityRow& row) {
  return rowValue(row) + " on " + std::string(platformName(platform)) + " (" + std::string(row.source) + ")";
}

}  // namespace parity::platforms
