// A technique's render targets as its platform plans them: the logical targets it declares
// (Technique::logicalTargets), planned by platforms::planTargets and created by
// platforms::GpuTargets, so that each platform decides the real formats, EDRAM placement,
// resolves and diagnostics. Every technique allocates its frame colour and depth here, so no
// technique renders a console platform through the reference's targets.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "platforms/platform_layer.h"
#include "rhi/rhi.h"
#include "techniques/technique.h"

namespace parity::techniques {

inline constexpr const char* kOutputColor = "color";
inline constexpr const char* kSceneDepth = "depth";

// The frame's final colour, the image the harness reads, rendered by `pass`.
platforms::LogicalTarget outputColorTarget(const RenderSettings& settings, const std::string& pass);
// Scene depth rendered by `pass`; `readLater` when a later pass samples it, `stencil` when the
// technique uses the stencil.
platforms::LogicalTarget sceneDepthTarget(const std::string& pass, bool readLater = false, bool stencil = false);

class PlannedTargets {
 public:
  // Plans `logical` at `extent` (the output size when empty) and creates every target; throws
  // TechniqueError naming `technique` and the target that could not be created.
  PlannedTargets(rhi::Device& device, const RenderSettings& settings, const std::vector<platforms::LogicalTarget>& logical,
                 const std::string& technique, TargetExtent extent = {});

  const platforms::TargetPlan& plan() const { return targets_->plan(); }
  platforms::GpuTargets& gpu() { return *targets_; }
  rhi::TextureHandle attachment(const std::string& name) const { return targets_->attachment(name); }
  rhi::TextureHandle readTexture(const std::string& name) const { return targets_->readTexture(name); }
  // The host format `name` is rendered into (what its pipelines must name).
  rhi::Format format(const std::string& name) const;
  // The technique's shader options plus the plan's platform defines.
  rhi::ShaderCompileOptions shaderOptions(const RenderSettings& settings) const;
  // Records the platform's resolve of `name` (x360: EDRAM -> texture; dx10/ps3: the depth copy);
  // `rect` resolves a rectangle of it on x360 (GpuTargets::resolve).
  void resolve(const std::string& name, uint32_t sourceSamples = 1, const rhi::Rect& rect = {});
  // Resolves the output colour and returns the texture the harness reads (on x360 the resolved
  // front buffer, elsewhere the attachment itself).
  rhi::TextureHandle present(const std::string& name = kOutputColor);

 private:
  std::string technique_;
  std::unique_ptr<platforms::GpuTargets> targets_;
};

}  // namespace parity::techniques
