// Vulkan 1.3 backend of the parity RHI: the Device implementation shared by the files of this
// folder (one file per concept, mirroring rhi/gl/): vk_device.cpp (instance, device, submit,
// memory, staging), vk_buffer.cpp, vk_texture.cpp (formats, textures, views, samplers,
// transfers), vk_shader.cpp, vk_pipeline.cpp, vk_commands.cpp (passes, draws, dispatches,
// bindings, timestamps).
//
// Synchronisation model, chosen for correctness and simplicity over speed (this is a test
// harness): every image is moved to VK_IMAGE_LAYOUT_GENERAL once, when it is created, and stays
// there; GENERAL is valid for every use on every driver, so no layout tracking is needed. After
// every render pass, dispatch, copy and upload a global memory barrier (ALL_COMMANDS ->
// ALL_COMMANDS, MEMORY_WRITE -> MEMORY_READ | MEMORY_WRITE) orders it before everything that
// follows. Draws inside one pass need no barriers: the RHI has no feedback loops.
//
// Recording: commands go into one primary command buffer; resource initialisation (layout
// transitions, initial data, zero fills) goes into a second one that is submitted just before
// it, so resources may be created at any time, even inside a pass. submit() ends both, submits,
// waits on a fence, then releases what was destroyed or staged meanwhile.
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rhi/handle_pool.h"
#include "rhi/rhi.h"
#include "rhi/shader_reflection.h"

namespace parity::rhi::vulkan {

// --- formats (vk_texture.cpp) ---
VkFormat toVkFormat(Format f);
VkImageAspectFlags formatAspects(Format f);  // every aspect of the format
VkFormat toVkVertexFormat(VertexFormat f);

const char* resultName(VkResult r);  // "VK_ERROR_DEVICE_LOST", ... (vk_device.cpp)

struct BufferViewKey {
  VkFormat format;
  VkDeviceSize offset, range;
  bool operator==(const BufferViewKey&) const = default;
};

struct BufferObject {
  BufferDesc desc;  // initialData cleared
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  std::vector<std::pair<BufferViewKey, VkBufferView>> views;  // texel buffer views, on demand
};

struct ViewKey {
  VkImageViewType type;
  VkFormat format;
  VkImageAspectFlags aspect;
  uint32_t baseMip, mipCount, baseLayer, layerCount;  // in the underlying VkImage
  bool swizzled;  // with the texture's component mapping (sampled reads), else the identity
  bool operator==(const ViewKey&) const = default;
};

struct TextureObject {
  TextureDesc desc;  // initialData cleared; views: resolved against the parent
  VkImage image = VK_NULL_HANDLE;         // views share their parent's image
  VkDeviceMemory memory = VK_NULL_HANDLE;  // null for views
  VkImageUsageFlags usage = 0;            // usage the VkImage was created with
  VkFormat format = VK_FORMAT_UNDEFINED;  // this texture's (or view's) format
  bool isView = false;
  uint32_t baseLayer = 0, baseMip = 0;  // views: where they start in the VkImage
  VkComponentMapping components{};      // views: TextureViewDesc::swizzle (zeros: the identity)
  std::vector<std::pair<ViewKey, VkImageView>> views;  // created on demand
};

struct SamplerObject {
  SamplerDesc desc;
  VkSampler sampler = VK_NULL_HANDLE;
};

struct ShaderObject {
  ShaderStage stage = ShaderStage::Vertex;
  VkShaderModule module = VK_NULL_HANDLE;
  std::string entryPoint;
  ShaderReflection reflection;
  // Vertex stage on a device without 64-bit vertex formats: the module's words, rewritten for
  // each pipeline that feeds it 64-bit attributes (rhi/double_vertex_inputs.h).
  std::vector<uint32_t> spirv;
};

// Descriptor set 0 and push-constant range of a pipeline: the union of its stages' reflection.
struct LayoutInfo {
  VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  std::vector<ShaderResource> bindings;  // sorted by binding
  std::vector<SeparatePair> separatePairs;  // union of the stages'
  uint32_t pushConstantSize = 0;
  VkShaderStageFlags stages = 0;
};

struct PipelineObject {
  PipelineDesc desc;
  VkPipeline pipeline = VK_NULL_HANDLE;
  LayoutInfo layout;
};

struct ComputePipelineObject {
  ComputePipelineDesc desc;
  VkPipeline pipeline = VK_NULL_HANDLE;
  LayoutInfo layout;
};

class VulkanDevice final : public Device {
 public:
  VulkanDevice() = default;
  ~VulkanDevice() override;
  VulkanDevice(const VulkanDevice&) = delete;
  VulkanDevice& operator=(const VulkanDevice&) = delete;

  // Returns false with a one-line reason; prints nothing.
  bool init(const DeviceDesc& desc, std::string* whyNot);
  void debugMessage(const std::string& message);  // from the validation layer's messenger

  const DeviceInfo& info() const override { return info_; }

  BufferHandle createBuffer(const BufferDesc& desc) override;
  TextureHandle createTexture(const TextureDesc& desc) override;
  TextureHandle createTextureView(const TextureViewDesc& desc) override;
  SamplerHandle createSampler(const SamplerDesc& desc) override;
  ShaderHandle createShader(const ShaderDesc& desc) override;
  PipelineHandle createPipeline(const PipelineDesc& desc) override;
  ComputePipelineHandle createComputePipeline(const ComputePipelineDesc& desc) override;
  void destroy(BufferHandle h) override;
  void destroy(TextureHandle h) override;
  void destroy(SamplerHandle h) override;
  void destroy(ShaderHandle h) override;
  void destroy(PipelineHandle h) override;
  void destroy(ComputePipelineHandle h) override;
  const BufferDesc* describe(BufferHandle h) const override;
  const TextureDesc* describe(TextureHandle h) const override;

  void writeBuffer(BufferHandle h, size_t offset, const void* data, size_t size) override;
  void writeTexture(TextureHandle h, uint32_t layer, uint32_t mip, const void* data) override;
  std::vector<uint8_t> readBuffer(BufferHandle h, size_t offset, size_t size) override;
  std::vector<uint8_t> readTexture(TextureHandle h, const ReadbackRegion& region) override;
  void copyTexture(TextureHandle src, TextureHandle dst, const ReadbackRegion& srcRegion,
                   const ReadbackRegion& dstRegion) override;
  void copyBuffer(BufferHandle src, size_t srcOffset, BufferHandle dst, size_t dstOffset, size_t size) override;

  void beginPass(const PassDesc& desc) override;
  void endPass() override;
  void setPipeline(PipelineHandle h) override;
  void setViewport(const Viewport& vp) override;
  void setScissor(const Rect& r) override;
  void setStencilReference(uint8_t ref) override;
  void setBlendConstant(const std::array<float, 4>& c) override;
  void setVertexBuffer(uint32_t slot, BufferHandle h, size_t offset) override;
  void setIndexBuffer(BufferHandle h, IndexType type, size_t offset) override;
  void draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) override;
  void drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                   uint32_t firstInstance) override;

  void setComputePipeline(ComputePipelineHandle h) override;
  void dispatch(uint32_t x, uint32_t y, uint32_t z) override;

  void setBindings(std::span<const ResourceBinding> bindings) override;
  void pushConstants(const void* data, uint32_t size) override;

  TimestampId writeTimestamp() override;
  std::optional<uint64_t> timestampNs(TimestampId id) override;
  void resetTimestamps() override;

  void submit() override;
  std::vector<std::string> takeNotes() override;

 private:
  // --- vk_device.cpp: instance, device, memory, staging, submission ---
  bool createInstance(const DeviceDesc& desc, std::string* whyNot);
  bool pickPhysicalDevice(std::string* whyNot);
  std::string adapter_;  // DeviceDesc::adapter
  bool createLogicalDevice(std::string* whyNot);
  // DeviceInfo::features (the enabled ones) and DeviceInfo::extensions (every offered one).
  void recordFeatures(const VkPhysicalDeviceFeatures& f10, const VkPhysicalDeviceVulkan11Features& f11,
                      const VkPhysicalDeviceVulkan12Features& f12, const VkPhysicalDeviceVulkan13Features& f13);
  bool allocateMemory(const VkMemoryRequirements& req, VkMemoryPropertyFlags required,
                      VkMemoryPropertyFlags preferred, VkDeviceMemory* out);
  // A host-visible buffer for transfers; its memory stays mapped.
  bool createHostBuffer(VkDeviceSize size, VkBufferUsageFlags usage, VkBuffer* buffer, VkDeviceMemory* memory,
                        void** mapped);
  struct StagingSlice {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceSize offset = 0;
    uint8_t* data = nullptr;  // size bytes, to be filled by the caller
  };
  // Host-visible space that lives until the next submit completes.
  StagingSlice stagingAlloc(VkDeviceSize size);
  void beginRecording();
  void flushAndWait();  // ends, submits and waits for both command buffers; starts new ones
  void globalBarrier(VkCommandBuffer cb, bool toHost = false);
  void defer(std::function<void()> release);  // run after the next submit completes
  VkCommandBuffer initCmd();                   // resource initialisation command buffer
  VkFormatFeatureFlags formatFeatures(VkFormat f) const;

  // --- vk_texture.cpp ---
  // Records upload of tightly packed texels of one layer/mip (relative to the texture).
  void recordTextureUpload(VkCommandBuffer cb, const TextureObject& t, uint32_t layer, uint32_t mip,
                           const void* data);
  // `sampled`: a view for SampledTexture/SeparateTexture descriptors, with the texture's component
  // mapping; attachments and storage images take the identity, as Vulkan requires.
  VkImageView imageView(TextureObject& t, VkImageViewType type, VkImageAspectFlags aspect, uint32_t mip,
                        uint32_t mipCount, uint32_t layer, uint32_t layerCount, bool sampled = false);
  VkImageView attachmentView(TextureObject& t, uint32_t layer, uint32_t mip);
  // A texture standing in for an unbound SampledTexture/StorageTexture of the given kind.
  TextureObject* dummyTexture(const ShaderResource& r);
  BufferObject* dummyBuffer();
  // --- vk_buffer.cpp ---
  VkBufferView bufferView(BufferObject& b, VkFormat format, VkDeviceSize offset, VkDeviceSize range);
  VkSampler defaultSampler(bool compare);

  // --- vk_pipeline.cpp ---
  bool buildLayout(const std::vector<const ShaderObject*>& shaders, LayoutInfo* out);
  void destroyLayout(const LayoutInfo& layout);

  // --- vk_commands.cpp ---
  // Allocates and writes descriptor set 0 for `layout` from the current bindings, binds it and
  // the push constants.
  void bindResources(VkPipelineBindPoint point, const LayoutInfo& layout);
  VkDescriptorSet allocateDescriptorSet(VkDescriptorSetLayout layout);
  bool prepareDraw();
  void recordPendingTimestampReset();

  // --- state ---
  DeviceInfo info_;
  std::function<void(const std::string&)> log_;

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties props_{};
  VkPhysicalDeviceMemoryProperties memProps_{};
  uint32_t queueFamily_ = 0;
  uint32_t timestampValidBits_ = 0;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool commandPool_ = VK_NULL_HANDLE;
  VkCommandBuffer mainCmd_ = VK_NULL_HANDLE;
  VkCommandBuffer initCmd_ = VK_NULL_HANDLE;
  bool initUsed_ = false;
  // R64* vertex buffer formats; without them Capabilities::doubleVertexFormats is met with 32-bit
  // word attributes (rhi/double_vertex_inputs.h).
  bool nativeDoubleVertexFormats_ = true;
  VkFence fence_ = VK_NULL_HANDLE;

  struct StagingChunk {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    uint8_t* mapped = nullptr;
    VkDeviceSize size = 0, used = 0;
  };
  std::vector<StagingChunk> staging_;
  std::vector<std::function<void()>> deferred_;

  std::vector<VkDescriptorPool> descriptorPools_;
  size_t currentPool_ = 0;

  HandlePool<BufferHandle, BufferObject> buffers_;
  HandlePool<TextureHandle, TextureObject> textures_;
  HandlePool<SamplerHandle, SamplerObject> samplers_;
  HandlePool<ShaderHandle, ShaderObject> shaders_;
  HandlePool<PipelineHandle, PipelineObject> pipelines_;
  HandlePool<ComputePipelineHandle, ComputePipelineObject> computePipelines_;

  std::map<uint32_t, TextureHandle> dummyTextures_;  // by a key made of ShaderResource flags
  BufferHandle dummyBuffer_;
  VkSampler defaultSampler_ = VK_NULL_HANDLE, defaultCompareSampler_ = VK_NULL_HANDLE;

  // Timestamps: ids are query indices since the last reset.
  static constexpr uint32_t kMaxTimestamps = 4096;
  VkQueryPool queryPool_ = VK_NULL_HANDLE;
  uint32_t timestampCount_ = 0;      // written since the last reset
  uint32_t timestampsSubmitted_ = 0;  // of those, how many were in a completed submission
  bool timestampResetPending_ = false;

  // Pass and draw state.
  bool inPass_ = false;
  uint32_t passWidth_ = 0, passHeight_ = 0;
  PipelineHandle pipeline_;
  ComputePipelineHandle computePipeline_;
  Viewport viewport_;
  Rect scissor_;
  uint8_t stencilRef_ = 0;
  std::array<float, 4> blendConstant_{0, 0, 0, 0};
  struct VertexBinding {
    BufferHandle buffer;
    size_t offset = 0;
  };
  std::array<VertexBinding, kMaxVertexBuffers> vertexBuffers_{};
  BufferHandle indexBuffer_;
  std::vector<std::string> notes_;  // takeNotes()
  IndexType indexType_ = IndexType::UInt32;
  size_t indexOffset_ = 0;
  std::array<std::array<std::optional<ResourceBinding>, kMaxArrayElements>, kMaxBindings> bindings_{};  // [binding][element]
  std::array<uint8_t, kMaxPushConstantBytes> pushData_{};
};

}  // namespace parity::rhi::vulkan
