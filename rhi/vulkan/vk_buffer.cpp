// Vulkan backend: buffers (device-local memory, uploads through staging, readback).
#include <cstring>

#include "rhi/vulkan/vk_device.h"

namespace parity::rhi::vulkan {

BufferHandle VulkanDevice::createBuffer(const BufferDesc& desc) {
  if (desc.size == 0) return {};
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  // Rounded up to 4 bytes so that vkCmdFillBuffer zeroes every byte.
  bi.size = (static_cast<VkDeviceSize>(desc.size) + 3) & ~VkDeviceSize(3);
  bi.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  if (desc.usage & BufferUsage_Vertex) bi.usage |= VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
  if (desc.usage & BufferUsage_Index) bi.usage |= VK_BUFFER_USAGE_INDEX_BUFFER_BIT;
  // Uniform and storage buffers may also be bound as texel buffers (rhi.h).
  if (desc.usage & BufferUsage_Uniform)
    bi.usage |= VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
  if (desc.usage & BufferUsage_Storage)
    bi.usage |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;

  BufferObject b;
  if (vkCreateBuffer(device_, &bi, nullptr, &b.buffer) != VK_SUCCESS) return {};
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device_, b.buffer, &req);
  if (!allocateMemory(req, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, &b.memory)) {
    vkDestroyBuffer(device_, b.buffer, nullptr);
    return {};
  }
  vkBindBufferMemory(device_, b.buffer, b.memory, 0);

  VkCommandBuffer cb = initCmd();
  vkCmdFillBuffer(cb, b.buffer, 0, VK_WHOLE_SIZE, 0);
  if (desc.initialData) {
    globalBarrier(cb);
    StagingSlice s = stagingAlloc(desc.size);
    if (s.data) {
      std::memcpy(s.data, desc.initialData, desc.size);
      VkBufferCopy region{s.offset, 0, desc.size};
      vkCmdCopyBuffer(cb, s.buffer, b.buffer, 1, &region);
    }
  }
  globalBarrier(cb);

  b.desc = desc;
  b.desc.initialData = nullptr;
  return buffers_.add(std::move(b));
}

void VulkanDevice::destroy(BufferHandle h) {
  std::optional<BufferObject> b = buffers_.remove(h);
  if (!b) return;
  VkDevice device = device_;
  defer([device, buffer = b->buffer, memory = b->memory, views = b->views] {
    for (const auto& [key, view] : views) vkDestroyBufferView(device, view, nullptr);
    vkDestroyBuffer(device, buffer, nullptr);
    vkFreeMemory(device, memory, nullptr);
  });
}

// A texel buffer view of a range, created once per (format, offset, range) and kept with the
// buffer.
VkBufferView VulkanDevice::bufferView(BufferObject& b, VkFormat format, VkDeviceSize offset, VkDeviceSize range) {
  const BufferViewKey key{format, offset, range};
  for (const auto& [k, view] : b.views)
    if (k == key) return view;
  VkBufferViewCreateInfo ci{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  ci.buffer = b.buffer;
  ci.format = format;
  ci.offset = offset;
  ci.range = range;
  VkBufferView view = VK_NULL_HANDLE;
  if (vkCreateBufferView(device_, &ci, nullptr, &view) != VK_SUCCESS) return VK_NULL_HANDLE;
  b.views.push_back({key, view});
  return view;
}

const BufferDesc* VulkanDevice::describe(BufferHandle h) const {
  const BufferObject* b = buffers_.get(h);
  return b ? &b->desc : nullptr;
}

void VulkanDevice::writeBuffer(BufferHandle h, size_t offset, const void* data, size_t size) {
  BufferObject* b = buffers_.get(h);
  if (!b || size == 0) return;
  StagingSlice s = stagingAlloc(size);
  if (!s.data) return;
  std::memcpy(s.data, data, size);
  VkBufferCopy region{s.offset, offset, size};
  vkCmdCopyBuffer(mainCmd_, s.buffer, b->buffer, 1, &region);
  globalBarrier(mainCmd_);
}

std::vector<uint8_t> VulkanDevice::readBuffer(BufferHandle h, size_t offset, size_t size) {
  BufferObject* b = buffers_.get(h);
  if (!b || size == 0) return {};
  VkBuffer staging;
  VkDeviceMemory memory;
  void* mapped = nullptr;
  if (!createHostBuffer(size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, &staging, &memory, &mapped)) return {};
  // Recorded after all pending work; the global barriers order it after every earlier write.
  VkBufferCopy region{offset, 0, size};
  vkCmdCopyBuffer(mainCmd_, b->buffer, staging, 1, &region);
  globalBarrier(mainCmd_, /*toHost=*/true);
  flushAndWait();
  std::vector<uint8_t> out(size);
  std::memcpy(out.data(), mapped, size);
  vkDestroyBuffer(device_, staging, nullptr);
  vkFreeMemory(device_, memory, nullptr);
  return out;
}

void VulkanDevice::copyBuffer(BufferHandle src, size_t srcOffset, BufferHandle dst, size_t dstOffset, size_t size) {
  BufferObject* s = buffers_.get(src);
  BufferObject* d = buffers_.get(dst);
  if (!s || !d || size == 0) return;
  VkBufferCopy region{srcOffset, dstOffset, size};
  vkCmdCopyBuffer(mainCmd_, s->buffer, d->buffer, 1, &region);
  globalBarrier(mainCmd_);
}

}  // namespace parity::rhi::vulkan
