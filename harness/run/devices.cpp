#include "harness/run/devices.h"

#include <algorithm>
#include <cctype>
#include <memory>

namespace parity::harness {

std::string deviceName(const std::string& backend, const std::string& adapter, const rhi::DeviceInfo& info) {
  std::string word = !adapter.empty() && backend == "gl" ? adapter : info.renderer.substr(0, info.renderer.find_first_of(" ("));
  if (word.empty()) word = adapter;
  std::string slug;
  for (char ch : word)
    slug += std::isalnum(static_cast<unsigned char>(ch)) ? static_cast<char>(std::tolower(static_cast<unsigned char>(ch))) : '-';
  if (backend == "vk" && slug == "llvmpipe") slug = "lavapipe";
  return backend + "-" + slug;
}

std::string backendOfDevice(const std::string& name) {
  const std::vector<std::string> backends = rhi::compiledBackends();
  const std::string prefix = name.substr(0, name.find('-'));
  return std::find(backends.begin(), backends.end(), prefix) != backends.end() ? prefix : "";
}

bool resolveDevice(const std::string& name, rhi::DeviceDesc* desc, std::string* error) {
  const std::string backend = backendOfDevice(name);
  std::string known;
  if (!backend.empty()) {
    desc->backend = backend;
    if (name == backend) return true;
    for (const std::string& adapter : rhi::adapterNames(backend)) {
      rhi::DeviceInfo info;
      info.renderer = adapter;
      const std::string candidate = deviceName(backend, adapter, info);
      if (candidate == name) {
        desc->adapter = adapter;
        return true;
      }
      known += (known.empty() ? "" : ", ") + candidate;
    }
    // The backend's default device where it is none of the adapters (a vendor's GL driver, which
    // is no Mesa Gallium driver): named from what it says of itself, as `parity list` names it.
    rhi::DeviceDesc probe;
    probe.backend = backend;
    probe.validation = false;
    std::string why;
    if (std::unique_ptr<rhi::Device> device = rhi::createDevice(probe, &why)) {
      const std::string candidate = deviceName(backend, "", device->info());
      if (candidate == name) {
        desc->adapter.clear();
        return true;
      }
      if (known.find(candidate) == std::string::npos) known += (known.empty() ? "" : ", ") + candidate;
    }
  }
  *error = "unknown device '" + name + "' (" + (known.empty() ? std::string("devices are named BACKEND-DRIVER, e.g. gl-zink") : "here: " + known) +
           "; `parity list` lists them)";
  return false;
}

}  // namespace parity::harness
