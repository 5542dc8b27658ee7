// A Device that forwards every call to another and writes a GPU timestamp after each pass,
// dispatch and copy, so a benchmark gets per-pass GPU times from any technique without the
// technique knowing it is measured (timestamps may only be written outside passes: after
// endPass is the earliest point that covers a pass's work).
#pragma once

#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "rhi/rhi.h"

namespace parity::bench {

class TimingDevice final : public rhi::Device {
 public:
  explicit TimingDevice(rhi::Device& inner) : inner_(inner) {}

  // Starts a measured frame: resets the timestamps and writes the first one. With
  // timestamps unsupported (Capabilities::timestamps false) nothing is recorded.
  void beginFrame();
  // After submit(): GPU time of every pass since beginFrame() in recording order, in
  // milliseconds, named by the pass label with trailing numbers removed ("light 12" -> "light")
  // and summed per name, so a multi-pass technique's passes form one row.
  std::vector<std::pair<std::string, double>> passTimesMs();
  // After submit(): GPU time from beginFrame() to the last pass, in milliseconds; -1 without
  // timestamps.
  double frameGpuMs();

  const rhi::DeviceInfo& info() const override { return inner_.info(); }
  rhi::BufferHandle createBuffer(const rhi::BufferDesc& d) override { return inner_.createBuffer(d); }
  rhi::TextureHandle createTexture(const rhi::TextureDesc& d) override { return inner_.createTexture(d); }
  rhi::TextureHandle createTextureView(const rhi::TextureViewDesc& d) override { return inner_.createTextureView(d); }
  rhi::SamplerHandle createSampler(const rhi::SamplerDesc& d) override { return inner_.createSampler(d); }
  rhi::ShaderHandle createShader(const rhi::ShaderDesc& d) override { return inner_.createShader(d); }
  rhi::PipelineHandle createPipeline(const rhi::PipelineDesc& d) override { return inner_.createPipeline(d); }
  rhi::ComputePipelineHandle createComputePipeline(const rhi::ComputePipelineDesc& d) override;
  void destroy(rhi::BufferHandle h) override { inner_.destroy(h); }
  void destroy(rhi::TextureHandle h) override { inner_.destroy(h); }
  void destroy(rhi::SamplerHandle h) override { inner_.destroy(h); }
  void destroy(rhi::ShaderHandle h) override { inner_.destroy(h); }
  void destroy(rhi::PipelineHandle h) override { inner_.destroy(h); }
  void destroy(rhi::ComputePipelineHandle h) override;
  const rhi::BufferDesc* describe(rhi::BufferHandle h) const override { return inner_.describe(h); }
  const rhi::TextureDesc* describe(rhi::TextureHandle h) const override { return inner_.describe(h); }
  void writeBuffer(rhi::BufferHandle h, size_t offset, const void* data, size_t size) override {
    inner_.writeBuffer(h, offset, data, size);
  }
  void writeTexture(rhi::TextureHandle h, uint32_t layer, uint32_t mip, const void* data) override {
    inner_.writeTexture(h, layer, mip, data);
  }
  std::vector<uint8_t> readBuffer(rhi::BufferHandle h, size_t offset, size_t size) override {
    return inner_.readBuffer(h, offset, size);
  }
  std::vector<uint8_t> readTexture(rhi::TextureHandle h, const rhi::ReadbackRegion& r) override {
    return inner_.readTexture(h, r);
  }
  void copyTexture(rhi::TextureHandle src, rhi::TextureHandle dst, const rhi::ReadbackRegion& s,
                   const rhi::ReadbackRegion& d) override;
  void copyBuffer(rhi::BufferHandle src, size_t so, rhi::BufferHandle dst, size_t dso, size_t size) override;
  void beginPass(const rhi::PassDesc& d) override;
  void endPass() override;
  void setPipeline(rhi::PipelineHandle h) override { inner_.setPipeline(h); }
  void setViewport(const rhi::Viewport& v) override { inner_.setViewport(v); }
  void setScissor(const rhi::Rect& r) override { inner_.setScissor(r); }
  void setStencilReference(uint8_t ref) override { inner_.setStencilReference(ref); }
  void setBlendConstant(const std::array<float, 4>& c) override { inner_.setBlendConstant(c); }
  void setVertexBuffer(uint32_t slot, rhi::BufferHandle h, size_t offset) override { inner_.setVertexBuffer(slot, h, offset); }
  void setIndexBuffer(rhi::BufferHandle h, rhi::IndexType t, size_t offset) override { inner_.setIndexBuffer(h, t, offset); }
  void draw(uint32_t vc, uint32_t ic, uint32_t fv, uint32_t fi) override { inner_.draw(vc, ic, fv, fi); }
  void drawIndexed(uint32_t ic, uint32_t inst, uint32_t fi, int32_t vo, uint32_t finst) override {
    inner_.drawIndexed(ic, inst, fi, vo, finst);
  }
  void setComputePipeline(rhi::ComputePipelineHandle h) override;
  void dispatch(uint32_t x, uint32_t y, uint32_t z) override;
  void setBindings(std::span<const rhi::ResourceBinding> b) override { inner_.setBindings(b); }
  void pushConstants(const void* data, uint32_t size) override { inner_.pushConstants(data, size); }
  rhi::TimestampId writeTimestamp() override { return inner_.writeTimestamp(); }
  std::optional<uint64_t> timestampNs(rhi::TimestampId id) override { return inner_.timestampNs(id); }
  void resetTimestamps() override { inner_.resetTimestamps(); }
  void submit() override { inner_.submit(); }

 private:
  void mark(const std::string& label);

  rhi::Device& inner_;
  bool measuring_ = false;
  std::string passLabel_, computeLabel_;
  std::unordered_map<uint32_t, std::string> computeLabels_;
  rhi::TimestampId start_ = 0;
  std::vector<std::pair<std::string, rhi::TimestampId>> marks_;
};

// "light 12" -> "light", "blur pass 2/3" -> "blur pass", "" -> "(unnamed)".
std::string passGroupName(const std::string& label);

}  // namespace parity::bench
