#include "platforms/texel_counters.h"

#include <cstring>

namespace parity::platforms {

namespace {
constexpr uint32_t kSlots = 256;  // slots between two reads of the buffer (a read waits for the GPU)
}

TexelCounters::~TexelCounters() {
  if (buffer_) host_.destroy(buffer_);
}

uint32_t TexelCounters::open(Slot slot) {
  if (!buffer_) {
    rhi::BufferDesc d;
    d.size = size_t(kSlots) * kLanes * sizeof(uint32_t);
    d.usage = rhi::BufferUsage_Storage;
    d.label = "platform texel counters";
    buffer_ = host_.createBuffer(d);  // zeroed
  }
  if (open_.size() == kSlots) drain();
  open_.push_back(std::move(slot));
  return uint32_t(open_.size() - 1);
}

void TexelCounters::drain() {
  if (open_.empty() || !buffer_) return;
  const size_t bytes = open_.size() * kLanes * sizeof(uint32_t);
  std::vector<uint8_t> raw = host_.readBuffer(buffer_, 0, bytes);
  std::vector<uint32_t> counts(open_.size() * kLanes, 0);
  if (raw.size() == bytes) std::memcpy(counts.data(), raw.data(), bytes);
  for (size_t s = 0; s < open_.size(); ++s)
    for (uint32_t lane = 0; lane < kLanes; ++lane) {
      const uint32_t n = counts[s * kLanes + lane];
      if (n == 0 || open_[s].codes[lane].empty()) continue;
      Key key{std::string(open_[s].codes[lane]), open_[s].target, open_[s].pass};
      auto [it, fresh] = totals_.try_emplace(key, 0, open_[s].what[lane]);
      if (fresh) order_.push_back(key);
      it->second.first += n;
    }
  const std::vector<uint8_t> zeros(bytes, 0);
  host_.writeBuffer(buffer_, 0, zeros.data(), zeros.size());
  open_.clear();
}

void TexelCounters::collect(DiagnosticList& out) {
  drain();
  for (const Key& key : order_) {
    const auto& [code, target, pass] = key;
    const auto& [count, what] = totals_.at(key);
    DiagnosticSite site;
    site.pass = pass;
    site.count = count;
    out.report(code, {target}, std::to_string(count) + " " + what, site);
  }
}

}  // namespace parity::platforms
