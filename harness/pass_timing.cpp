#include "harness/pass_timing.h"

namespace parity::harness {

void PassTimingDevice::beginFrame() {
  passes_.clear();
  timing_ = d_.info().caps.timestamps;
  if (timing_) d_.resetTimestamps();
}

void PassTimingDevice::beginPass(const rhi::PassDesc& desc) {
  if (timing_) passes_.push_back({desc.label.empty() ? "pass " + std::to_string(passes_.size()) : desc.label,
                                  d_.writeTimestamp(), 0});
  d_.beginPass(desc);
}

void PassTimingDevice::endPass() {
  d_.endPass();
  if (timing_ && !passes_.empty()) passes_.back().end = d_.writeTimestamp();
}

std::vector<PassTiming> PassTimingDevice::passTimings() {
  std::vector<PassTiming> out;
  for (const Recorded& p : passes_) {
    std::optional<uint64_t> a = d_.timestampNs(p.begin), b = d_.timestampNs(p.end);
    if (!a || !b || *b < *a) continue;
    out.push_back({p.label, static_cast<double>(*b - *a) / 1e6});
  }
  return out;
}

}  // namespace parity::harness
