// Deferred shading with screen-space ambient occlusion (Ferko 2012, §5.1-5.2): the deferred
// technique renders the lit image; a geometry pass writes the depth and view-space normals SSAO
// reads and the diffuse colour of the ambient term (logical targets of the platform layer, so
// console depth reads and resolves apply); the occlusion is computed at reduced resolution,
// blurred by a separable cross-bilateral filter, and attenuates the ambient term only, as in
// Ferko's pipeline: direct light is left as the deferred technique computed it. The occlusion
// chain is an R8Unorm plan at the reduced size (8 bits on every platform, the reference too:
// lossless across platforms; resolved out of EDRAM after each pass on x360).
#pragma once

#include <memory>

#include "techniques/deferred/deferred.h"
#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace parity::techniques {

class DeferredSsao : public Technique {
 public:
  struct Params {
    float radius = 0.5f;      // sampling sphere radius r, world units
    uint32_t reduction = 2;   // the occlusion target is (w / reduction) x (h / reduction)
    int blurRadius = 6;       // taps each side of the separable blur
  };
  DeferredSsao() = default;
  explicit DeferredSsao(Params params) : params_(params) {}
  std::string name() const override { return "deferred-ssao"; }
  std::vector<PassInfo> passes() const override;
  std::vector<platforms::LogicalTarget> logicalTargets(const RenderSettings& settings) const override;
  std::vector<SizedTargets> furtherTargetPlans(const RenderSettings& settings) const override;  // the occlusion chain
  void prepare(rhi::Device& device, const RenderSettings& settings) override;
  rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) override;
  std::vector<NamedTarget> targets() const override;
  void release(rhi::Device& device) override;

 private:
  Params params_;
  RenderSettings settings_;
  DeferredShading lit_;
  std::unique_ptr<ShaderLibrary> shaders_;
  std::unique_ptr<PlannedTargets> targets_;
  // The occlusion chain at the reduced resolution (a plan of its own: its own size).
  std::unique_ptr<PlannedTargets> occlusion_;
  rhi::PipelineHandle geometry_, ssao_, blur_, apply_;
  rhi::TextureHandle randomVectors_;
  rhi::SamplerHandle linear_;
  rhi::BufferHandle passParams_;  // three uniform slots: SSAO, blur horizontal, blur vertical
  uint32_t aoWidth_ = 0, aoHeight_ = 0;
};

}  // namespace parity::techniques
