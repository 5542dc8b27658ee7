#include "techniques/light_prepass/light_prepass.h"
#include "techniques/common/pass_helpers.h"
#include "techniques/common/planned_targets.h"

#include "scene/culling.h"

namespace parity::techniques {

namespace {

const char* const kDepth = "nm.depth";
const char* const kNormals = "nm.normals";
const char* const kPower = "nm.power";
const char* const kDiffuseLight = "light.diffuse";    // 4 channels: diffuse RGB + specular luminance
const char* const kSpecularLight = "light.specular";  // 6 channels only

}  // namespace

std::vector<PassInfo> LightPrePass::passes() const {
  std::vector<std::string> light = {kDiffuseLight};
  if (!fourChannel_) light.push_back(kSpecularLight);
  return {{"geometry", "first geometry pass over the camera visibility list: the n/m buffer (normal, specular power) "
                       "and depth",
           {kDepth, kNormals, kPower}},
          {"lights",
           fourChannel_ ? "directional light full screen, then one light volume per point/spot light: diffuse light "
                          "RGB and specular luminance accumulated in four channels"
                        : "directional light full screen, then one light volume per point/spot light: diffuse and "
                          "specular light accumulated in two RGB targets",
           light},
          {"material",
           fourChannel_ ? "second geometry pass: diffuse colour x (ambient + diffuse light) + specular colour x "
                          "specular light rebuilt from the diffuse chromaticity"
                        : "second geometry pass: diffuse colour x (ambient + diffuse light) + specular colour x "
                          "specular light",
           {"color"}}};
}

std::vector<platforms::LogicalTarget> LightPrePass::logicalTargets(const RenderSettings& settings) const {
  using platforms::LogicalFormat;
  using platforms::TargetRole;
  std::vector<platforms::LogicalTarget> t = {
      {kNormals, LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"},
      {kPower, LogicalFormat::Rgba8Unorm, true, TargetRole::GBuffer, "geometry"},
      // the light volumes and the material pass test against it
      {kDepth, LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer, "geometry", 1, false, rhi::Format::RGBA8, 0,
       {"geometry", "lights", "material"}},
      {kDiffuseLight, LogicalFormat::Rgba16Hdr, true, TargetRole::LBuffer, "lights"}};
  if (!fourChannel_) t.push_back({kSpecularLight, LogicalFormat::Rgba16Hdr, true, TargetRole::LBuffer, "lights"});
  t.push_back(outputColorTarget(settings, "material"));
  return t;
}

void LightPrePass::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  const std::string label = name();
  shaders_ = std::make_unique<ShaderLibrary>(device);
  std::vector<platforms::LogicalTarget> logical = logicalTargets(settings);
  targets_ = std::make_unique<PlannedTargets>(device, settings, logical, label);
  const platforms::TargetPlan& plan = targets_->plan();
  rhi::ShaderCompileOptions options = targets_->shaderOptions(settings);
  options.defines.push_back({"PARITY_LIGHT_PREPASS_4CH", fourChannel_ ? "1" : "0"});
  const rhi::Format depthFormat = attachmentFormat(plan, kDepth);
  const uint32_t lightTargets = fourChannel_ ? 1 : 2;

  rhi::ShaderHandle sceneVs = shaders_->load("forward/forward.vert", options);
  rhi::PipelineDesc g;
  g.vertexShader = sceneVs;
  g.fragmentShader = shaders_->load("light_prepass/nm.frag", options);
  scene::SceneGpu::describeVertexLayout(g);
  g.raster.cull = rhi::CullMode::Back;
  g.depthStencil.depthCompare = rhi::CompareOp::Less;
  g.depthStencil.depthWrite = true;
  g.colorTargets[0].format = attachmentFormat(plan, kNormals);
  g.colorTargets[1].format = attachmentFormat(plan, kPower);
  g.colorTargetCount = 2;
  g.depthStencilFormat = depthFormat;
  g.label = label + " n/m";
  nmPipeline_ = device.createPipeline(g);

  rhi::PipelineDesc light;
  light.colorTargets[0].format = attachmentFormat(plan, kDiffuseLight);
  if (!fourChannel_) light.colorTargets[1].format = attachmentFormat(plan, kSpecularLight);
  for (uint32_t i = 0; i < lightTargets; ++i) enableAdditiveBlending(light.colorTargets[i]);
  light.colorTargetCount = lightTargets;
  light.depthStencilFormat = depthFormat;

  rhi::PipelineDesc d = light;
  d.vertexShader = shaders_->load("deferred/fullscreen_far.vert", options);
  d.fragmentShader = shaders_->load("light_prepass/directional.frag", options);
  d.depthStencil.depthCompare = rhi::CompareOp::Greater;  // only pixels the geometry pass covered
  d.label = label + " directional";
  directionalPipeline_ = device.createPipeline(d);

  rhi::PipelineDesc v = light;
  v.vertexShader = shaders_->load("deferred/light_volume.vert", options);
  v.fragmentShader = shaders_->load("light_prepass/light.frag", options);
  v.label = label + " light volume";
  volumes_ = std::make_unique<LightVolumePass>(device, v);

  // Second geometry pass: the same vertex shader as the first, so the same depths; EQUAL keeps
  // only the visible surface.
  rhi::PipelineDesc m = g;
  m.fragmentShader = shaders_->load("light_prepass/material.frag", options);
  m.depthStencil.depthCompare = rhi::CompareOp::Equal;
  m.depthStencil.depthWrite = false;
  m.colorTargets = {};
  m.colorTargets[0].format = attachmentFormat(plan, kOutputColor);
  m.colorTargetCount = 1;
  m.label = label + " material";
  materialPipeline_ = device.createPipeline(m);
  if (!nmPipeline_ || !directionalPipeline_ || !volumes_->ok() || !materialPipeline_)
    throw TechniqueError(label + ": the device rejected a pipeline");

}

rhi::TextureHandle LightPrePass::render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) {
  const std::string label = name();
  const float aspect = static_cast<float>(settings_.width) / static_cast<float>(settings_.height);
  scene.setCamera(camera, aspect);
  const scene::Scene& s = scene.scene();
  const scene::LightLists lists = scene::buildLightLists(s, camera.viewProjection(aspect));
  volumes_->upload(s);

  // 1. n/m buffer.
  rhi::PassDesc g;
  g.colors[0].texture = targets_->attachment(kNormals);
  g.colors[1].texture = targets_->attachment(kPower);
  g.depthStencil.texture = targets_->attachment(kDepth);
  g.label = "geometry";
  device.beginPass(g);
  device.setPipeline(nmPipeline_);
  for (uint32_t m : lists.visible) scene.drawMesh(s.meshes[m]);
  device.endPass();
  for (const char* t : {kNormals, kPower, kDepth})
    targets_->resolve(t);

  // 2. Light accumulation.
  const std::vector<rhi::ResourceBinding> nm = {sampled(4, targets_->readTexture(kDepth)),
                                                sampled(5, targets_->readTexture(kNormals)),
                                                sampled(6, targets_->readTexture(kPower))};
  rhi::PassDesc l;
  l.colors[0].texture = targets_->attachment(kDiffuseLight);
  if (!fourChannel_) l.colors[1].texture = targets_->attachment(kSpecularLight);
  l.depthStencil.texture = targets_->attachment(kDepth);  // sampled through its resolve or copy
  l.depthStencil.load = rhi::LoadOp::Load;
  l.label = "lights";
  device.beginPass(l);
  device.setPipeline(directionalPipeline_);
  device.setBindings(withSceneBuffers(nm, scene));
  drawFullScreenTriangle(device);
  volumes_->draw(scene, lists, camera, aspect, nm);
  device.endPass();
  std::vector<const char*> lightTargets = {kDiffuseLight};
  if (!fourChannel_) lightTargets.push_back(kSpecularLight);
  for (const char* t : lightTargets)
    targets_->resolve(t);

  // 3. Materials.
  rhi::PassDesc m;
  m.colors[0].texture = targets_->attachment(kOutputColor);
  m.colors[0].clearColor = {0.0f, 0.0f, 0.0f, 1.0f};
  m.depthStencil.texture = targets_->attachment(kDepth);
  m.depthStencil.load = rhi::LoadOp::Load;
  m.label = "material";
  device.beginPass(m);
  device.setPipeline(materialPipeline_);
  std::vector<rhi::ResourceBinding> light = {sampled(8, targets_->readTexture(kDiffuseLight))};
  if (!fourChannel_) light.push_back(sampled(9, targets_->readTexture(kSpecularLight)));
  device.setBindings(light);
  for (uint32_t i : lists.visible) scene.drawMesh(s.meshes[i]);
  device.endPass();
  return targets_->present();
}

std::vector<NamedTarget> LightPrePass::targets() const {
  if (!targets_) return {};
  std::vector<NamedTarget> t = {{kDepth, targets_->attachment(kDepth)},
                                {kNormals, targets_->attachment(kNormals)},
                                {kPower, targets_->attachment(kPower)},
                                {kDiffuseLight, targets_->attachment(kDiffuseLight)}};
  if (!fourChannel_) t.push_back({kSpecularLight, targets_->attachment(kSpecularLight)});
  t.push_back({kOutputColor, targets_->readTexture(kOutputColor)});
  return t;
}

void LightPrePass::release(rhi::Device& device) {
  volumes_.reset();
  device.destroy(nmPipeline_);
  device.destroy(directionalPipeline_);
  device.destroy(materialPipeline_);
  targets_.reset();
  shaders_.reset();
}

}  // namespace parity::techniques
