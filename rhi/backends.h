// The one place that knows which backends exist. Each factory lives in its backend folder
// (rhi/gl/gl_device.cpp, rhi/vulkan/vk_device.cpp); createDevice() in rhi/device.cpp picks one
// by name.
#pragma once

#include <memory>
#include <string>

#include "rhi/rhi.h"

namespace parity::rhi {

std::unique_ptr<Device> createGlDevice(const DeviceDesc& desc, std::string* whyNot);
std::unique_ptr<Device> createVkDevice(const DeviceDesc& desc, std::string* whyNot);

}  // namespace parity::rhi
