#include "harness/cli/explain_capabilities.h"

#include <cstdio>
#include <memory>
#include <vector>

#include "platforms/common/capabilities.h"
#include "techniques/technique.h"

namespace parity::harness {

namespace {

// What the technique takes on the platform, with the capabilities the platform publishes over a
// host that has everything (the host's own limits are the backend's, not the console's).
std::vector<techniques::PortPath> portPaths(platforms::PlatformId platform, const std::string& technique) {
  std::unique_ptr<techniques::Technique> t = techniques::createTechnique(technique);
  if (!t) return {};
  return t->portPaths(platforms::publishedCapabilities(platform, rhi::Capabilities{}));
}


std::string formatName(rhi::Format f) { return f == rhi::Format::Undefined ? "-" : rhi::formatInfo(f).name; }

}  // namespace

void printCapabilities(platforms::PlatformId platform, const std::string& technique) {
  const std::vector<techniques::PortPath> paths = portPaths(platform, technique);
  std::printf("\nport paths (what a port runs where the platform lacks a capability):\n");
  if (paths.empty()) std::printf("  none: the technique runs as its paper does\n");
  for (const techniques::PortPath& p : paths) std::printf("  %s\n", techniques::describePortPath(p, platform).c_str());
  const platforms::PlatformCapabilities& caps = platforms::platformCapabilities(platform);
  std::printf("\ncapabilities (a draw or dispatch that needs more raises the capability's E_CAP_ code):\n");
  for (const platforms::CapabilityRow& row : caps.rows)
    std::printf("  %-24s %-16s %s\n", std::string(platforms::capabilityName(row.capability)).c_str(), platforms::rowValue(row).c_str(),
                std::string(row.source).c_str());
  if (caps.formats.empty()) return;
  std::printf("  formats (render, blend, filter, vertex fetch, multisample; n none, o optional, y guaranteed):\n");
  auto c = [](platforms::Support s) { return s == platforms::Support::None ? 'n' : s == platforms::Support::Optional ? 'o' : 'y'; };
  for (const platforms::FormatRow& f : caps.formats)
    std::printf("    %-22s %-16s %c %c %c %c %c  %s\n", std::string(f.console).c_str(), formatName(f.host).c_str(),
                c(f.render), c(f.blend), c(f.filter), c(f.vertexFetch), c(f.multisample), std::string(f.source).c_str());
}

nlohmann::json capabilitiesJson(platforms::PlatformId platform, const std::string& technique) {
  nlohmann::json j;
  j["port_paths"] = nlohmann::json::array();
  for (const techniques::PortPath& p : portPaths(platform, technique)) {
    const platforms::CapabilityRow& row = platforms::platformCapabilities(platform).row(p.capability);
    j["port_paths"].push_back({{"pass", p.pass},
                               {"path", p.path},
                               {"capability", platforms::capabilityName(p.capability)},
                               {"platform_value", platforms::rowValue(row)},
                               {"source", row.source}});
  }
  const platforms::PlatformCapabilities& caps = platforms::platformCapabilities(platform);
  j["capabilities"] = nlohmann::json::array();
  for (const platforms::CapabilityRow& row : caps.rows)
    j["capabilities"].push_back({{"capability", platforms::capabilityName(row.capability)},
                                 {"code", platforms::capabilityCode(row.capability)},
                                 {"support", platforms::supportName(row.support)},
                                 {"limit", row.limit},
                                 {"source", row.source}});
  j["formats"] = nlohmann::json::array();
  for (const platforms::FormatRow& f : caps.formats)
    j["formats"].push_back({{"console", f.console},
                            {"host", formatName(f.host)},
                            {"render", platforms::supportName(f.render)},
                            {"blend", platforms::supportName(f.blend)},
                            {"filter", platforms::supportName(f.filter)},
                            {"vertex_fetch", platforms::supportName(f.vertexFetch)},
                            {"multisample", platforms::supportName(f.multisample)},
                            {"source", f.source}});
  return j;
}

}  // namespace parity::harness
