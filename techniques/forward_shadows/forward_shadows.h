// Forward shading with shadow maps (thesis §3.1): a base pass with ambient and the shadowed
// directional light, then one additive pass per local light, each light that casts shadows
// first rendering its map (techniques/effects/shadow_maps.h), which the next light reuses.
#pragma once

#include <memory>

#include "techniques/effects/shadow_maps.h"
#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace parity::techniques {

class ForwardShadows : public Technique {
 public:
  // directionalSize 0: 2048 (the thesis) for images 1280 pixels wide or more, 1024 below, which
  // keeps the CI-sized frames fast on software rasterisers.
  explicit ForwardShadows(effects::ShadowSettings shadows = {0, 512}) : shadowSettings_(shadows) {}
  std::string name() const override { return "forward-shadows"; }
  std::vector<PassInfo> passes() const override;
  std::vector<platforms::LogicalTarget> logicalTargets(const RenderSettings& settings) const override;
  std::vector<SizedTargets> furtherTargetPlans(const RenderSettings& settings) const override;
  void prepare(rhi::Device& device, const RenderSettings& settings) override;
  rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) override;
  std::vector<NamedTarget> targets() const override;
  void release(rhi::Device& device) override;

 private:
  RenderSettings settings_;
  effects::ShadowSettings shadowSettings_;
  // The shadow settings at this output size (the directional map's size follows it when unset).
  effects::ShadowSettings shadowSettingsFor(const RenderSettings& settings) const;
  std::unique_ptr<ShaderLibrary> shaders_;
  effects::ShadowMaps shadows_;
  rhi::PipelineHandle base_, light_;
  std::unique_ptr<PlannedTargets> targets_;
};

}  // namespace parity::techniques
