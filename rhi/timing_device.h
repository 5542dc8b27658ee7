// GPU time per pass without the technique knowing: a Device that forwards every call to another
// (rhi::ForwardingDevice) and writes a timestamp after each pass, dispatch and copy (timestamps may only be written
// outside passes, so the end of a pass is the earliest point that covers its work). Each
// entry's time runs from the previous timestamp, so the entries of a frame add up to the frame.
// Used by `parity run` and `parity view` (per-pass timings in reports and the title bar) and by
// `parity bench` (per-pass rows of its studies).
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include "rhi/forwarding_device.h"

namespace parity::rhi {

struct PassTiming {
  std::string label;  // the PassDesc / ComputePipelineDesc label; "pass N" when empty; "copy"
  double ms = 0;
};

class TimingDevice final : public ForwardingDevice {
 public:
  explicit TimingDevice(Device& inner) : ForwardingDevice(inner), inner_(inner) {}

  // Starts a measured frame: forgets earlier entries, resets the timestamps and writes the
  // first one. Where the device has no timestamps (Capabilities::timestamps) nothing is recorded.
  void beginFrame();
  // Starts a frame that writes no timestamp (passTimings() empty, frameGpuMs() -1): a frame whose
  // wall time is to be the technique's alone. Software rasterisers (llvmpipe, lavapipe) finish
  // the queued work at every timestamp, so a frame with them takes longer and varies more.
  void beginUntimedFrame();
  // After submit(): one entry per pass, dispatch and copy since beginFrame(), in recording
  // order; empty without timestamps.
  std::vector<PassTiming> passTimings();
  // After submit(): GPU time from beginFrame() to the last entry in milliseconds; -1 without
  // timestamps.
  double frameGpuMs();

  ComputePipelineHandle createComputePipeline(const ComputePipelineDesc& d) override;
  void destroy(ComputePipelineHandle h) override;
  using ForwardingDevice::destroy;
  void copyTexture(TextureHandle src, TextureHandle dst, const ReadbackRegion& s = {},
                   const ReadbackRegion& d = {}) override;
  void copyBuffer(BufferHandle src, size_t srcOffset, BufferHandle dst, size_t dstOffset, size_t size) override;
  void beginPass(const PassDesc& d) override;
  void endPass() override;
  void setComputePipeline(ComputePipelineHandle h) override;
  void dispatch(uint32_t x, uint32_t y = 1, uint32_t z = 1) override;

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
