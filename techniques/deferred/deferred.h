// Deferred shading (thesis §3.1.4; RTR blog "Deferred lighting approaches", classic deferred
// shading): a geometry pass fills the G-buffer (depth, normals, diffuse colour, specular colour
// and power), a full-screen pass adds ambient and the directional light, light volumes add each
// point and spot light into an HDR accumulation target, and a last full-screen pass turns the
// accumulated light into the final colour.
//
// deferred-shadows adds the thesis's shadowed variant (§3.1, the "big lights with shadows" of
// chapter 4): the directional light's map before the geometry pass, and for each light that
// casts shadows its map (techniques/effects/shadow_maps.h) rendered between light volumes, so
// the lighting pass breaks there; unshadowed lights are drawn in the first lighting pass.
//
// Every target is a logical target of the platform layer (planTargets / GpuTargets): on ps3 and
// x360 the normals go through the console's packing and resolve, depth through its depth read.
#pragma once

#include <memory>

#include "platforms/platform_layer.h"
#include "techniques/deferred/light_volume_pass.h"
#include "techniques/effects/shadow_maps.h"
#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace parity::techniques {

class DeferredShading : public Technique {
 public:
  // shadowSettings: the map sizes (directionalSize 0: forward-shadows' rule, 2048 from 1280
  // pixels wide, else 1024); its bindings are the deferred shaders' 11 and 12 whatever it says.
  explicit DeferredShading(bool shadows = false, effects::ShadowSettings shadowSettings = {0, 512})
      : withShadows_(shadows), shadowSettings_(shadowSettings) {}
  std::string name() const override { return withShadows_ ? "deferred-shadows" : "deferred"; }
  std::vector<PassInfo> passes() const override;
  std::vector<platforms::LogicalTarget> logicalTargets(const RenderSettings& settings) const override;
  std::vector<SizedTargets> furtherTargetPlans(const RenderSettings& settings) const override;
  void prepare(rhi::Device& device, const RenderSettings& settings) override;
  rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) override;
  std::vector<NamedTarget> targets() const override;
  void release(rhi::Device& device) override;

  // Lights drawn in the last frame with the camera inside their volume (back faces).
  uint32_t lightsDrawnFromInside() const { return volumes_ ? volumes_->insideCount() : 0; }

 private:
  bool withShadows_;
  effects::ShadowSettings shadowSettings_;
  // The shadow settings at this output size (the directional map's size follows it when unset).
  effects::ShadowSettings shadowSettingsFor(const RenderSettings& settings) const;
  RenderSettings settings_;
  std::unique_ptr<ShaderLibrary> shaders_;
  effects::ShadowMaps shadowMaps_;
  std::unique_ptr<PlannedTargets> targets_;
  std::unique_ptr<LightVolumePass> volumes_;
  rhi::PipelineHandle geometryPipeline_, ambientDirectionalPipeline_, composePipeline_;
  // The light passes test against the scene's depth while their shaders read it; the test runs
  // on this copy, so that no pass samples its own depth attachment.
};

}  // namespace parity::techniques
