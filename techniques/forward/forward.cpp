#include "techniques/forward/forward.h"

#include "techniques/common/planned_targets.h"

namespace parity::techniques {

std::vector<PassInfo> ForwardSinglePass::passes() const {
  return {{"shade", "geometry drawn once; ambient + directional + every local light summed per fragment",
           {"color", "depth"}}};
}

std::vector<platforms::LogicalTarget> ForwardSinglePass::logicalTargets(const RenderSettings& settings) const {
  return {outputColorTarget(settings, "shade"), sceneDepthTarget("shade")};
}

void ForwardSinglePass::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  shaders_ = std::make_unique<ShaderLibrary>(device);
  targets_ = std::make_unique<PlannedTargets>(device, settings, logicalTargets(settings), name());
  const rhi::ShaderCompileOptions options = targets_->shaderOptions(settings);

  rhi::PipelineDesc p;
  p.vertexShader = shaders_->load("forward/forward.vert", options);
  p.fragmentShader = shaders_->load("forward/forward_single_pass.frag", options);
  scene::SceneGpu::describeVertexLayout(p);
  p.raster.cull = rhi::CullMode::Back;
  p.depthStencil.depthCompare = rhi::CompareOp::Less;
  p.depthStencil.depthWrite = true;
  p.colorTargets[0].format = targets_->format(kOutputColor);
  p.colorTargetCount = 1;
  p.depthStencilFormat = targets_->format(kSceneDepth);
  p.label = "forward shade";
  pipeline_ = device.createPipeline(p);
  if (!pipeline_) throw TechniqueError("forward: the device rejected the shading pipeline");
}

rhi::TextureHandle ForwardSinglePass::render(rhi::Device& device, scene::SceneGpu& scene,
                                             const scene::Camera& camera) {
  scene.setCamera(camera, static_cast<float>(settings_.width) / static_cast<float>(settings_.height));
  rhi::PassDesc pass;
  pass.colors[0].texture = targets_->attachment(kOutputColor);
  pass.colors[0].clearColor = {0.0f, 0.0f, 0.0f, 1.0f};
  pass.depthStencil.texture = targets_->attachment(kSceneDepth);
  pass.label = "shade";
  device.beginPass(pass);
  device.setPipeline(pipeline_);
  for (const scene::Mesh& mesh : scene.scene().meshes) scene.drawMesh(mesh);
  device.endPass();
  return targets_->present();
}

std::vector<NamedTarget> ForwardSinglePass::targets() const {
  if (!targets_) return {};
  return {{kOutputColor, targets_->readTexture(kOutputColor)}, {kSceneDepth, targets_->attachment(kSceneDepth)}};
}

void ForwardSinglePass::release(rhi::Device& device) {
  device.destroy(pipeline_);
  targets_.reset();
  shaders_.reset();
}

}  // namespace parity::techniques
