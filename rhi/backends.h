// The one place that knows which backends exist. Each factory lives in its backend folder
// (rhi/gl/gl_device.cpp, rhi/vulkan/vk_device.cpp); createDevice() in rhi/device.cpp picks one
// by name.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "rhi/rhi.h"

namespace parity::rhi {

std::unique_ptr<Device> createGlDevice(const DeviceDesc& desc, std::string* whyNot);
std::unique_ptr<Device> createVkDevice(const DeviceDesc& desc, std::string* whyNot);
// The names of the Vulkan 1.3 physical devices with a graphics and compute queue (rhi::adapterNames).
std::vector<std::string> vkAdapterNames();

// rhi::preloadDriverLibraries for one backend (rhi/gl/gl_driver_libraries.cpp,
// rhi/vulkan/vk_driver_libraries.cpp): the libraries loaded.
std::vector<std::string> preloadGlDriverLibraries();
std::vector<std::string> preloadVkDriverLibraries();

}  // namespace parity::rhi
