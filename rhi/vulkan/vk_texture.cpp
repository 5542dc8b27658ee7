// Vulkan backend: the format table, textures, texture views, samplers, texture transfers, and the
// dummy resources that fill unbound descriptor slots.
#include <algorithm>
#include <cstring>

#include "rhi/vulkan/vk_device.h"

namespace parity::rhi::vulkan {

// ---------------------------------------------------------------------------------------------
// Formats: the one table mapping parity formats to Vulkan
// ---------------------------------------------------------------------------------------------
VkFormat toVkFormat(Format f) {
  switch (f) {
    case Format::RGBA8: return VK_FORMAT_R8G8B8A8_UNORM;
    case Format::RGBA8_SRGB: return VK_FORMAT_R8G8B8A8_SRGB;
    case Format::RGBA8_UINT: return VK_FORMAT_R8G8B8A8_UINT;
    case Format::R8: return VK_FORMAT_R8_UNORM;
    case Format::RG16_UNORM: return VK_FORMAT_R16G16_UNORM;
    case Format::RG16_SNORM: return VK_FORMAT_R16G16_SNORM;
    case Format::RG16_FLOAT: return VK_FORMAT_R16G16_SFLOAT;
    case Format::RG16_UINT: return VK_FORMAT_R16G16_UINT;
    case Format::R32_UINT: return VK_FORMAT_R32_UINT;
    case Format::R32F: return VK_FORMAT_R32_SFLOAT;
    case Format::RGBA16F: return VK_FORMAT_R16G16B16A16_SFLOAT;
    case Format::RG32F: return VK_FORMAT_R32G32_SFLOAT;
    case Format::RGBA32F: return VK_FORMAT_R32G32B32A32_SFLOAT;
    case Format::D24S8: return VK_FORMAT_D24_UNORM_S8_UINT;
    case Format::D32F: return VK_FORMAT_D32_SFLOAT;
    case Format::D16: return VK_FORMAT_D16_UNORM;
    case Format::RG8_UINT: return VK_FORMAT_R8G8_UINT;
    case Format::RG8_SNORM: return VK_FORMAT_R8G8_SNORM;
    case Format::R16_SNORM: return VK_FORMAT_R16_SNORM;
    case Format::RGBA8_SNORM: return VK_FORMAT_R8G8B8A8_SNORM;
    case Format::RGBA16_SNORM: return VK_FORMAT_R16G16B16A16_SNORM;
    case Format::B10G11R11_UFLOAT: return VK_FORMAT_B10G11R11_UFLOAT_PACK32;
    case Format::R32_SINT: return VK_FORMAT_R32_SINT;
    case Format::RGBA32_UINT: return VK_FORMAT_R32G32B32A32_UINT;
    case Format::RGBA32_SINT: return VK_FORMAT_R32G32B32A32_SINT;
    default: return VK_FORMAT_UNDEFINED;
  }
}

VkImageAspectFlags formatAspects(Format f) {
  if (f == Format::D24S8) return VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT;
  if (f == Format::D32F || f == Format::D16) return VK_IMAGE_ASPECT_DEPTH_BIT;
  return VK_IMAGE_ASPECT_COLOR_BIT;
}

VkFormat toVkVertexFormat(VertexFormat f) {
  switch (f) {
    case VertexFormat::Float: return VK_FORMAT_R32_SFLOAT;
    case VertexFormat::Float2: return VK_FORMAT_R32G32_SFLOAT;
    case VertexFormat::Float3: return VK_FORMAT_R32G32B32_SFLOAT;
    case VertexFormat::Float4: return VK_FORMAT_R32G32B32A32_SFLOAT;
    case VertexFormat::UByte4Norm: return VK_FORMAT_R8G8B8A8_UNORM;
    case VertexFormat::UInt: return VK_FORMAT_R32_UINT;
    case VertexFormat::UInt2: return VK_FORMAT_R32G32_UINT;
    case VertexFormat::UInt4: return VK_FORMAT_R32G32B32A32_UINT;
    case VertexFormat::UInt3: return VK_FORMAT_R32G32B32_UINT;
    case VertexFormat::Int: return VK_FORMAT_R32_SINT;
    case VertexFormat::Int2: return VK_FORMAT_R32G32_SINT;
    case VertexFormat::Int3: return VK_FORMAT_R32G32B32_SINT;
    case VertexFormat::Int4: return VK_FORMAT_R32G32B32A32_SINT;
    case VertexFormat::Double: return VK_FORMAT_R64_SFLOAT;
    case VertexFormat::Double2: return VK_FORMAT_R64G64_SFLOAT;
    case VertexFormat::Double3: return VK_FORMAT_R64G64B64_SFLOAT;
    case VertexFormat::Double4: return VK_FORMAT_R64G64B64A64_SFLOAT;
  }
  return VK_FORMAT_UNDEFINED;
}

namespace {

// Image usages a format supports in optimal tiling.
VkImageUsageFlags usageSupported(VkFormatFeatureFlags features) {
  VkImageUsageFlags u = 0;
  if (features & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT) u |= VK_IMAGE_USAGE_SAMPLED_BIT;
  if (features & VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT) u |= VK_IMAGE_USAGE_STORAGE_BIT;
  if (features & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT) u |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
  if (features & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT) u |= VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
  if (features & VK_FORMAT_FEATURE_TRANSFER_SRC_BIT) u |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  if (features & VK_FORMAT_FEATURE_TRANSFER_DST_BIT) u |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  return u;
}

VkFilter toVk(Filter f) { return f == Filter::Linear ? VK_FILTER_LINEAR : VK_FILTER_NEAREST; }

VkBorderColor toVk(BorderColor c) {
  switch (c) {
    case BorderColor::FloatTransparentBlack: return VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK;
    case BorderColor::FloatOpaqueBlack: return VK_BORDER_COLOR_FLOAT_OPAQUE_BLACK;
    case BorderColor::FloatOpaqueWhite: return VK_BORDER_COLOR_FLOAT_OPAQUE_WHITE;
    case BorderColor::IntTransparentBlack: return VK_BORDER_COLOR_INT_TRANSPARENT_BLACK;
    case BorderColor::IntOpaqueBlack: return VK_BORDER_COLOR_INT_OPAQUE_BLACK;
    case BorderColor::IntOpaqueWhite: return VK_BORDER_COLOR_INT_OPAQUE_WHITE;
  }
  return VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK;
}

VkSamplerAddressMode toVk(AddressMode m) {
  switch (m) {
    case AddressMode::ClampToEdge: return VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    case AddressMode::Repeat: return VK_SAMPLER_ADDRESS_MODE_REPEAT;
    case AddressMode::MirroredRepeat: return VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT;
    case AddressMode::ClampToBorder: return VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER;
  }
  return VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
}

VkCompareOp toVkCompare(CompareOp op) {
  switch (op) {
    case CompareOp::Always: return VK_COMPARE_OP_ALWAYS;
    case CompareOp::Never: return VK_COMPARE_OP_NEVER;
    case CompareOp::Less: return VK_COMPARE_OP_LESS;
    case CompareOp::LessEqual: return VK_COMPARE_OP_LESS_OR_EQUAL;
    case CompareOp::Equal: return VK_COMPARE_OP_EQUAL;
    case CompareOp::NotEqual: return VK_COMPARE_OP_NOT_EQUAL;
    case CompareOp::Greater: return VK_COMPARE_OP_GREATER;
    case CompareOp::GreaterEqual: return VK_COMPARE_OP_GREATER_OR_EQUAL;
  }
  return VK_COMPARE_OP_ALWAYS;
}

uint32_t mipSize(uint32_t size, uint32_t mip) { return std::max(1u, size >> mip); }

// Where a copy finds layer `layer` of a texture: an array layer, or for Tex3D the slice at z.
void addressLayer(const TextureObject& t, uint32_t layer, VkImageSubresourceLayers* sub, VkOffset3D* offset) {
  const bool slice = t.desc.type == TextureType::Tex3D;
  sub->baseArrayLayer = slice ? 0 : t.baseLayer + layer;
  *offset = {0, 0, slice ? static_cast<int32_t>(layer) : 0};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Textures
// ---------------------------------------------------------------------------------------------
TextureHandle VulkanDevice::createTexture(const TextureDesc& desc) {
  VkFormat format = toVkFormat(desc.format);
  if (format == VK_FORMAT_UNDEFINED || desc.width == 0 || desc.height == 0) return {};
  const bool depth = isDepthFormat(desc.format);
  const VkFormatFeatureFlags features = formatFeatures(format);

  VkImageUsageFlags usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  if ((desc.usage & TextureUsage_Sampled) || (features & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT))
    usage |= VK_IMAGE_USAGE_SAMPLED_BIT;
  if (desc.usage & TextureUsage_RenderTarget)
    usage |= depth ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
  if (desc.usage & TextureUsage_Storage) usage |= VK_IMAGE_USAGE_STORAGE_BIT;

  VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  if (desc.type == TextureType::Cube) ci.flags |= VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT;
  if (!depth) {
    // Views may reinterpret colour textures in any format of the same size class.
    ci.flags |= VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT;
    // A usage the texture's own format lacks (storage on RGBA8_SRGB, say) is then only legal
    // through views of formats that have it.
    if ((usage & usageSupported(features)) != usage) ci.flags |= VK_IMAGE_CREATE_EXTENDED_USAGE_BIT;
  }
  ci.imageType = desc.type == TextureType::Tex1D   ? VK_IMAGE_TYPE_1D
                 : desc.type == TextureType::Tex3D ? VK_IMAGE_TYPE_3D
                                                   : VK_IMAGE_TYPE_2D;
  // A slice of a 3D texture is a colour attachment through a 2D view of it.
  if (desc.type == TextureType::Tex3D) ci.flags |= VK_IMAGE_CREATE_2D_ARRAY_COMPATIBLE_BIT;
  ci.format = format;
  ci.extent = {desc.width, desc.height, desc.type == TextureType::Tex3D ? desc.depth : 1};
  ci.mipLevels = std::max(1u, desc.mipLevels);
  ci.arrayLayers = desc.type == TextureType::Cube ? 6 : std::max(1u, desc.layers);
  ci.samples = desc.samples == 4 ? VK_SAMPLE_COUNT_4_BIT : VK_SAMPLE_COUNT_1_BIT;
  ci.tiling = VK_IMAGE_TILING_OPTIMAL;
  ci.usage = usage;
  ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;

  TextureObject t;
  if (vkCreateImage(device_, &ci, nullptr, &t.image) != VK_SUCCESS) return {};
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(device_, t.image, &req);
  if (!allocateMemory(req, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, &t.memory)) {
    vkDestroyImage(device_, t.image, nullptr);
    return {};
  }
  vkBindImageMemory(device_, t.image, t.memory, 0);
  t.desc = desc;
  t.desc.initialData = nullptr;
  t.desc.layers = ci.arrayLayers;
  t.desc.mipLevels = ci.mipLevels;
  t.usage = usage;
  t.format = format;

  // The one layout transition of this image's life: to GENERAL (see vk_device.h).
  VkCommandBuffer cb = initCmd();
  VkImageMemoryBarrier2 ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
  ib.srcStageMask = VK_PIPELINE_STAGE_2_NONE;
  ib.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  ib.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
  ib.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  ib.newLayout = VK_IMAGE_LAYOUT_GENERAL;
  ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  ib.image = t.image;
  ib.subresourceRange = {formatAspects(desc.format), 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.imageMemoryBarrierCount = 1;
  dep.pImageMemoryBarriers = &ib;
  vkCmdPipelineBarrier2(cb, &dep);

  // Every texture starts zeroed (deterministic across backends), then takes its initial data.
  VkImageSubresourceRange all = ib.subresourceRange;
  if (depth) {
    VkClearDepthStencilValue zero{0.0f, 0};
    vkCmdClearDepthStencilImage(cb, t.image, VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &all);
  } else {
    VkClearColorValue zero{};
    vkCmdClearColorImage(cb, t.image, VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &all);
  }
  if (desc.initialData && ci.samples == VK_SAMPLE_COUNT_1_BIT) {
    globalBarrier(cb);
    const size_t layerBytes = size_t(desc.width) * desc.height * formatInfo(desc.format).bytesPerTexel;
    const uint32_t layers = desc.type == TextureType::Tex3D ? desc.depth : ci.arrayLayers;
    for (uint32_t layer = 0; layer < layers; ++layer)
      recordTextureUpload(cb, t, layer, 0, static_cast<const uint8_t*>(desc.initialData) + layer * layerBytes);
  }
  globalBarrier(cb);
  return textures_.add(std::move(t));
}

// TextureViewDesc::swizzle as VkImageViewCreateInfo::components.
static VkComponentMapping componentMapping(const ComponentMapping& m) {
  auto source = [](Swizzle s) {
    switch (s) {
      case Swizzle::Zero: return VK_COMPONENT_SWIZZLE_ZERO;
      case Swizzle::One: return VK_COMPONENT_SWIZZLE_ONE;
      case Swizzle::Red: return VK_COMPONENT_SWIZZLE_R;
      case Swizzle::Green: return VK_COMPONENT_SWIZZLE_G;
      case Swizzle::Blue: return VK_COMPONENT_SWIZZLE_B;
      case Swizzle::Alpha: return VK_COMPONENT_SWIZZLE_A;
      case Swizzle::Identity: break;
    }
    return VK_COMPONENT_SWIZZLE_IDENTITY;
  };
  if (m.isIdentity()) return {};
  return {source(m.r), source(m.g), source(m.b), source(m.a)};
}

TextureHandle VulkanDevice::createTextureView(const TextureViewDesc& desc) {
  const TextureObject* p = textures_.get(desc.parent);
  if (!p) return {};
  const TextureDesc& pd = p->desc;
  if (desc.baseLayer >= pd.layers || desc.baseMip >= pd.mipLevels) return {};
  TextureObject v;
  v.isView = true;
  v.image = p->image;
  v.usage = p->usage;
  v.baseLayer = p->baseLayer + desc.baseLayer;
  v.baseMip = p->baseMip + desc.baseMip;
  v.desc = pd;
  v.desc.format = desc.format == Format::Undefined ? pd.format : desc.format;
  v.desc.layers = desc.layerCount ? desc.layerCount : pd.layers - desc.baseLayer;
  v.desc.mipLevels = desc.mipCount ? desc.mipCount : pd.mipLevels - desc.baseMip;
  v.desc.width = mipSize(pd.width, desc.baseMip);
  v.desc.height = mipSize(pd.height, desc.baseMip);
  if (v.desc.layers != pd.layers && pd.type != TextureType::Tex1D)
    v.desc.type = v.desc.layers == 1 ? TextureType::Tex2D : TextureType::Tex2DArray;
  v.desc.label = desc.label;
  v.format = toVkFormat(v.desc.format);
  if (v.format == VK_FORMAT_UNDEFINED) return {};
  v.components = componentMapping(desc.swizzle);
  return textures_.add(std::move(v));
}

void VulkanDevice::destroy(TextureHandle h) {
  std::optional<TextureObject> t = textures_.remove(h);
  if (!t) return;
  VkDevice device = device_;
  defer([device, obj = std::move(*t)] {
    for (auto& [key, view] : obj.views) vkDestroyImageView(device, view, nullptr);
    if (!obj.isView) {
      vkDestroyImage(device, obj.image, nullptr);
      vkFreeMemory(device, obj.memory, nullptr);
    }
  });
}

const TextureDesc* VulkanDevice::describe(TextureHandle h) const {
  const TextureObject* t = textures_.get(h);
  return t ? &t->desc : nullptr;
}

VkImageView VulkanDevice::imageView(TextureObject& t, VkImageViewType type, VkImageAspectFlags aspect,
                                    uint32_t mip, uint32_t mipCount, uint32_t layer, uint32_t layerCount, bool sampled) {
  const VkComponentMapping identity{};
  const bool swizzled = sampled && std::memcmp(&t.components, &identity, sizeof identity) != 0;
  ViewKey key{type, t.format, aspect, t.baseMip + mip, mipCount, t.baseLayer + layer, layerCount, swizzled};
  for (auto& [k, view] : t.views)
    if (k == key) return view;

  VkImageViewCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  ci.image = t.image;
  ci.viewType = type;
  ci.format = t.format;
  ci.subresourceRange = {aspect, key.baseMip, mipCount, key.baseLayer, layerCount};
  if (swizzled) ci.components = t.components;
  // A view inherits the image's usage; restrict it to what the view's format supports.
  VkImageViewUsageCreateInfo usageInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_USAGE_CREATE_INFO};
  usageInfo.usage = t.usage & usageSupported(formatFeatures(t.format));
  if (usageInfo.usage != t.usage && usageInfo.usage != 0) ci.pNext = &usageInfo;
  VkImageView view = VK_NULL_HANDLE;
  if (vkCreateImageView(device_, &ci, nullptr, &view) != VK_SUCCESS) return VK_NULL_HANDLE;
  t.views.push_back({key, view});
  return view;
}

VkImageView VulkanDevice::attachmentView(TextureObject& t, uint32_t layer, uint32_t mip) {
  // Tex3D: layer is the slice (a 2D view of a 3D image addresses slices as array layers).
  const VkImageViewType type = t.desc.type == TextureType::Tex1D ? VK_IMAGE_VIEW_TYPE_1D : VK_IMAGE_VIEW_TYPE_2D;
  return imageView(t, type, formatAspects(t.desc.format), mip, 1, layer, 1);
}

// ---------------------------------------------------------------------------------------------
// Transfers
// ---------------------------------------------------------------------------------------------
void VulkanDevice::recordTextureUpload(VkCommandBuffer cb, const TextureObject& t, uint32_t layer, uint32_t mip,
                                       const void* data) {
  const uint32_t w = mipSize(t.desc.width, mip), h = mipSize(t.desc.height, mip);
  const size_t texels = size_t(w) * h;
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, t.baseMip + mip, 0, 1};
  addressLayer(t, layer, &region.imageSubresource, &region.imageOffset);
  region.imageExtent = {w, h, 1};

  if (t.desc.format == Format::D24S8) {
    // Texels as 32-bit words, depth in the high 24 bits and stencil in the low 8 (GL's
    // UNSIGNED_INT_24_8); Vulkan takes the aspects separately.
    const uint32_t* words = static_cast<const uint32_t*>(data);
    StagingSlice d = stagingAlloc(texels * 4);
    StagingSlice s = stagingAlloc(texels);
    if (!d.data || !s.data) return;
    for (size_t i = 0; i < texels; ++i) {
      uint32_t depthBits = words[i] >> 8;
      std::memcpy(d.data + i * 4, &depthBits, 4);
      s.data[i] = static_cast<uint8_t>(words[i] & 0xFF);
    }
    region.bufferOffset = d.offset;
    region.imageSubresource.aspectMask = VK_IMAGE_ASPECT_DEPTH_BIT;
    vkCmdCopyBufferToImage(cb, d.buffer, t.image, VK_IMAGE_LAYOUT_GENERAL, 1, &region);
    region.bufferOffset = s.offset;
    region.imageSubresource.aspectMask = VK_IMAGE_ASPECT_STENCIL_BIT;
    vkCmdCopyBufferToImage(cb, s.buffer, t.image, VK_IMAGE_LAYOUT_GENERAL, 1, &region);
    return;
  }
  const size_t bytes = texels * formatInfo(t.desc.format).bytesPerTexel;
  StagingSlice s = stagingAlloc(bytes);
  if (!s.data) return;
  std::memcpy(s.data, data, bytes);
  region.bufferOffset = s.offset;
  region.imageSubresource.aspectMask = formatAspects(t.desc.format);  // D32F, D16: depth
  vkCmdCopyBufferToImage(cb, s.buffer, t.image, VK_IMAGE_LAYOUT_GENERAL, 1, &region);
}

void VulkanDevice::writeTexture(TextureHandle h, uint32_t layer, uint32_t mip, const void* data) {
  TextureObject* t = textures_.get(h);
  if (!t || !data) return;
  recordTextureUpload(mainCmd_, *t, layer, mip, data);
  globalBarrier(mainCmd_);
}

std::vector<uint8_t> VulkanDevice::readTexture(TextureHandle h, const ReadbackRegion& region) {
  TextureObject* t = textures_.get(h);
  if (!t || t->desc.samples > 1) return {};
  const Format format = t->desc.format;
  const uint32_t w = mipSize(t->desc.width, region.mip), h2 = mipSize(t->desc.height, region.mip);
  const size_t texels = size_t(w) * h2;

  VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
  size_t bytesPerTexel = formatInfo(format).bytesPerTexel;
  if (isDepthFormat(format)) {
    if (region.aspect == TextureAspect::Stencil) {
      if (!hasStencil(format)) return {};
      aspect = VK_IMAGE_ASPECT_STENCIL_BIT;
      bytesPerTexel = 1;
    } else {
      aspect = VK_IMAGE_ASPECT_DEPTH_BIT;
      bytesPerTexel = format == Format::D16 ? 2 : 4;  // D32F as is, D24S8 as X8_D24 words
    }
  } else if (region.aspect != TextureAspect::Color) {
    return {};
  }

  const size_t bytes = texels * bytesPerTexel;
  VkBuffer staging;
  VkDeviceMemory memory;
  void* mapped = nullptr;
  if (!createHostBuffer(bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, &staging, &memory, &mapped)) return {};
  VkBufferImageCopy copy{};
  copy.imageSubresource = {aspect, t->baseMip + region.mip, 0, 1};
  addressLayer(*t, region.layer, &copy.imageSubresource, &copy.imageOffset);
  copy.imageExtent = {w, h2, 1};
  vkCmdCopyImageToBuffer(mainCmd_, t->image, VK_IMAGE_LAYOUT_GENERAL, staging, 1, &copy);
  globalBarrier(mainCmd_, /*toHost=*/true);
  flushAndWait();

  std::vector<uint8_t> out(bytes);
  std::memcpy(out.data(), mapped, bytes);
  if (format == Format::D24S8 && aspect == VK_IMAGE_ASPECT_DEPTH_BIT) {
    for (size_t i = 0; i < texels; ++i) {
      uint32_t q;
      std::memcpy(&q, out.data() + i * 4, 4);
      float d = static_cast<float>(static_cast<double>(q & 0xFFFFFFu) / 16777215.0);
      std::memcpy(out.data() + i * 4, &d, 4);
    }
  }
  vkDestroyBuffer(device_, staging, nullptr);
  vkFreeMemory(device_, memory, nullptr);
  if (format == Format::D16 && aspect == VK_IMAGE_ASPECT_DEPTH_BIT) return unorm16DepthToFloat(out);
  return out;
}

void VulkanDevice::copyTexture(TextureHandle src, TextureHandle dst, const ReadbackRegion& srcRegion,
                               const ReadbackRegion& dstRegion) {
  TextureObject* s = textures_.get(src);
  TextureObject* d = textures_.get(dst);
  if (!s || !d) return;
  VkImageCopy region{};
  region.srcSubresource = {formatAspects(s->desc.format), s->baseMip + srcRegion.mip, 0, 1};
  region.dstSubresource = {formatAspects(d->desc.format), d->baseMip + dstRegion.mip, 0, 1};
  addressLayer(*s, srcRegion.layer, &region.srcSubresource, &region.srcOffset);
  addressLayer(*d, dstRegion.layer, &region.dstSubresource, &region.dstOffset);
  region.extent = {mipSize(s->desc.width, srcRegion.mip), mipSize(s->desc.height, srcRegion.mip), 1};
  vkCmdCopyImage(mainCmd_, s->image, VK_IMAGE_LAYOUT_GENERAL, d->image, VK_IMAGE_LAYOUT_GENERAL, 1, &region);
  globalBarrier(mainCmd_);
}

// ---------------------------------------------------------------------------------------------
// Samplers
// ---------------------------------------------------------------------------------------------
SamplerHandle VulkanDevice::createSampler(const SamplerDesc& desc) {
  VkSamplerCreateInfo ci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  ci.magFilter = toVk(desc.magFilter);
  ci.minFilter = toVk(desc.minFilter);
  ci.mipmapMode = desc.mipFilter == MipFilter::Linear ? VK_SAMPLER_MIPMAP_MODE_LINEAR : VK_SAMPLER_MIPMAP_MODE_NEAREST;
  ci.addressModeU = toVk(desc.addressU);
  ci.addressModeV = toVk(desc.addressV);
  ci.addressModeW = toVk(desc.addressW);
  ci.compareEnable = desc.compareEnabled;
  ci.compareOp = toVkCompare(desc.compare);
  if (desc.mipFilter == MipFilter::None) {
    // No mip filtering: the base level only (the spec's recipe: maxLod 0.25 with NEAREST),
    // whatever the clamp says.
    ci.minLod = 0.0f;
    ci.maxLod = 0.25f;
  } else {
    // A level of detail below 0 selects level 0 as a clamp at 0 does.
    ci.minLod = std::max(0.0f, desc.minLod);
    ci.maxLod = std::max(ci.minLod, std::min(desc.maxLod, VK_LOD_CLAMP_NONE));
  }
  ci.mipLodBias = desc.mipLodBias;
  ci.borderColor = toVk(desc.borderColor);
  SamplerObject s;
  s.desc = desc;
  if (vkCreateSampler(device_, &ci, nullptr, &s.sampler) != VK_SUCCESS) return {};
  return samplers_.add(std::move(s));
}

void VulkanDevice::destroy(SamplerHandle h) {
  std::optional<SamplerObject> s = samplers_.remove(h);
  if (!s) return;
  VkDevice device = device_;
  defer([device, sampler = s->sampler] { vkDestroySampler(device, sampler, nullptr); });
}

VkSampler VulkanDevice::defaultSampler(bool compare) {
  VkSampler& slot = compare ? defaultCompareSampler_ : defaultSampler_;
  if (!slot) {
    VkSamplerCreateInfo ci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    ci.magFilter = ci.minFilter = VK_FILTER_NEAREST;
    ci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    ci.addressModeU = ci.addressModeV = ci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    ci.compareEnable = compare;
    ci.compareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
    ci.maxLod = 0.25f;
    ci.borderColor = VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK;
    vkCreateSampler(device_, &ci, nullptr, &slot);
  }
  return slot;
}

// ---------------------------------------------------------------------------------------------
// Dummy resources. lavapipe 22.3 crashes when a bound set has an unwritten combined image
// sampler, so every binding of a set is written; the ones the caller left unbound get these.
// ---------------------------------------------------------------------------------------------
TextureObject* VulkanDevice::dummyTexture(const ShaderResource& r) {
  const bool storage = r.kind == BindingKind::StorageTexture;
  const uint32_t key = uint32_t(r.multisampled) | uint32_t(r.arrayed) << 1 | uint32_t(r.cube) << 2 |
                       uint32_t(r.depthCompare) << 3 | uint32_t(r.integer) << 4 | uint32_t(storage) << 5 |
                       r.dimensions << 6;
  auto it = dummyTextures_.find(key);
  if (it != dummyTextures_.end()) return textures_.get(it->second);
  TextureDesc d;
  d.type = r.cube ? TextureType::Cube : r.arrayed ? TextureType::Tex2DArray : TextureType::Tex2D;
  if (r.dimensions == 1) d.type = TextureType::Tex1D;
  if (r.dimensions == 3) d.type = TextureType::Tex3D;
  d.layers = r.cube ? 6 : 1;
  if (storage)
    d.format = r.integer ? Format::R32_UINT : Format::RGBA8;
  else
    d.format = r.depthCompare ? Format::D32F : r.integer ? Format::RGBA8_UINT : Format::RGBA8;
  d.samples = r.multisampled ? 4 : 1;
  d.usage = TextureUsage_Sampled;
  if (storage) d.usage |= TextureUsage_Storage;
  if (r.multisampled) d.usage |= TextureUsage_RenderTarget;
  d.label = "parity dummy texture";
  TextureHandle h = createTexture(d);
  dummyTextures_[key] = h;
  return textures_.get(h);
}

BufferObject* VulkanDevice::dummyBuffer() {
  if (!buffers_.get(dummyBuffer_)) {
    BufferDesc d;
    d.size = 16384;  // the smallest maxUniformBufferRange a driver may have
    d.usage = BufferUsage_Uniform | BufferUsage_Storage;
    d.label = "parity dummy buffer";
    dummyBuffer_ = createBuffer(d);
  }
  return buffers_.get(dummyBuffer_);
}

}  // namespace parity::rhi::vulkan
