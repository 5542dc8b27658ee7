// The device a technique renders through on a platform: the host device, with the platform's
// rasterisation conventions applied to every draw, and the platform's rules evaluated on every
// call, so that no technique has to know either.
//
// Conventions. X5: on x360 with D3DRS_HALFPIXELOFFSET false (the console's default)
// PA_SU_VTX_CNTL.PIX_CENTER is kD3DZero and pixel (x, y) is sampled at (x, y), not
// (x + 0.5, y + 0.5). A GL/Vulkan host, whose centres are at .5, reproduces that by moving every
// viewport by +0.5 px (hostPixelCenterOffset; Xenia's draw_util.cc and DXVK do the same). Scene
// geometry then lands half a pixel down and right of the reference, and every interpolated
// screen-space coordinate is half a pixel off, as on the console. A screen-space pass that
// compensates as a D3D9 port does (its viewport at -0.5, TargetPlan::pixelCenterOffset) samples
// where the reference does.
//
// Rules. The device is the consoles' validation layer (platform_rules.h): it mirrors the state
// of the command stream (passes and their attachments, pipelines, bindings and samplers,
// viewports) and hands every pass, draw, dispatch, copy and resolve to the platform's rules with
// the real state. GpuTargets registers the platform targets it creates (registerSurface) and its
// resolves, records its own passes on the host device underneath (they are the console's resolve
// hardware, not draws: hostDevice()), and counts the values its passes clamp (texel_counters.h).
// Every diagnostic names the pass and the pipeline it fired in; diagnostics() gathers them with
// the plans' own (EDRAM placement, resolve precision).
//
// And it names what escaped the platform: every texture the technique created itself (through
// this device, not through GpuTargets) and then rendered into. Such a target has the host's
// format and only the rules that speak of host formats apply to it; `parity render` lists them
// and tests/technique_platform_targets_test.cpp holds each technique to its documented list.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "platforms/platform_rules.h"
#include "platforms/shader_use.h"
#include "platforms/texel_counters.h"
#include "rhi/forwarding_device.h"

namespace parity::platforms {

class PlatformDevice final : public rhi::ForwardingDevice {
 public:
  // `countValues`: the platform's store and resolve passes count the values they clamp (read
  // back by diagnostics()); a device whose diagnostics nobody reads (`parity bench`, `parity
  // view`) passes false, so that no read of the counters waits for the GPU between its frames.
  PlatformDevice(rhi::Device& host, PlatformId platform, const PlatformParams& params, bool countValues = true);
  ~PlatformDevice() override;

  PlatformId platform() const { return platform_; }
  // The host's, with only what the platform guarantees (publishedCapabilities, capabilities.h):
  // what a technique on this platform chooses its paths from.
  const rhi::DeviceInfo& info() const override { return info_; }
  // What the frame's plans, rules and counted values raised so far, each distinct diagnostic
  // once. Reads the value counters back (it waits for the GPU).
  DiagnosticList diagnostics();
  void report(const DiagnosticList& found);

  // --- GpuTargets' side ----------------------------------------------------------------------
  // A platform target of plan `plan` (a GpuTargets) and the textures through which calls reach
  // it. `afterPass`, if set, is called at the end of every pass that draws into the surface,
  // outside the pass: the x360 fixed-point clamp and 7e3 rounding (GpuTargets::clampFixedPoint,
  // quantiseFloat7e3), the render backend's store of what the shaders wrote.
  struct SurfaceTextures {
    std::vector<rhi::TextureHandle> attachment;  // the attachment and its per-layer views
    rhi::TextureHandle bits, readView, resolved;
    std::vector<rhi::TextureHandle> resolvedViews;
  };
  uint32_t registerSurface(uint32_t plan, const PhysicalTarget& target, uint32_t width, uint32_t height,
                           const SurfaceTextures& textures, std::function<void()> afterPass = {});
  void forgetPlan(uint32_t plan);
  uint32_t newPlanId() { return ++plans_; }
  // The platform's resolve (or copy) of a surface into its Resolved texture.
  void resolved(uint32_t surface, const ResolveEvent& event);
  // The value counters the platform's passes count into (created on first use); null when the
  // device counts no values.
  TexelCounters* counters();
  // The label of the technique pass that last drew into `surface` (for counted values).
  std::string lastPassOf(uint32_t surface) const;
  // "pass: texture" for every attachment the technique created itself rather than through the
  // platform's plan (see above), each once, sorted.
  const std::set<std::string>& unplannedAttachments() const { return unplanned_; }

  // --- the technique's calls -----------------------------------------------------------------
  rhi::TextureHandle createTexture(const rhi::TextureDesc& d) override;
  rhi::TextureHandle createTextureView(const rhi::TextureViewDesc& d) override;
  void destroy(rhi::TextureHandle h) override;
  rhi::SamplerHandle createSampler(const rhi::SamplerDesc& d) override;
  void destroy(rhi::SamplerHandle h) override;
  rhi::ShaderHandle createShader(const rhi::ShaderDesc& d) override;
  void destroy(rhi::ShaderHandle h) override;
  rhi::PipelineHandle createPipeline(const rhi::PipelineDesc& d) override;
  void destroy(rhi::PipelineHandle h) override;
  rhi::ComputePipelineHandle createComputePipeline(const rhi::ComputePipelineDesc& d) override;
  void destroy(rhi::ComputePipelineHandle h) override;
  using ForwardingDevice::destroy;
  void copyTexture(rhi::TextureHandle src, rhi::TextureHandle dst, const rhi::ReadbackRegion& s = {},
                   const rhi::ReadbackRegion& d = {}) override;
  void beginPass(const rhi::PassDesc& d) override;
  void endPass() override;
  void setPipeline(rhi::PipelineHandle h) override;
  void setViewport(const rhi::Viewport& vp) override;
  void setComputePipeline(rhi::ComputePipelineHandle h) override;
  void setBindings(std::span<const rhi::ResourceBinding> bindings) override;
  void pushConstants(const void* data, uint32_t size) override;
  void draw(uint32_t vertexCount, uint32_t instanceCount = 1, uint32_t firstVertex = 0,
            uint32_t firstInstance = 0) override;
  void drawIndexed(uint32_t indexCount, uint32_t instanceCount = 1, uint32_t firstIndex = 0, int32_t vertexOffset = 0,
                   uint32_t firstInstance = 0) override;
  void dispatch(uint32_t x, uint32_t y = 1, uint32_t z = 1) override;

 private:
  struct TextureRef {
    uint32_t surface = 0;  // 0: not a platform target
    SurfaceView view = SurfaceView::Attachment;
  };
  struct PipelineInfo;
  struct SurfaceRecord {
    Surface surface;
    std::function<void()> afterPass;
    std::string lastPass;
  };
  TextureUse use(rhi::TextureHandle texture) const;
  // The draw's or dispatch's state for the rules; null pipeline: none bound.
  bool drawState(bool compute, DrawState* out) const;
  void checkDraw(uint32_t vertices, uint32_t instances);
  void checkDispatch();
  // The platform's own passes (resolves, stores) bind and push on the host device too: before
  // the technique's next draw or dispatch its bindings and push constants are sent again.
  void restoreHostState();
  // Runs a rule callback and stamps the pass and pipeline on what it reported.
  template <class F>
  void run(const std::string& pipeline, F&& rule);

  PlatformId platform_;
  PlatformParams params_;
  float offset_ = 0;
  bool countValues_ = true;
  rhi::DeviceInfo info_;
  std::unique_ptr<PlatformRules> rules_;
  std::unique_ptr<PlatformRules> capabilityRules_;
  std::unique_ptr<TexelCounters> counters_;
  DiagnosticList diagnostics_;
  uint32_t plans_ = 0, nextSurface_ = 0;
  std::map<uint32_t, SurfaceRecord> surfaces_;   // by surface id
  std::map<uint32_t, TextureRef> platformTextures_;  // texture id -> surface and view
  std::map<uint32_t, std::string> ownTextures_;  // created through this device: id -> label
  std::map<uint32_t, uint32_t> viewRoots_;       // view id -> the texture it was made of
  std::map<uint32_t, rhi::SamplerDesc> samplers_;
  std::map<uint32_t, ShaderUse> shaders_;
  std::map<uint32_t, std::shared_ptr<PipelineInfo>> pipelines_, computePipelines_;
  std::set<std::string> unplanned_;
  std::set<uint32_t> renderedOwn_;  // roots of textures of the technique's own that a pass rendered into
  // Mirrored state.
  bool inPass_ = false;
  PassState pass_;
  uint32_t pipeline_ = 0, computePipeline_ = 0;
  float viewportX_ = 0, viewportY_ = 0;  // as the technique set it
  std::map<std::pair<uint32_t, uint32_t>, rhi::ResourceBinding> bindings_;  // (binding, element)
  std::vector<uint8_t> pushed_;                                            // the last push constants
  bool hostStateChanged_ = false;
  std::map<uint32_t, std::function<void()>> afterPass_;  // surfaces drawn into in this pass
};

// The device under `device` when it is a PlatformDevice, else `device` itself.
rhi::Device& hostDevice(rhi::Device& device);
// `device` as a PlatformDevice, or null.
PlatformDevice* asPlatformDevice(rhi::Device& device);

}  // namespace parity::platforms
