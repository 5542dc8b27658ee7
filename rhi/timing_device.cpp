#include "rhi/timing_device.h"

namespace parity::rhi {

void TimingDevice::beginFrame() {
  marks_.clear();
  measuring_ = inner_.info().caps.timestamps;
  if (!measuring_) return;
  inner_.resetTimestamps();
  start_ = inner_.writeTimestamp();
}

void TimingDevice::beginUntimedFrame() {
  marks_.clear();
  measuring_ = false;
}

void TimingDevice::mark(const std::string& label) {
  if (measuring_) marks_.push_back({label, inner_.writeTimestamp()});
}

ComputePipelineHandle TimingDevice::createComputePipeline(const ComputePipelineDesc& d) {
  ComputePipelineHandle h = inner_.createComputePipeline(d);
  if (h) computeLabels_[h.id] = d.label.empty() ? "compute" : d.label;
  return h;
}

void TimingDevice::destroy(ComputePipelineHandle h) {
  computeLabels_.erase(h.id);
  inner_.destroy(h);
}

void TimingDevice::setComputePipeline(ComputePipelineHandle h) {
  auto it = computeLabels_.find(h.id);
  computeLabel_ = it == computeLabels_.end() ? "compute" : it->second;
  inner_.setComputePipeline(h);
}

void TimingDevice::copyTexture(TextureHandle src, TextureHandle dst, const ReadbackRegion& s, const ReadbackRegion& d) {
  inner_.copyTexture(src, dst, s, d);
  mark("copy");
}

void TimingDevice::copyBuffer(BufferHandle src, size_t srcOffset, BufferHandle dst, size_t dstOffset, size_t size) {
  inner_.copyBuffer(src, srcOffset, dst, dstOffset, size);
  mark("copy");
}

void TimingDevice::beginPass(const PassDesc& d) {
  passLabel_ = d.label.empty() ? "pass " + std::to_string(marks_.size()) : d.label;
  inner_.beginPass(d);
}

void TimingDevice::endPass() {
  inner_.endPass();
  mark(passLabel_);
}

void TimingDevice::dispatch(uint32_t x, uint32_t y, uint32_t z) {
  inner_.dispatch(x, y, z);
  mark(computeLabel_);
}

std::vector<PassTiming> TimingDevice::passTimings() {
  std::vector<PassTiming> out;
  if (!measuring_) return out;
  std::optional<uint64_t> previous = inner_.timestampNs(start_);
  for (const Mark& m : marks_) {
    std::optional<uint64_t> t = inner_.timestampNs(m.id);
    if (!t || !previous) return {};
    out.push_back({m.label, static_cast<double>(*t >= *previous ? *t - *previous : 0) * 1e-6});
    previous = t;
  }
  return out;
}

double TimingDevice::frameGpuMs() {
  if (!measuring_ || marks_.empty()) return -1;
  std::optional<uint64_t> a = inner_.timestampNs(start_), b = inner_.timestampNs(marks_.back().id);
  if (!a || !b || *b < *a) return -1;
  return static_cast<double>(*b - *a) * 1e-6;
}

}  // namespace parity::rhi
