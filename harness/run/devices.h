// Devices: a backend with one of its drivers, under a stable name (`parity list`, `parity run
// --devices`): "gl-llvmpipe", "gl-zink" (OpenGL over the Vulkan device), "vk-lavapipe". A bare
// backend name ("gl", "vk") is that backend's default device.
#pragma once

#include <string>

#include "rhi/rhi.h"

namespace parity::harness {

// The device's name from its backend, the adapter asked for ("" for the default) and what the
// device says of itself: GL adapters by their Gallium driver, others by the first word of the
// renderer (Mesa's llvmpipe on Vulkan is lavapipe).
std::string deviceName(const std::string& backend, const std::string& adapter, const rhi::DeviceInfo& info);

// The backend a device name belongs to ("gl-zink" -> "gl", "vk" -> "vk"); "" for neither.
std::string backendOfDevice(const std::string& name);

// Fills desc.backend and desc.adapter for a device name; false with a one-line reason naming the
// devices there are. Vulkan names are resolved by listing the physical devices in this process;
// a name that is no adapter's may be the backend's default device (a vendor's GL driver), which
// is then created in this process to learn its name.
bool resolveDevice(const std::string& name, rhi::DeviceDesc* desc, std::string* error);

}  // namespace parity::harness
