#include "techniques/forward_multipass/forward_multipass.h"

namespace parity::techniques {

std::vector<PassInfo> ForwardMultiPass::passes() const {
  return {{"ambient+directional", "ambient light pass and directional light pass over the camera visibility list",
           {"color", "depth"}},
          {"lights", "one pass per point/spot light over its visibility light list, added to the colour target",
           {"color", "depth"}}};
}

std::vector<platforms::LogicalTarget> ForwardMultiPass::logicalTargets(const RenderSettings& settings) const {
  return {outputColorTarget(settings, "ambient+directional"), sceneDepthTarget("ambient+directional")};
}

void ForwardMultiPass::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  shaders_ = std::make_unique<ShaderLibrary>(device);
  targets_ = std::make_unique<PlannedTargets>(device, settings, logicalTargets(settings), name());
  const rhi::ShaderCompileOptions options = targets_->shaderOptions(settings);
  rhi::ShaderHandle vs = shaders_->load("forward/forward.vert", options);

  rhi::PipelineDesc p;
  p.vertexShader = vs;
  p.fragmentShader = shaders_->load("forward/forward_ambient_directional.frag", options);
  scene::SceneGpu::describeVertexLayout(p);
  p.raster.cull = rhi::CullMode::Back;
  p.depthStencil.depthCompare = rhi::CompareOp::Less;
  p.depthStencil.depthWrite = true;
  p.colorTargets[0].format = targets_->format(kOutputColor);
  p.colorTargetCount = 1;
  p.depthStencilFormat = targets_->format(kSceneDepth);
  p.label = "forward-multipass ambient+directional";
  ambientPipeline_ = device.createPipeline(p);

  // Per-light passes: the same vertex shader, so the same depths; only the nearest surface
  // (depth equal to the first pass's) is lit, and the light is added.
  p.fragmentShader = shaders_->load("forward/forward_light.frag", options);
  p.depthStencil.depthCompare = rhi::CompareOp::Equal;
  p.depthStencil.depthWrite = false;
  rhi::BlendState& b = p.colorTargets[0].blend;
  b.enabled = true;
  b.srcColor = b.dstColor = rhi::BlendFactor::One;
  b.srcAlpha = b.dstAlpha = rhi::BlendFactor::One;
  p.label = "forward-multipass light";
  lightPipeline_ = device.createPipeline(p);
  if (!ambientPipeline_ || !lightPipeline_) throw TechniqueError("forward-multipass: the device rejected a pipeline");

}

rhi::TextureHandle ForwardMultiPass::render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) {
  float aspect = static_cast<float>(settings_.width) / static_cast<float>(settings_.height);
  scene.setCamera(camera, aspect);
  const scene::Scene& s = scene.scene();
  lists_ = scene::buildLightLists(s, camera.viewProjection(aspect));

  rhi::PassDesc pass;
  pass.colors[0].texture = targets_->attachment(kOutputColor);
  pass.colors[0].clearColor = {0.0f, 0.0f, 0.0f, 1.0f};
  pass.depthStencil.texture = targets_->attachment(kSceneDepth);
  pass.label = "ambient+directional";
  device.beginPass(pass);
  device.setPipeline(ambientPipeline_);
  for (uint32_t m : lists_.visible) scene.drawMesh(s.meshes[m]);
  device.endPass();

  // Lights in scene order, as the single-pass shader sums them. Point and spot lights share the
  // shader (it branches on the light's type), so the thesis's separate loops are one here.
  for (uint32_t l = 0; l < lists_.perLight.size(); ++l) {
    if (lists_.perLight[l].empty()) continue;
    rhi::PassDesc lightPass;
    lightPass.colors[0].texture = targets_->attachment(kOutputColor);
    lightPass.colors[0].load = rhi::LoadOp::Load;
    lightPass.depthStencil.texture = targets_->attachment(kSceneDepth);
    lightPass.depthStencil.load = rhi::LoadOp::Load;
    lightPass.label = "light " + std::to_string(l);
    device.beginPass(lightPass);
    device.setPipeline(lightPipeline_);
    for (uint32_t m : lists_.perLight[l]) scene.drawMesh(s.meshes[m], l);
    device.endPass();
  }
  return targets_->present();
}

std::vector<NamedTarget> ForwardMultiPass::targets() const {
  if (!targets_) return {};
  return {{kOutputColor, targets_->readTexture(kOutputColor)}, {kSceneDepth, targets_->attachment(kSceneDepth)}};
}

void ForwardMultiPass::release(rhi::Device& device) {
  device.destroy(ambientPipeline_);
  device.destroy(lightPipeline_);
  targets_.reset();
  shaders_.reset();
}

}  // namespace parity::techniques
