#include <cstdio>

#include "rhi/backends.h"
#include "rhi/rhi.h"
#include "rhi/validation.h"

namespace parity::rhi {

std::vector<std::string> compiledBackends() { return {"gl", "vk"}; }

std::vector<std::string> preloadDriverLibraries() {
  std::vector<std::string> loaded = preloadGlDriverLibraries();
  for (const std::string& l : preloadVkDriverLibraries()) loaded.push_back(l);
  return loaded;
}

std::vector<std::string> adapterNames(const std::string& backend) {
  // Mesa's software Gallium drivers: llvmpipe, and Zink, OpenGL over Vulkan (lavapipe here; any
  // Vulkan device elsewhere), the layering ANGLE-on-Vulkan and Zink ports ship.
  if (backend == "gl") return {"llvmpipe", "zink"};
  if (backend == "vk") return vkAdapterNames();
  return {};
}

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
