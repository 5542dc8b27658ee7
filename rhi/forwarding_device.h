// A Device that passes every call to another one: the base of decorators that change a few
// commands and leave the rest alone (rhi::TimingDevice, the x360 pixel-centre layer).
#pragma once

#include "rhi/rhi.h"

namespace parity::rhi {

class ForwardingDevice : public Device {
 public:
  explicit ForwardingDevice(Device& inner) : inner_(inner) {}
  Device& inner() const { return inner_; }

  const DeviceInfo& info() const override { return inner_.info(); }
  BufferHandle createBuffer(const BufferDesc& d) override { return inner_.createBuffer(d); }
  TextureHandle createTexture(const TextureDesc& d) override { return inner_.createTexture(d); }
  TextureHandle createTextureView(const TextureViewDesc& d) override { return inner_.createTextureView(d); }
  SamplerHandle createSampler(const SamplerDesc& d) override { return inner_.createSampler(d); }
  ShaderHandle createShader(const ShaderDesc& d) override { return inner_.createShader(d); }
  PipelineHandle createPipeline(const PipelineDesc& d) override { return inner_.createPipeline(d); }
  ComputePipelineHandle createComputePipeline(const ComputePipelineDesc& d) override {
    return inner_.createComputePipeline(d);
  }
  void destroy(BufferHandle h) override { inner_.destroy(h); }
  void destroy(TextureHandle h) override { inner_.destroy(h); }
  void destroy(SamplerHandle h) override { inner_.destroy(h); }
  void destroy(ShaderHandle h) override { inner_.destroy(h); }
  void destroy(PipelineHandle h) override { inner_.destroy(h); }
  void destroy(ComputePipelineHandle h) override { inner_.destroy(h); }
  const BufferDesc* describe(BufferHandle h) const override { return inner_.describe(h); }
  const TextureDesc* describe(TextureHandle h) const override { return inner_.describe(h); }
  void writeBuffer(BufferHandle h, size_t offset, const void* data, size_t size) override {
    inner_.writeBuffer(h, offset, data, size);
  }
  void writeTexture(TextureHandle h, uint32_t layer, uint32_t mip, const void* data) override {
    inner_.writeTexture(h, layer, mip, data);
  }
  std::vector<uint8_t> readBuffer(BufferHandle h, size_t offset, size_t size) override {
    return inner_.readBuffer(h, offset, size);
  }
  std::vector<uint8_t> readTexture(TextureHandle h, const ReadbackRegion& r = {}) override {
    return inner_.readTexture(h, r);
  }
  void copyTexture(TextureHandle src, TextureHandle dst, const ReadbackRegion& s = {},
                   const ReadbackRegion& d = {}) override {
    inner_.copyTexture(src, dst, s, d);
  }
  void copyBuffer(BufferHandle src, size_t srcOffset, BufferHandle dst, size_t dstOffset, size_t size) override {
    inner_.copyBuffer(src, srcOffset, dst, dstOffset, size);
  }
  void beginPass(const PassDesc& d) override { inner_.beginPass(d); }
  void endPass() override { inner_.endPass(); }
  void setPipeline(PipelineHandle h) override { inner_.setPipeline(h); }
  void setViewport(const Viewport& v) override { inner_.setViewport(v); }
  void setScissor(const Rect& r) override { inner_.setScissor(r); }
  void setStencilReference(uint8_t ref) override { inner_.setStencilReference(ref); }
  void setBlendConstant(const std::array<float, 4>& c) override { inner_.setBlendConstant(c); }
  void setVertexBuffer(uint32_t slot, BufferHandle h, size_t offset = 0) override {
    inner_.setVertexBuffer(slot, h, offset);
  }
  void setIndexBuffer(BufferHandle h, IndexType t, size_t offset = 0) override { inner_.setIndexBuffer(h, t, offset); }
  void draw(uint32_t vertexCount, uint32_t instanceCount = 1, uint32_t firstVertex = 0,
            uint32_t firstInstance = 0) override {
    inner_.draw(vertexCount, instanceCount, firstVertex, firstInstance);
  }
  void drawIndexed(uint32_t indexCount, uint32_t instanceCount = 1, uint32_t firstIndex = 0, int32_t vertexOffset = 0,
                   uint32_t firstInstance = 0) override {
    inner_.drawIndexed(indexCount, instanceCount, firstIndex, vertexOffset, firstInstance);
  }
  void setComputePipeline(ComputePipelineHandle h) override { inner_.setComputePipeline(h); }
  void dispatch(uint32_t x, uint32_t y = 1, uint32_t z = 1) override { inner_.dispatch(x, y, z); }
  void setBindings(std::span<const ResourceBinding> b) override { inner_.setBindings(b); }
  void pushConstants(const void* data, uint32_t size) override { inner_.pushConstants(data, size); }
  void setProgramParameter(ShaderStage stage, bool local, uint32_t index, const std::array<float, 4>& value) override {
    inner_.setProgramParameter(stage, local, index, value);
  }
  void setTransformMatrices(const std::array<float, 16>& modelView, const std::array<float, 16>& projection) override {
    inner_.setTransformMatrices(modelView, projection);
  }
  void setCurrentAttribute(CurrentAttribute attribute, uint32_t index, const std::array<float, 4>& value) override {
    inner_.setCurrentAttribute(attribute, index, value);
  }
  TimestampId writeTimestamp() override { return inner_.writeTimestamp(); }
  std::optional<uint64_t> timestampNs(TimestampId id) override { return inner_.timestampNs(id); }
  void resetTimestamps() override { inner_.resetTimestamps(); }
  void submit() override { inner_.submit(); }
  std::vector<std::string> takeNotes() override { return inner_.takeNotes(); }

 private:
  Device& inner_;
};

}  // namespace parity::rhi
