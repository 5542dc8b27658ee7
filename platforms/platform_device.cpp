#include "platforms/platform_device.h"

#include "platforms/platform_layer.h"

namespace parity::platforms {

PlatformDevice::PlatformDevice(rhi::Device& host, PlatformId platform, const PlatformParams& params)
    : ForwardingDevice(host), offset_(hostPixelCenterOffset(platform, params)) {}

void PlatformDevice::setPipeline(rhi::PipelineHandle h) {
  inner().setPipeline(h);  // resets the viewport to the whole pass...
  if (offset_ != 0) setViewport({});  // ...which moves with the pixel centres too
}

void PlatformDevice::setViewport(const rhi::Viewport& vp) {
  rhi::Viewport moved = vp;  // width and height 0 keep meaning "the whole attachment"
  moved.x += offset_;
  moved.y += offset_;
  inner().setViewport(moved);
}

rhi::Device& hostDevice(rhi::Device& device) {
  if (auto* p = dynamic_cast<PlatformDevice*>(&device)) return p->inner();
  return device;
}

}  // namespace parity::platforms
