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
//
// It also collects the diagnostics of the frame: every plan a technique allocates through
// GpuTargets on this device (EDRAM placement, MRT rules, resolve precision) and what the
// platform finds in the resolves it plans (X3 alignment), so that the harness can put them in
// the case's verdict (platforms/common/diagnostics.h). Draw-level rules are checked on the real
// pipelines: every draw into a registered platform target (GpuTargets registers its
// attachments) with the pipeline's blend state and write mask: PS3 packed targets
// (E_PACKED_BLEND, W_PACKED_PARTIAL_WRITEMASK), x360 k_16_16 surfaces (W_FIXED16_MULT_BLEND).
//
// And it names what escaped the platform: every texture the technique created itself (through
// this device, not through GpuTargets) and then rendered into. Such a target has the host's
// format and no console rule applies to it; `parity render` lists them and
// tests/technique_platform_targets_test.cpp holds each technique to its documented list.
#pragma once

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "rhi/forwarding_device.h"

#include <array>
#include <functional>
#include <map>
#include <set>
#include <string>

namespace parity::platforms {

class PlatformDevice final : public rhi::ForwardingDevice {
 public:
  PlatformDevice(rhi::Device& host, PlatformId platform, const PlatformParams& params);

  // What the frame's targets and resolves raised so far, each distinct diagnostic once.
  const DiagnosticList& diagnostics() const { return diagnostics_; }
  void report(const DiagnosticList& found);
  // A platform target's attachment (or its integer write view): draws into it are checked.
  // `afterPass`, if set, is called at the end of every pass with a draw into it that blends, or
  // with any draw into it when `blendedOnly` is false (the x360 fixed-point clamp,
  // GpuTargets::clampFixedPoint; the 7e3 rounding, GpuTargets::quantiseFloat7e3).
  void registerTarget(rhi::TextureHandle texture, const std::string& name, LogicalFormat format,
                      std::function<void()> afterPass = {}, bool blendedOnly = true);
  void forgetTarget(rhi::TextureHandle texture) { targets_.erase(texture.id); }
  // "pass: texture" for every attachment the technique created itself rather than through the
  // platform's plan (see above), each once, sorted.
  const std::set<std::string>& unplannedAttachments() const { return unplanned_; }

  rhi::TextureHandle createTexture(const rhi::TextureDesc& d) override;
  rhi::TextureHandle createTextureView(const rhi::TextureViewDesc& d) override;
  void destroy(rhi::TextureHandle h) override;
  rhi::PipelineHandle createPipeline(const rhi::PipelineDesc& d) override;
  void destroy(rhi::PipelineHandle h) override;
  using ForwardingDevice::destroy;
  void beginPass(const rhi::PassDesc& d) override;
  void endPass() override;
  void setPipeline(rhi::PipelineHandle h) override;
  void setViewport(const rhi::Viewport& vp) override;
  void draw(uint32_t vertexCount, uint32_t instanceCount = 1, uint32_t firstVertex = 0,
            uint32_t firstInstance = 0) override;
  void drawIndexed(uint32_t indexCount, uint32_t instanceCount = 1, uint32_t firstIndex = 0, int32_t vertexOffset = 0,
                   uint32_t firstInstance = 0) override;

 private:
  struct Target {
    std::string name;
    LogicalFormat format = LogicalFormat::Rgba8Unorm;
    std::function<void()> afterPass;
    bool blendedOnly = true;
  };
  void checkDraw();

  PlatformId platform_;
  PlatformParams params_;
  float offset_ = 0;
  DiagnosticList diagnostics_;
  std::map<uint32_t, Target> targets_;                          // by texture handle id
  std::map<uint32_t, std::string> ownTextures_;                 // created through this device: id -> label
  std::set<std::string> unplanned_;
  std::map<uint32_t, std::array<rhi::ColorTargetState, rhi::kMaxColorTargets>> pipelines_;  // colour states
  std::array<rhi::TextureHandle, rhi::kMaxColorTargets> passColors_{};
  uint32_t pipeline_ = 0;
  std::map<uint32_t, std::function<void()>> afterPass_;  // targets blended into in this pass, by texture id
};

// The device under `device` when it is a PlatformDevice, else `device` itself.
rhi::Device& hostDevice(rhi::Device& device);
// `device` as a PlatformDevice, or null.
PlatformDevice* asPlatformDevice(rhi::Device& device);

}  // namespace parity::platforms
