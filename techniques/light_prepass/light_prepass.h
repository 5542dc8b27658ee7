// Deferred lighting / light pre-pass (RTR blog "Deferred lighting approaches"; Engel's light
// pre-pass with the specular power stored, as the blog recommends):
//   1. geometry pass: the n/m buffer, the normal and the specular power m (plus depth);
//   2. light pass: the directional light over the full screen, then a light volume per point and
//      spot light, accumulating diffuse and specular light separately (no material colours);
//   3. second geometry pass: each mesh applies its diffuse and specular colours (and ambient) to
//      the accumulated light.
// Two accumulation layouts: 6 channels (diffuse RGB and specular RGB in two targets,
// "light-prepass") and 4 channels (diffuse RGB + specular luminance in A, the specular colour
// reconstructed from the diffuse chromaticity as the blog's appendix A does, "light-prepass-4ch").
#pragma once

#include <memory>

#include "platforms/platform_layer.h"
#include "techniques/deferred/light_volume_pass.h"
#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace parity::techniques {

class LightPrePass : public Technique {
 public:
  explicit LightPrePass(bool fourChannel) : fourChannel_(fourChannel) {}
  std::string name() const override { return fourChannel_ ? "light-prepass-4ch" : "light-prepass"; }
  std::vector<PassInfo> passes() const override;
  std::vector<platforms::LogicalTarget> logicalTargets(const RenderSettings& settings) const override;
  void prepare(rhi::Device& device, const RenderSettings& settings) override;
  rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) override;
  std::vector<NamedTarget> targets() const override;
  void release(rhi::Device& device) override;

 private:
  bool fourChannel_;
  RenderSettings settings_;
  std::unique_ptr<ShaderLibrary> shaders_;
  std::unique_ptr<PlannedTargets> targets_;
  std::unique_ptr<LightVolumePass> volumes_;
  rhi::PipelineHandle nmPipeline_, directionalPipeline_, materialPipeline_;
  // The light pass tests against the scene's depth while its shaders read it; the test runs on
  // this copy, so that no pass samples its own depth attachment.
};

}  // namespace parity::techniques
