// Multi-pass forward shading (thesis §3.1.3): an ambient + directional pass over the camera
// visibility list, then one additive pass per point/spot light over that light's visibility
// light list (sphere–AABB and cone–AABB tests, §3.1.1, scene/culling.h).
#pragma once

#include <memory>

#include "scene/culling.h"
#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace parity::techniques {

class ForwardMultiPass : public Technique {
 public:
  std::string name() const override { return "forward-multipass"; }
  std::vector<PassInfo> passes() const override;
  std::vector<platforms::LogicalTarget> logicalTargets(const RenderSettings& settings) const override;
  void prepare(rhi::Device& device, const RenderSettings& settings) override;
  rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) override;
  std::vector<NamedTarget> targets() const override;
  void release(rhi::Device& device) override;

  // The lists the last render() drew with.
  const scene::LightLists& lightLists() const { return lists_; }

 private:
  RenderSettings settings_;
  std::unique_ptr<ShaderLibrary> shaders_;
  rhi::PipelineHandle ambientPipeline_, lightPipeline_;
  std::unique_ptr<PlannedTargets> targets_;
  scene::LightLists lists_;
};

}  // namespace parity::techniques
