// The device a technique renders through on a platform: the host device, with the platform's
// rasterisation conventions applied to every draw the technique records, so that no technique
// has to know them.
//
// Today that is one convention, X5: on x360 with D3DRS_HALFPIXELOFFSET false (the console's
// default) PA_SU_VTX_CNTL.PIX_CENTER is kD3DZero and pixel (x, y) is sampled at (x, y), not
// (x + 0.5, y + 0.5). A GL/Vulkan host, whose centres are at .5, reproduces that by moving every
// viewport by +0.5 px (hostPixelCenterOffset; Xenia's draw_util.cc and DXVK do the same). Scene
// geometry then lands half a pixel down and right of the reference, and every interpolated
// screen-space coordinate is half a pixel off, as on the console.
//
// GpuTargets records the platform's own resolve and copy passes on the host device
// (hostDevice()): on the console those are the resolve hardware's, not draws.
#pragma once

#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "rhi/forwarding_device.h"

namespace parity::platforms {

class PlatformDevice final : public rhi::ForwardingDevice {
 public:
  PlatformDevice(rhi::Device& host, PlatformId platform, const PlatformParams& params);

  // What every viewport of the technique is moved by, in pixels (0 where centres already match).
  float pixelCenterOffset() const { return offset_; }

  void setPipeline(rhi::PipelineHandle h) override;
  void setViewport(const rhi::Viewport& vp) override;

 private:
  float offset_ = 0;
};

// The device under `device` when it is a PlatformDevice, else `device` itself.
rhi::Device& hostDevice(rhi::Device& device);

}  // namespace parity::platforms
