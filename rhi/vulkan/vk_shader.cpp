// Vulkan backend: shader modules, with the reflection that pipeline layouts are built from.
#include "rhi/spirv_lowering.h"
#include "rhi/vulkan/vk_device.h"

#include <utility>

namespace parity::rhi::vulkan {

ShaderHandle VulkanDevice::createShader(const ShaderDesc& desc) {
  if (desc.spirv.empty()) return {};
  if (!desc.arbProgram.empty()) {  // OpenGL's own assembly language: no Vulkan form
    notes_.push_back((desc.label.empty() ? std::string("shader") : desc.label) + ": ARB assembly programs (GL only)");
    return {};
  }
  ShaderObject s;
  std::vector<uint32_t> spirv = desc.spirv;
  if (std::string lowered = lowerForDrivers(spirv); !lowered.empty())
    notes_.push_back((desc.label.empty() ? std::string("shader") : desc.label) + ": " + lowered);
  std::string error;
  if (!reflectSpirv(spirv, desc.stage, &s.reflection, &error)) {
    debugMessage("Vulkan error: shader '" + desc.label + "': " + error);
    return {};
  }
  VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  ci.codeSize = spirv.size() * sizeof(uint32_t);
  ci.pCode = spirv.data();
  if (vkCreateShaderModule(device_, &ci, nullptr, &s.module) != VK_SUCCESS) return {};
  s.stage = desc.stage;
  if (desc.stage == ShaderStage::Vertex && !nativeDoubleVertexFormats_) s.spirv = std::move(spirv);
  s.entryPoint = desc.entryPoint.empty() ? "main" : desc.entryPoint;
  return shaders_.add(std::move(s));
}

void VulkanDevice::destroy(ShaderHandle h) {
  std::optional<ShaderObject> s = shaders_.remove(h);
  if (!s) return;
  // Pipelines keep what they need from a module; it can go at once.
  vkDestroyShaderModule(device_, s->module, nullptr);
}

std::vector<std::string> VulkanDevice::takeNotes() { return std::exchange(notes_, {}); }

}  // namespace parity::rhi::vulkan
