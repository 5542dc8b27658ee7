#include "techniques/forward_shadows/forward_shadows.h"

namespace parity::techniques {

std::vector<PassInfo> ForwardShadows::passes() const {
  return {{"shadow directional", "orthographic shadow map of the directional light over the scene's bounds", {"shadow.directional"}},
          {"base", "ambient + directional light with PCF shadow lookups; lays down depth", {"color", "depth"}},
          {"shadow local", "per shadow-casting light: its spot map or six point-cube faces, reused by the next light",
           {"shadow.local"}},
          {"light", "per local light: geometry again with depth EQUAL, added to the colour", {"color"}}};
}

std::vector<platforms::LogicalTarget> ForwardShadows::logicalTargets(const RenderSettings& settings) const {
  return {outputColorTarget(settings, "base"), sceneDepthTarget("base")};
}

effects::ShadowSettings ForwardShadows::shadowSettingsFor(const RenderSettings& settings) const {
  effects::ShadowSettings s = shadowSettings_;
  if (s.directionalSize == 0) s.directionalSize = settings.width >= 1280 ? 2048 : 1024;
  return s;
}

std::vector<Technique::SizedTargets> ForwardShadows::furtherTargetPlans(const RenderSettings& settings) const {
  return effects::ShadowMaps::targetPlans(shadowSettingsFor(settings));
}

void ForwardShadows::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  shaders_ = std::make_unique<ShaderLibrary>(device);
  targets_ = std::make_unique<PlannedTargets>(device, settings, logicalTargets(settings), name());
  const rhi::ShaderCompileOptions options = targets_->shaderOptions(settings);
  shadows_.prepare(device, *shaders_, shadowSettingsFor(settings), settings);

  rhi::PipelineDesc p;
  p.vertexShader = shaders_->load("forward/forward.vert", options);
  p.fragmentShader = shaders_->load("effects/forward_shadows_base.frag", options);
  scene::SceneGpu::describeVertexLayout(p);
  p.raster.cull = rhi::CullMode::Back;
  p.depthStencil.depthCompare = rhi::CompareOp::Less;
  p.depthStencil.depthWrite = true;
  p.colorTargets[0].format = targets_->format(kOutputColor);
  p.colorTargetCount = 1;
  p.depthStencilFormat = targets_->format(kSceneDepth);
  p.label = "forward-shadows base";
  base_ = device.createPipeline(p);
  p.fragmentShader = shaders_->load("effects/forward_shadows_light.frag", options);
  p.depthStencil.depthCompare = rhi::CompareOp::Equal;  // the same vertices give the same depths
  p.depthStencil.depthWrite = false;
  p.colorTargets[0].blend.enabled = true;
  p.colorTargets[0].blend.srcColor = rhi::BlendFactor::One;
  p.colorTargets[0].blend.dstColor = rhi::BlendFactor::One;
  p.colorTargets[0].blend.srcAlpha = rhi::BlendFactor::Zero;
  p.colorTargets[0].blend.dstAlpha = rhi::BlendFactor::One;
  p.label = "forward-shadows light";
  light_ = device.createPipeline(p);
  if (!base_ || !light_) throw TechniqueError("forward-shadows: the device rejected a shading pipeline");

}

rhi::TextureHandle ForwardShadows::render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) {
  scene.setCamera(camera, static_cast<float>(settings_.width) / static_cast<float>(settings_.height));
  const scene::Scene& sc = scene.scene();
  shadows_.beginFrame(device, scene);
  shadows_.renderDirectional(device, scene);

  rhi::PassDesc pass;
  pass.colors[0].texture = targets_->attachment(kOutputColor);
  pass.colors[0].clearColor = {0.0f, 0.0f, 0.0f, 1.0f};
  pass.depthStencil.texture = targets_->attachment(kSceneDepth);
  pass.label = "base";
  device.beginPass(pass);
  device.setPipeline(base_);
  shadows_.bindDirectional(device);
  for (const scene::Mesh& mesh : sc.meshes) scene.drawMesh(mesh);
  device.endPass();

  for (uint32_t i = 0; i < sc.lights.size(); ++i) {
    if (sc.lights[i].castsShadows) shadows_.renderLocal(device, scene, i);
    rhi::PassDesc lp;
    lp.colors[0].texture = targets_->attachment(kOutputColor);
    lp.colors[0].load = rhi::LoadOp::Load;
    lp.depthStencil.texture = targets_->attachment(kSceneDepth);
    lp.depthStencil.load = rhi::LoadOp::Load;
    lp.label = "light";
    device.beginPass(lp);
    device.setPipeline(light_);
    shadows_.bindLocal(device, i);
    for (const scene::Mesh& mesh : sc.meshes) scene.drawMesh(mesh, i);
    device.endPass();
  }
  return targets_->present();
}

std::vector<NamedTarget> ForwardShadows::targets() const {
  if (!targets_) return {};
  return {{"shadow.directional", shadows_.directionalMap()},
          {kOutputColor, targets_->readTexture(kOutputColor)},
          {kSceneDepth, targets_->attachment(kSceneDepth)},
          {"shadow.local", shadows_.localMap()}};
}

void ForwardShadows::release(rhi::Device& device) {
  shadows_.release(device);
  device.destroy(base_);
  device.destroy(light_);
  targets_.reset();
  shaders_.reset();
}

}  // namespace parity::techniques
