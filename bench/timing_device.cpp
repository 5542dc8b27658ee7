#include "bench/timing_device.h"

#include <cctype>

namespace parity::bench {

std::string passGroupName(const std::string& label) {
  std::string s = label;
  while (!s.empty() && (std::isdigit(static_cast<unsigned char>(s.back())) || s.back() == ' ' || s.back() == '/' ||
                        s.back() == '#' || s.back() == '-' || s.back() == '_' || s.back() == '.'))
    s.pop_back();
  return s.empty() ? "(unnamed)" : s;
}

void TimingDevice::beginFrame() {
  marks_.clear();
  measuring_ = inner_.info().caps.timestamps;
  if (!measuring_) return;
  inner_.resetTimestamps();
  start_ = inner_.writeTimestamp();
}

void TimingDevice::mark(const std::string& label) {
  if (measuring_) marks_.emplace_back(passGroupName(label), inner_.writeTimestamp());
}

rhi::ComputePipelineHandle TimingDevice::createComputePipeline(const rhi::ComputePipelineDesc& d) {
  rhi::ComputePipelineHandle h = inner_.createComputePipeline(d);
  if (h) computeLabels_[h.id] = d.label.empty() ? "compute" : d.label;
  return h;
}

void TimingDevice::destroy(rhi::ComputePipelineHandle h) {
  computeLabels_.erase(h.id);
  inner_.destroy(h);
}

void TimingDevice::setComputePipeline(rhi::ComputePipelineHandle h) {
  auto it = computeLabels_.find(h.id);
  computeLabel_ = it == computeLabels_.end() ? "compute" : it->second;
  inner_.setComputePipeline(h);
}

void TimingDevice::copyTexture(rhi::TextureHandle src, rhi::TextureHandle dst, const rhi::ReadbackRegion& s,
                               const rhi::ReadbackRegion& d) {
  inner_.copyTexture(src, dst, s, d);
  mark("copy");
}

void TimingDevice::copyBuffer(rhi::BufferHandle src, size_t so, rhi::BufferHandle dst, size_t dso, size_t size) {
  inner_.copyBuffer(src, so, dst, dso, size);
  mark("copy");
}

void TimingDevice::beginPass(const rhi::PassDesc& d) {
  passLabel_ = d.label;
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

std::vector<std::pair<std::string, double>> TimingDevice::passTimesMs() {
  std::vector<std::pair<std::string, double>> out;
  if (!measuring_) return out;
  std::optional<uint64_t> previous = inner_.timestampNs(start_);
  for (const auto& [name, id] : marks_) {
    std::optional<uint64_t> t = inner_.timestampNs(id);
    if (!t || !previous) return {};
    double ms = static_cast<double>(*t >= *previous ? *t - *previous : 0) * 1e-6;
    previous = t;
    bool merged = false;
    for (auto& [n, v] : out)
      if (n == name) {
        v += ms;
        merged = true;
      }
    if (!merged) out.emplace_back(name, ms);
  }
  return out;
}

double TimingDevice::frameGpuMs() {
  if (!measuring_ || marks_.empty()) return -1;
  std::optional<uint64_t> a = inner_.timestampNs(start_), b = inner_.timestampNs(marks_.back().second);
  if (!a || !b || *b < *a) return -1;
  return static_cast<double>(*b - *a) * 1e-6;
}

}  // namespace parity::bench
