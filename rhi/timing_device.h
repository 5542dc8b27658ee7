// GPU time per pass without the technique knowing: a Device that forwards every call to another
// and writes a timestamp after each pass, dispatch and copy (timestamps may only be written
// outside passes, so the end of a pass is the earliest point that covers its work). Each
// entry's time runs from the previous timestamp, so the entries of a frame add up to the frame.
// Used by `parity run` and `parity view` (per-pass timings in reports and the title bar) and by
// `parity bench` (per-pass rows of its studies).
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include "rhi/rhi.h"

namespace parity::rhi {

struct PassTiming {
  std::string label;  // the PassDesc / ComputePipelineDesc label; "pass N" when empty; "copy"
  double ms = 0;
};

class TimingDevice final : public Device {
 public:
  explicit TimingDevice(Device& inner) : inner_(inner) {}

  // Starts a measured frame: forgets earlier entries, resets the timestamps and writes the
  // first one. Where the device has no timestamps (Capabilities::timestamps) nothing is recorded.
  void beginFrame();
  // After submit(): one entry per pass, dispatch and copy since beginFrame(), in recording
  // order; empty without timestamps.
  std::vector<PassTiming> passTimings();
  // After submit(): GPU time from beginFrame() to the last entry in milliseconds; -1 without
  // timestamps.
  double frameGpuMs();

  const DeviceInfo& info() const override { return inner_.info(); }
  BufferHandle createBuffer(const BufferDesc& d) override { return inner_.createBuffer(d); }
  TextureHandle createTexture(const TextureDesc& d) override { return inner_.createTexture(d); }
  TextureHandle createTextureView(const TextureViewDesc& d) override { return inner_.createTextureView(d); }
  SamplerHandle createSampler(const SamplerDesc& d) override { return inner_.createSampler(d); }
  ShaderHandle createShader(const ShaderDesc& d) override { return inner_.createShader(d); }
  PipelineHandle createPipeline(const PipelineDesc& d) override { return inner_.createPipeline(d); }
  ComputePipelineHandle createComputePipeline(const ComputePipelineDesc& d) override;
  void destroy(BufferHandle h) override { inner_.destroy(h); }
  void destroy(TextureHandle h) override { inner_.destroy(h); }
  void destroy(SamplerHandle h) override { inner_.destroy(h); }
  void destroy(ShaderHandle h) override { inner_.destroy(h); }
  void destroy(PipelineHandle h) override { inner_.destroy(h); }
  void destroy(ComputePipelineHandle h) override;
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
                   const ReadbackRegion& d = {}) override;
  void copyBuffer(BufferHandle src, size_t srcOffset, BufferHandle dst, size_t dstOffset, size_t size) override;
  void beginPass(const PassDesc& d) override;
  void endPass() override;
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
  void setComputePipeline(ComputePipelineHandle h) override;
  void dispatch(uint32_t x, uint32_t y = 1, uint32_t z = 1) override;
  void setBindings(std::span<const ResourceBinding> b) override { inner_.setBindings(b); }
  void pushConstants(const void* data, uint32_t size) override { inner_.pushConstants(data, size); }
  TimestampId writeTimestamp() override { return inner_.writeTimestamp(); }
  std::optional<uint64_t> timestampNs(TimestampId id) override { return inner_.timestampNs(id); }
  void resetTimestamps() override { inner_.resetTimestamps(); }
  void submit() override { inner_.submit(); }

 private:
  void mark(const std::string& label);

  Device& inner_;
  bool measuring_ = false;
  std::string passLabel_, computeLabel_;
  std::unordered_map<uint32_t, std::string> computeLabels_;
  TimestampId start_ = 0;
  struct Mark {
    std::string label;
    TimestampId id = 0;
  };
  std::vector<Mark> marks_;
};

}  // namespace parity::rhi
