// Vulkan backend: passes (dynamic rendering), draws, dispatches, resource bindings, push
// constants and timestamps.
//
// State is kept on the CPU and applied in full at every draw and dispatch (pipeline, dynamic
// state, vertex buffers, a freshly written descriptor set, push constants). That costs a little
// recording time and makes every command independent of what was recorded before it, including
// across submits (a new command buffer starts with no state).
#include <algorithm>
#include <array>
#include <cstring>

#include "rhi/vulkan/vk_device.h"

namespace parity::rhi::vulkan {

namespace {

uint32_t mipSize(uint32_t size, uint32_t mip) { return std::max(1u, size >> mip); }

VkAttachmentLoadOp toVk(LoadOp op) {
  switch (op) {
    case LoadOp::Clear: return VK_ATTACHMENT_LOAD_OP_CLEAR;
    case LoadOp::Load: return VK_ATTACHMENT_LOAD_OP_LOAD;
    case LoadOp::DontCare: return VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  }
  return VK_ATTACHMENT_LOAD_OP_CLEAR;
}

constexpr uint32_t kSetsPerPool = 256;

}  // namespace

// ---------------------------------------------------------------------------------------------
// Passes
// ---------------------------------------------------------------------------------------------
void VulkanDevice::beginPass(const PassDesc& desc) {
  if (inPass_) endPass();
  std::array<VkRenderingAttachmentInfo, kMaxColorTargets> colors{};
  uint32_t colorCount = 0;
  uint32_t width = UINT32_MAX, height = UINT32_MAX;
  for (uint32_t i = 0; i < kMaxColorTargets; ++i) {
    const ColorAttachment& ca = desc.colors[i];
    VkRenderingAttachmentInfo& a = colors[i];
    a.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
    TextureObject* t = textures_.get(ca.texture);
    if (!t) continue;  // an unused slot: imageView stays null
    colorCount = i + 1;
    a.imageView = attachmentView(*t, ca.layer, ca.mip);
    a.imageLayout = VK_IMAGE_LAYOUT_GENERAL;
    a.loadOp = toVk(ca.load);
    a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    const bool integer = isIntegerFormat(t->desc.format);
    for (int c = 0; c < 4; ++c) {
      if (formatInfo(t->desc.format).kind == FormatKind::Sint)
        a.clearValue.color.int32[c] = static_cast<int32_t>(ca.clearColor[c]);
      else if (integer)
        a.clearValue.color.uint32[c] = static_cast<uint32_t>(std::max(0.0f, ca.clearColor[c]));
      else
        a.clearValue.color.float32[c] = ca.clearColor[c];
    }
    width = std::min(width, mipSize(t->desc.width, ca.mip));
    height = std::min(height, mipSize(t->desc.height, ca.mip));
    if (TextureObject* r = textures_.get(ca.resolveTarget)) {
      a.resolveImageView = attachmentView(*r, 0, 0);
      a.resolveImageLayout = VK_IMAGE_LAYOUT_GENERAL;
      a.resolveMode = integer ? VK_RESOLVE_MODE_SAMPLE_ZERO_BIT : VK_RESOLVE_MODE_AVERAGE_BIT;
    }
  }

  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  VkRenderingAttachmentInfo stencil{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  bool hasDepth = false, hasStencilAttachment = false;
  if (TextureObject* t = textures_.get(desc.depthStencil.texture)) {
    const DepthStencilAttachment& da = desc.depthStencil;
    depth.imageView = attachmentView(*t, da.layer, 0);
    depth.imageLayout = VK_IMAGE_LAYOUT_GENERAL;
    depth.loadOp = toVk(da.load);
    depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depth.clearValue.depthStencil = {da.clearDepth, da.clearStencil};
    hasDepth = true;
    if (hasStencil(t->desc.format)) {
      stencil = depth;
      hasStencilAttachment = true;
    }
    width = std::min(width, t->desc.width);
    height = std::min(height, t->desc.height);
  }
  if (width == UINT32_MAX) width = height = 1;  // no attachment at all

  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, {width, height}};
  ri.layerCount = 1;
  ri.colorAttachmentCount = colorCount;
  ri.pColorAttachments = colors.data();
  ri.pDepthAttachment = hasDepth ? &depth : nullptr;
  ri.pStencilAttachment = hasStencilAttachment ? &stencil : nullptr;
  vkCmdBeginRendering(mainCmd_, &ri);

  inPass_ = true;
  passWidth_ = width;
  passHeight_ = height;
  pipeline_ = {};
  viewport_ = {};
  scissor_ = {0, 0, width, height};
}

void VulkanDevice::endPass() {
  if (!inPass_) return;
  vkCmdEndRendering(mainCmd_);  // also resolves MSAA attachments that have a resolve target
  globalBarrier(mainCmd_);
  inPass_ = false;
  if (timestampResetPending_) recordPendingTimestampReset();
}

// ---------------------------------------------------------------------------------------------
// Draw state
// ---------------------------------------------------------------------------------------------
void VulkanDevice::setPipeline(PipelineHandle h) {
  pipeline_ = h;
  viewport_ = {};
  scissor_ = {0, 0, passWidth_, passHeight_};
}

void VulkanDevice::setViewport(const Viewport& vp) { viewport_ = vp; }
void VulkanDevice::setScissor(const Rect& r) { scissor_ = r; }
void VulkanDevice::setStencilReference(uint8_t ref) { stencilRef_ = ref; }
void VulkanDevice::setBlendConstant(const std::array<float, 4>& c) { blendConstant_ = c; }

void VulkanDevice::setVertexBuffer(uint32_t slot, BufferHandle h, size_t offset) {
  if (slot < kMaxVertexBuffers) vertexBuffers_[slot] = {h, offset};
}

void VulkanDevice::setIndexBuffer(BufferHandle h, IndexType type, size_t offset) {
  indexBuffer_ = h;
  indexType_ = type;
  indexOffset_ = offset;
}

void VulkanDevice::setComputePipeline(ComputePipelineHandle h) { computePipeline_ = h; }

// Merges: each entry replaces the (binding, element) it names; the others stay bound.
void VulkanDevice::setBindings(std::span<const ResourceBinding> bindings) {
  for (const ResourceBinding& b : bindings)
    if (b.binding < kMaxBindings && b.arrayElement < kMaxArrayElements) bindings_[b.binding][b.arrayElement] = b;
}

void VulkanDevice::pushConstants(const void* data, uint32_t size) {
  std::memcpy(pushData_.data(), data, std::min<size_t>(size, pushData_.size()));
}

bool VulkanDevice::prepareDraw() {
  PipelineObject* p = pipelines_.get(pipeline_);
  if (!p || !inPass_) return false;
  vkCmdBindPipeline(mainCmd_, VK_PIPELINE_BIND_POINT_GRAPHICS, p->pipeline);

  // The RHI's viewport counts y from row 0, which is where Vulkan puts NDC y = -1: no flip.
  VkViewport vp{viewport_.x,
                viewport_.y,
                viewport_.width > 0 ? viewport_.width : float(passWidth_),
                viewport_.height > 0 ? viewport_.height : float(passHeight_),
                viewport_.minDepth,
                viewport_.maxDepth};
  const uint32_t viewports = info_.caps.viewports;  // every index alike, as glViewport sets them
  std::array<VkViewport, kMaxViewports> vps;
  vps.fill(vp);
  vkCmdSetViewport(mainCmd_, 0, viewports, vps.data());

  VkRect2D scissor{{0, 0}, {passWidth_, passHeight_}};
  if (p->desc.raster.scissorEnabled) {  // clamped to the attachment, as Vulkan requires
    int64_t x0 = std::clamp<int64_t>(scissor_.x, 0, passWidth_);
    int64_t y0 = std::clamp<int64_t>(scissor_.y, 0, passHeight_);
    int64_t x1 = std::clamp<int64_t>(int64_t(scissor_.x) + scissor_.width, x0, passWidth_);
    int64_t y1 = std::clamp<int64_t>(int64_t(scissor_.y) + scissor_.height, y0, passHeight_);
    scissor = {{int32_t(x0), int32_t(y0)}, {uint32_t(x1 - x0), uint32_t(y1 - y0)}};
  }
  std::array<VkRect2D, kMaxViewports> scissors;
  scissors.fill(scissor);
  vkCmdSetScissor(mainCmd_, 0, viewports, scissors.data());
  vkCmdSetStencilReference(mainCmd_, VK_STENCIL_FACE_FRONT_AND_BACK, stencilRef_);
  vkCmdSetBlendConstants(mainCmd_, blendConstant_.data());

  const uint32_t attributeCount = std::min<uint32_t>(p->desc.attributeCount, kMaxVertexAttributes);
  for (uint32_t i = 0; i < attributeCount; ++i) {
    uint32_t slot = p->desc.attributes[i].bufferSlot;
    if (slot >= kMaxVertexBuffers) continue;
    if (BufferObject* b = buffers_.get(vertexBuffers_[slot].buffer)) {
      VkDeviceSize offset = vertexBuffers_[slot].offset;
      vkCmdBindVertexBuffers(mainCmd_, slot, 1, &b->buffer, &offset);
    }
  }
  bindResources(VK_PIPELINE_BIND_POINT_GRAPHICS, p->layout);
  return true;
}

void VulkanDevice::draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) {
  if (prepareDraw()) vkCmdDraw(mainCmd_, vertexCount, instanceCount, firstVertex, firstInstance);
}

void VulkanDevice::drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                               uint32_t firstInstance) {
  BufferObject* ib = buffers_.get(indexBuffer_);
  if (!ib || !prepareDraw()) return;
  vkCmdBindIndexBuffer(mainCmd_, ib->buffer, indexOffset_,
                       indexType_ == IndexType::UInt16 ? VK_INDEX_TYPE_UINT16 : VK_INDEX_TYPE_UINT32);
  vkCmdDrawIndexed(mainCmd_, indexCount, instanceCount, firstIndex, vertexOffset, firstInstance);
}

void VulkanDevice::dispatch(uint32_t x, uint32_t y, uint32_t z) {
  ComputePipelineObject* p = computePipelines_.get(computePipeline_);
  if (!p || inPass_) return;
  vkCmdBindPipeline(mainCmd_, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipeline);
  bindResources(VK_PIPELINE_BIND_POINT_COMPUTE, p->layout);
  vkCmdDispatch(mainCmd_, x, y, z);
  globalBarrier(mainCmd_);
}

// ---------------------------------------------------------------------------------------------
// Descriptor sets: one per draw/dispatch from pools that are reset after each submit
// ---------------------------------------------------------------------------------------------
VkDescriptorSet VulkanDevice::allocateDescriptorSet(VkDescriptorSetLayout layout) {
  for (;;) {
    bool fresh = false;
    if (currentPool_ == descriptorPools_.size()) {
      const VkDescriptorPoolSize sizes[] = {
          {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kSetsPerPool * 4},
          {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kSetsPerPool * 4},
          {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, kSetsPerPool * 4},
          {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kSetsPerPool * 2},
          {VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, kSetsPerPool * 2},
          {VK_DESCRIPTOR_TYPE_SAMPLER, kSetsPerPool * 2},
          {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, kSetsPerPool * 2},
          {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, kSetsPerPool * 2},
      };
      VkDescriptorPoolCreateInfo ci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
      ci.maxSets = kSetsPerPool;
      ci.poolSizeCount = static_cast<uint32_t>(std::size(sizes));
      ci.pPoolSizes = sizes;
      VkDescriptorPool pool;
      if (vkCreateDescriptorPool(device_, &ci, nullptr, &pool) != VK_SUCCESS) return VK_NULL_HANDLE;
      descriptorPools_.push_back(pool);
      fresh = true;
    }
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = descriptorPools_[currentPool_];
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &layout;
    VkDescriptorSet set = VK_NULL_HANDLE;
    VkResult r = vkAllocateDescriptorSets(device_, &ai, &set);
    if (r == VK_SUCCESS) return set;
    if (fresh || (r != VK_ERROR_OUT_OF_POOL_MEMORY && r != VK_ERROR_FRAGMENTED_POOL)) return VK_NULL_HANDLE;
    ++currentPool_;
  }
}

void VulkanDevice::bindResources(VkPipelineBindPoint point, const LayoutInfo& layout) {
  if (!layout.bindings.empty()) {
    VkDescriptorSet set = allocateDescriptorSet(layout.setLayout);
    if (!set) return;
    // One write per descriptor (element of a binding); the infos it points to stay put.
    size_t descriptors = 0;
    for (const ShaderResource& r : layout.bindings) descriptors += r.arraySize;
    std::vector<VkDescriptorBufferInfo> bufferInfos(descriptors);
    std::vector<VkDescriptorImageInfo> imageInfos(descriptors);
    std::vector<VkBufferView> texelViews(descriptors);
    std::vector<VkWriteDescriptorSet> writes;
    size_t i = 0;
    for (const ShaderResource& r : layout.bindings)
      for (uint32_t element = 0; element < r.arraySize; ++element, ++i) {
        const std::optional<ResourceBinding>& bound = bindings_[r.binding][element];
        const ResourceBinding* rb = bound && bound->kind == r.kind ? &*bound : nullptr;

        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = set;
        w.dstBinding = r.binding;
        w.dstArrayElement = element;
        w.descriptorCount = 1;
        // Every binding is written: unbound ones get a dummy resource (see vk_texture.cpp).
        switch (r.kind) {
          case BindingKind::UniformBuffer:
          case BindingKind::StorageBuffer: {
            const bool uniform = r.kind == BindingKind::UniformBuffer;
            w.descriptorType = uniform ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            BufferObject* b = rb ? buffers_.get(rb->buffer) : nullptr;
            VkDeviceSize offset = 0, range = 0;
            if (b && rb->offset < b->desc.size) {
              offset = rb->offset;
              range = rb->size ? rb->size : b->desc.size - offset;
            } else {
              b = dummyBuffer();
              if (!b) return;
              range = b->desc.size;
            }
            const VkPhysicalDeviceLimits& l = props_.limits;
            range = std::min<VkDeviceSize>(range, uniform ? l.maxUniformBufferRange : l.maxStorageBufferRange);
            bufferInfos[i] = {b->buffer, offset, range};
            w.pBufferInfo = &bufferInfos[i];
            break;
          }
          case BindingKind::UniformTexelBuffer:
          case BindingKind::StorageTexelBuffer: {
            const bool uniform = r.kind == BindingKind::UniformTexelBuffer;
            w.descriptorType = uniform ? VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
            BufferObject* b = rb ? buffers_.get(rb->buffer) : nullptr;
            VkFormat format = rb ? toVkFormat(rb->texelFormat) : VK_FORMAT_UNDEFINED;
            VkDeviceSize offset = 0, range = 0;
            if (b && rb->offset < b->desc.size && format != VK_FORMAT_UNDEFINED) {
              offset = rb->offset;
              range = rb->size ? rb->size : b->desc.size - offset;
            } else {  // unbound: a view of the dummy buffer, as for the other kinds
              b = dummyBuffer();
              if (!b) return;
              format = r.integer ? VK_FORMAT_R32G32B32A32_UINT : VK_FORMAT_R32G32B32A32_SFLOAT;
              range = b->desc.size;
            }
            texelViews[i] = bufferView(*b, format, offset, range);
            if (!texelViews[i]) return;
            w.pTexelBufferView = &texelViews[i];
            break;
          }
          case BindingKind::SeparateSampler: {
            w.descriptorType = VK_DESCRIPTOR_TYPE_SAMPLER;
            const SamplerObject* s = rb ? samplers_.get(rb->sampler) : nullptr;
            // Null: the default sampler, comparing when a pair uses it as a shadow sampler.
            bool compare = false;
            for (const SeparatePair& pair : layout.separatePairs) compare |= pair.samplerBinding == r.binding && pair.depthCompare;
            imageInfos[i] = {s ? s->sampler : defaultSampler(compare), VK_NULL_HANDLE, VK_IMAGE_LAYOUT_UNDEFINED};
            w.pImageInfo = &imageInfos[i];
            break;
          }
          case BindingKind::SampledTexture:
          case BindingKind::SeparateTexture: {
            const bool separate = r.kind == BindingKind::SeparateTexture;
            w.descriptorType = separate ? VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
            TextureObject* t = rb ? textures_.get(rb->texture) : nullptr;
            if (!t) t = dummyTexture(r);
            if (!t) return;
            const SamplerObject* s = rb && !separate ? samplers_.get(rb->sampler) : nullptr;
            VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
            if (isDepthFormat(t->desc.format))  // usampler on D24S8 reads the stencil aspect
              aspect = (r.integer && hasStencil(t->desc.format)) ? VK_IMAGE_ASPECT_STENCIL_BIT : VK_IMAGE_ASPECT_DEPTH_BIT;
            VkImageViewType type = VK_IMAGE_VIEW_TYPE_2D;
            uint32_t layers = 1;
            if (r.dimensions == 1 && r.arrayed) {
              type = VK_IMAGE_VIEW_TYPE_1D_ARRAY;
              layers = t->desc.layers;
            } else if (r.dimensions != 2) {
              type = r.dimensions == 1 ? VK_IMAGE_VIEW_TYPE_1D : VK_IMAGE_VIEW_TYPE_3D;
            } else if (r.cube) {
              type = VK_IMAGE_VIEW_TYPE_CUBE;
              layers = 6;
            } else if (r.arrayed) {
              type = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
              layers = t->desc.layers;
            }
            imageInfos[i] = {separate ? VK_NULL_HANDLE : s ? s->sampler : defaultSampler(r.depthCompare),
                             imageView(*t, type, aspect, 0, t->desc.mipLevels, 0, layers, true), VK_IMAGE_LAYOUT_GENERAL};
            w.pImageInfo = &imageInfos[i];
            break;
          }
          case BindingKind::StorageTexture: {
            w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
            TextureObject* t = rb ? textures_.get(rb->texture) : nullptr;
            uint32_t mip = rb ? rb->mip : 0;
            if (!t || mip >= t->desc.mipLevels) {
              t = dummyTexture(r);
              mip = 0;
            }
            if (!t) return;
            VkImageViewType type = r.arrayed ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
            if (r.dimensions != 2) type = r.dimensions == 1 ? (r.arrayed ? VK_IMAGE_VIEW_TYPE_1D_ARRAY : VK_IMAGE_VIEW_TYPE_1D) : VK_IMAGE_VIEW_TYPE_3D;
            uint32_t layers = r.arrayed ? t->desc.layers : 1;
            imageInfos[i] = {VK_NULL_HANDLE, imageView(*t, type, VK_IMAGE_ASPECT_COLOR_BIT, mip, 1, 0, layers),
                             VK_IMAGE_LAYOUT_GENERAL};
            w.pImageInfo = &imageInfos[i];
            break;
          }
        }
        writes.push_back(w);
      }
    vkUpdateDescriptorSets(device_, static_cast<uint32_t>(writes.size()), writes.data(), 0, nullptr);
    vkCmdBindDescriptorSets(mainCmd_, point, layout.layout, 0, 1, &set, 0, nullptr);
  }
  if (layout.pushConstantSize)
    vkCmdPushConstants(mainCmd_, layout.layout, layout.stages, 0, (layout.pushConstantSize + 3) & ~3u,
                       pushData_.data());
}

// ---------------------------------------------------------------------------------------------
// Timestamps
// ---------------------------------------------------------------------------------------------
void VulkanDevice::recordPendingTimestampReset() {
  if (queryPool_) vkCmdResetQueryPool(mainCmd_, queryPool_, 0, kMaxTimestamps);
  timestampResetPending_ = false;
}

TimestampId VulkanDevice::writeTimestamp() {
  TimestampId id = timestampCount_++;
  if (queryPool_ && id < kMaxTimestamps)
    vkCmdWriteTimestamp(mainCmd_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queryPool_, id);
  return id;
}

std::optional<uint64_t> VulkanDevice::timestampNs(TimestampId id) {
  if (!queryPool_ || id >= timestampsSubmitted_ || id >= kMaxTimestamps) return std::nullopt;
  uint64_t ticks = 0;
  if (vkGetQueryPoolResults(device_, queryPool_, id, 1, sizeof ticks, &ticks, sizeof ticks, VK_QUERY_RESULT_64_BIT) !=
      VK_SUCCESS)
    return std::nullopt;
  if (timestampValidBits_ < 64) ticks &= (uint64_t(1) << timestampValidBits_) - 1;
  const float period = props_.limits.timestampPeriod;
  if (period == 1.0f) return ticks;
  return static_cast<uint64_t>(static_cast<double>(ticks) * period);
}

void VulkanDevice::resetTimestamps() {
  timestampCount_ = 0;
  timestampsSubmitted_ = 0;
  timestampResetPending_ = true;
  if (!inPass_) recordPendingTimestampReset();
}

}  // namespace parity::rhi::vulkan
