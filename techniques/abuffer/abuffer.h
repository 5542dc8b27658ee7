// Order-independent transparency with the stencil-routed A-buffer (Myers & Bavoil 2007; Ferko
// 2012 §4.1): opaque meshes are shaded first; every sample of a 4x MSAA stencil buffer gets its
// own routing value, so each translucent fragment of a pixel lands in its own sample; a
// full-screen pass sorts a pixel's samples by depth and blends them back to front. Up to
// (samples) layers per pixel are exact; further layers are dropped. Depth peeling, the reference,
// peels the same number of layers one pass each and blends them the same way.
//
// On a platform: the routing stencil, fragment colours (Rgba16Hdr) and depths (R32Float) are 4x
// targets of the plan, read sample by sample (x360 resolves each sample into an array layer, a
// bit copy of k_32_FLOAT depths: lossless; the colours take the platform's Rgba16Hdr storage).
// RSX cannot bind the store pass's two formats at once (E_MRT_FORMAT_MISMATCH on ps3).
#pragma once

#include <memory>
#include <vector>

#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace parity::techniques {

enum class TransparencyMode { StencilRouted, DepthPeeling };

class OrderIndependentTransparency : public Technique {
 public:
  explicit OrderIndependentTransparency(TransparencyMode mode) : mode_(mode) {}
  std::string name() const override { return mode_ == TransparencyMode::StencilRouted ? "abuffer" : "depth-peeling"; }
  std::vector<PassInfo> passes() const override;
  std::vector<platforms::LogicalTarget> logicalTargets(const RenderSettings& settings) const override;
  // Without 4x MSAA (rhi::Capabilities::maxSamples: DX10 feature level 10.0 makes it optional)
  // the A-buffer's port peels the layers instead, as its reference does.
  std::vector<PortPath> portPaths(const rhi::Capabilities& caps) const override;
  void prepare(rhi::Device& device, const RenderSettings& settings) override;
  rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) override;
  std::vector<NamedTarget> targets() const override;
  void release(rhi::Device& device) override;

  static constexpr uint32_t kLayers = 4;  // the A-buffer's samples per pixel; peeling passes

 private:
  void drawMeshes(rhi::Device& device, scene::SceneGpu& scene, bool translucent) const;
  // What runs on a device with these capabilities (the port's path where the A-buffer cannot).
  TransparencyMode runs(const rhi::Capabilities& caps) const;

  TransparencyMode mode_;
  TransparencyMode running_ = TransparencyMode::StencilRouted;
  RenderSettings settings_;
  std::unique_ptr<ShaderLibrary> shaders_;
  rhi::PipelineHandle opaque_, route_, store_, resolve_, peel_, composite_;
  static constexpr const char* kOpaqueColor = "opaque.color";
  static constexpr const char* kOpaqueDepth = "opaque.depth";
  static constexpr const char* kNoLayerDepth = "peel.depth.none";  // "previous layer" of the first peel
  static std::string peelColor(uint32_t k) { return "peel.layer" + std::to_string(k); }
  static std::string peelDepth(uint32_t k) { return "peel.depth" + std::to_string(k); }
  // The A-buffer: the 4x routing stencil, and each fragment's colour and depth in its own sample.
  static constexpr const char* kRouting = "abuffer.stencil";
  static constexpr const char* kFragmentColors = "abuffer.colors";
  static constexpr const char* kFragmentDepths = "abuffer.depths";
  std::unique_ptr<PlannedTargets> targets_;  // every target of the technique (logicalTargets)
};

}  // namespace parity::techniques
