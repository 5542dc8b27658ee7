// Inferred lighting (Kircher & Lawrance 2009): geometry pass and light pass at a reduced
// resolution, material pass at full resolution that "infers" its lighting from the L-buffer
// with the discontinuity sensitive filter (DSF, §3); alpha polygons take part through 2x2
// stipple patterns (§4). The G-buffers and the L-buffer are logical targets, so on ps3 and x360
// they go through the console's packing, EDRAM and resolve paths (§5).
#pragma once

#include <memory>
#include <vector>

#include "techniques/common/light_volumes.h"
#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace parity::techniques {

class InferredLighting : public Technique {
 public:
  // Resolution of the G-buffer and L-buffer relative to the output, per axis (the paper: 800x450
  // for 1280x720, 0.625). Each size is floor(output size * scale), at least 1: 320x180 -> 200x112.
  // A define INFERRED_LBUFFER_SCALE=<float> in RenderSettings::shaderOptions overrides it, so
  // that the harness and renderFrameTexels can choose it without a handle on the object.
  static constexpr float kDefaultScale = 0.625f;
  void setScale(float scale) { scale_ = scale; }
  // false: plain bilinear upsampling of the L-buffer instead of the DSF (for measuring what the
  // filter buys). The define INFERRED_PLAIN_BILINEAR in shaderOptions does the same.
  void setDiscontinuityFilter(bool on) { dsfFilter_ = on; }
  // The reduced size for an output size and scale (the rounding rule above).
  static uint32_t reducedSize(uint32_t size, float scale);

  std::string name() const override { return "inferred"; }
  std::vector<PassInfo> passes() const override;
  std::vector<platforms::LogicalTarget> logicalTargets(const RenderSettings& settings) const override;
  // The reduced size (reducedSize of each axis at the effective scale).
  TargetExtent logicalTargetExtent(const RenderSettings& settings) const override;
  std::vector<SizedTargets> furtherTargetPlans(const RenderSettings& settings) const override;  // the output
  void prepare(rhi::Device& device, const RenderSettings& settings) override;
  rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) override;
  std::vector<NamedTarget> targets() const override;
  void release(rhi::Device& device) override;

 private:
  float effectiveScale(const RenderSettings& settings) const;
  void uploadScene(rhi::Device& device, const scene::Scene& scene);
  void drawMesh(rhi::Device& device, scene::SceneGpu& scene, uint32_t meshIndex, uint32_t stipplePattern);

  RenderSettings settings_;
  float scale_ = kDefaultScale;
  bool dsfFilter_ = true;
  uint32_t reducedWidth_ = 0, reducedHeight_ = 0;
  bool stencilVolumes_ = false;  // depth-fail stencil optimisation available (see prepare())

  std::unique_ptr<ShaderLibrary> shaders_;
  std::unique_ptr<PlannedTargets> gpuTargets_;
  std::unique_ptr<LightVolumes> volumes_;
  rhi::PipelineHandle geometryOpaque_, geometryAlpha_, globalLightPipeline_, lightPipeline_, stencilVolume_, materialOpaque_, materialAlpha_;
  std::unique_ptr<PlannedTargets> output_;  // the output colour and full-size depth of the material pass
  rhi::BufferHandle params_;

  // The scene's triangles with a normal-group ID per vertex (vertices are split where triangles
  // of different groups share them), uploaded once per scene.
  const scene::Scene* uploadedScene_ = nullptr;
  rhi::BufferHandle vertices_, indices_;
};

}  // namespace parity::techniques
