// Unlit albedo: the scene drawn once, each fragment its material's diffuse colour (the texture
// applied), no light. Its image is what deferred shading's geometry pass stores as
// "gbuffer.diffuse", which is the independent evidence for its goldens (golden/manifest.json).
#pragma once

#include <memory>

#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace albedo {

class UnlitAlbedo : public parity::techniques::Technique {
 public:
  std::string name() const override { return "unlit-albedo"; }
  std::vector<parity::techniques::PassInfo> passes() const override;
  std::vector<parity::platforms::LogicalTarget> logicalTargets(
      const parity::techniques::RenderSettings& settings) const override;
  void prepare(parity::rhi::Device& device, const parity::techniques::RenderSettings& settings) override;
  parity::rhi::TextureHandle render(parity::rhi::Device& device, parity::scene::SceneGpu& scene,
                                    const parity::scene::Camera& camera) override;
  std::vector<parity::techniques::NamedTarget> targets() const override;
  void release(parity::rhi::Device& device) override;

 private:
  parity::techniques::RenderSettings settings_;
  std::unique_ptr<parity::techniques::ShaderLibrary> shaders_;
  parity::rhi::PipelineHandle pipeline_;
  std::unique_ptr<parity::techniques::PlannedTargets> targets_;
};

}  // namespace albedo
