// Pass timings from device timestamps: a Device that forwards every call to another and writes a
// timestamp before each beginPass and after each endPass (both outside passes, as the RHI asks),
// so a technique's passes are timed without the technique knowing. Passes are named by their
// PassDesc label.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "rhi/rhi.h"

namespace parity::harness {

struct PassTiming {
  std::string label;
  double ms = 0;
};

class PassTimingDevice final : public rhi::Device {
 public:
  explicit PassTimingDevice(rhi::Device& inner) : d_(inner) {}

  // Forgets earlier passes and resets the device's timestamps.
  void beginFrame();
  // The passes recorded since beginFrame(), after a submit(); empty where the device has no
  // timestamps (rhi::Capabilities::timestamps).
  std::vector<PassTiming> passTimings();

  const rhi::DeviceInfo& info() const override { return d_.info(); }
  rhi::BufferHandle createBuffer(const rhi::BufferDesc& desc) override { return d_.createBuffer(desc); }
  rhi::TextureHandle createTexture(const rhi::TextureDesc& desc) override { return d_.createTexture(desc); }
  rhi::TextureHandle createTextureView(const rhi::TextureViewDesc& desc) override { return d_.createTextureView(desc); }
  rhi::SamplerHandle createSampler(const rhi::SamplerDesc& desc) override { return d_.createSampler(desc); }
  rhi::ShaderHandle createShader(const rhi::ShaderDesc& desc) override { return d_.createShader(desc); }
  rhi::PipelineHandle createPipeline(const rhi::PipelineDesc& desc) override { return d_.createPipeline(desc); }
  rhi::ComputePipelineHandle createComputePipeline(const rhi::ComputePipelineDesc& desc) override {
    return d_.createComputePipeline(desc);
  }
  void destroy(rhi::BufferHandle h) override { d_.destroy(h); }
  void destroy(rhi::TextureHandle h) override { d_.destroy(h); }
  void destroy(rhi::SamplerHandle h) override { d_.destroy(h); }
  void destroy(rhi::ShaderHandle h) override { d_.destroy(h); }
  void destroy(rhi::PipelineHandle h) override { d_.destroy(h); }
  void destroy(rhi::ComputePipelineHandle h) override { d_.destroy(h); }
  const rhi::BufferDesc* describe(rhi::BufferHandle h) const override { return d_.describe(h); }
  const rhi::TextureDesc* describe(rhi::TextureHandle h) const override { return d_.describe(h); }
  void writeBuffer(rhi::BufferHandle h, size_t offset, const void* data, size_t size) override {
    d_.writeBuffer(h, offset, data, size);
  }
  void writeTexture(rhi::TextureHandle h, uint32_t layer, uint32_t mip, const void* data) override {
    d_.writeTexture(h, layer, mip, data);
  }
  std::vector<uint8_t> readBuffer(rhi::BufferHandle h, size_t offset, size_t size) override {
    return d_.readBuffer(h, offset, size);
  }
  std::vector<uint8_t> readTexture(rhi::TextureHandle h, const rhi::ReadbackRegion& region = {}) override {
    return d_.readTexture(h, region);
  }
  void copyTexture(rhi::TextureHandle src, rhi::TextureHandle dst, const rhi::ReadbackRegion& srcRegion = {},
                   const rhi::ReadbackRegion& dstRegion = {}) override {
    d_.copyTexture(src, dst, srcRegion, dstRegion);
  }
  void copyBuffer(rhi::BufferHandle src, size_t srcOffset, rhi::BufferHandle dst, size_t dstOffset, size_t size) override {
    d_.copyBuffer(src, srcOffset, dst, dstOffset, size);
  }
  void beginPass(const rhi::PassDesc& desc) override;
  void endPass() override;
  void setPipeline(rhi::PipelineHandle h) override { d_.setPipeline(h); }
  void setViewport(const rhi::Viewport& vp) override { d_.setViewport(vp); }
  void setScissor(const rhi::Rect& r) override { d_.setScissor(r); }
  void setStencilReference(uint8_t ref) override { d_.setStencilReference(ref); }
  void setBlendConstant(const std::array<float, 4>& c) override { d_.setBlendConstant(c); }
  void setVertexBuffer(uint32_t slot, rhi::BufferHandle h, size_t offset = 0) override { d_.setVertexBuffer(slot, h, offset); }
  void setIndexBuffer(rhi::BufferHandle h, rhi::IndexType type, size_t offset = 0) override { d_.setIndexBuffer(h, type, offset); }
  void draw(uint32_t vertexCount, uint32_t instanceCount = 1, uint32_t firstVertex = 0, uint32_t firstInstance = 0) override {
    d_.draw(vertexCount, instanceCount, firstVertex, firstInstance);
  }
  void drawIndexed(uint32_t indexCount, uint32_t instanceCount = 1, uint32_t firstIndex = 0, int32_t vertexOffset = 0,
                   uint32_t firstInstance = 0) override {
    d_.drawIndexed(indexCount, instanceCount, firstIndex, vertexOffset, firstInstance);
  }
  void setComputePipeline(rhi::ComputePipelineHandle h) override { d_.setComputePipeline(h); }
  void dispatch(uint32_t x, uint32_t y = 1, uint32_t z = 1) override { d_.dispatch(x, y, z); }
  void setBindings(std::span<const rhi::ResourceBinding> bindings) override { d_.setBindings(bindings); }
  void pushConstants(const void* data, uint32_t size) override { d_.pushConstants(data, size); }
  rhi::TimestampId writeTimestamp() override { return d_.writeTimestamp(); }
  std::optional<uint64_t> timestampNs(rhi::TimestampId id) override { return d_.timestampNs(id); }
  void resetTimestamps() override { d_.resetTimestamps(); }
  void submit() override { d_.submit(); }

 private:
  struct Recorded {
    std::string label;
    rhi::TimestampId begin = 0, end = 0;
  };
  rhi::Device& d_;
  std::vector<Recorded> passes_;
  bool timing_ = false;
};

}  // namespace parity::harness
