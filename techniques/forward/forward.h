// Forward shading (thesis §3.1.3 and its single-pass variant): every mesh is drawn once and its
// fragment shader sums ambient, the directional light and all point/spot lights.
#pragma once

#include <memory>

#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace parity::techniques {

class ForwardSinglePass : public Technique {
 public:
  std::string name() const override { return "forward"; }
  std::vector<PassInfo> passes() const override;
  std::vector<platforms::LogicalTarget> logicalTargets(const RenderSettings& settings) const override;
  void prepare(rhi::Device& device, const RenderSettings& settings) override;
  rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) override;
  std::vector<NamedTarget> targets() const override;
  void release(rhi::Device& device) override;

 private:
  RenderSettings settings_;
  std::unique_ptr<ShaderLibrary> shaders_;
  rhi::PipelineHandle pipeline_;
  std::unique_ptr<PlannedTargets> targets_;
};

}  // namespace parity::techniques
