#include "techniques/deferred/deferred.h"
#include "techniques/common/pass_helpers.h"
#include "techniques/common/planned_targets.h"

#include "scene/culling.h"

namespace parity::techniques {

namespace {

const char* const kDepth = "gbuffer.depth";
const char* const kNormals = "gbuffer.normals";
const char* const kDiffuse = "gbuffer.diffuse";
const char* const kSpecular = "gbuffer.specular";
const char* const kAccumulation = "light.accumulation";

}  // namespace

std::vector<PassInfo> DeferredShading::passes() const {
  std::vector<PassInfo> p = {{"geometry", "geometry pass over the camera visibility list: the G-buffer gets normals, diffuse colour, "
                       "specular colour and power; depth from rasterisation",
           {kDepth, kNormals, kDiffuse, kSpecular}},
          {"ambient+directional", "full-screen pass: ambient and directional light from the G-buffer into the light "
                                  "accumulation target",
           {kAccumulation}},
          {"lights", "one light volume per point (sphere) and spot (cone) light, shaded from the G-buffer and added; "
                     "back faces with an inverted depth test when the camera is inside the volume",
           {kAccumulation}},
          {"compose", "full-screen pass: the accumulated light becomes the final colour", {"color"}}};
  if (withShadows_) {
    p.insert(p.begin(), {"shadow directional", "orthographic shadow map of the directional light over the scene's bounds",
                         {"shadow.directional"}});
    p.insert(p.end() - 1, {"shadow local",
                           "per shadow-casting light: its spot map or six point-cube faces, then its volume in a "
                           "lighting pass of its own",
                           {"shadow.local"}});
  }
  return p;
}

std::vector<platforms::LogicalTarget> DeferredShading::logicalTargets(const RenderSettings& settings) const {
  using platforms::LogicalFormat;
  using platforms::TargetRole;
  return {{kNormals, LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"},
          {kDiffuse, LogicalFormat::Rgba8Unorm, true, TargetRole::GBuffer, "geometry"},
          {kSpecular, LogicalFormat::Rgba8Unorm, true, TargetRole::GBuffer, "geometry"},
          // the light volumes test against it while the lighting samples its resolve
          {kDepth, LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer, "geometry", 1, false,
           rhi::Format::RGBA8, 0, {"geometry", "lighting"}},
          {kAccumulation, LogicalFormat::Rgba16Hdr, true, TargetRole::LBuffer, "lighting"},
          outputColorTarget(settings, "compose")};
}

effects::ShadowSettings DeferredShading::shadowSettingsFor(const RenderSettings& settings) const {
  effects::ShadowSettings s = shadowSettings_;
  if (s.directionalSize == 0) s.directionalSize = settings.width >= 1280 ? 2048 : 1024;
  s.dataBinding = 11;
  s.mapBinding = 12;
  return s;
}

std::vector<Technique::SizedTargets> DeferredShading::furtherTargetPlans(const RenderSettings& settings) const {
  return withShadows_ ? effects::ShadowMaps::targetPlans(shadowSettingsFor(settings)) : std::vector<SizedTargets>{};
}

void DeferredShading::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  shaders_ = std::make_unique<ShaderLibrary>(device);
  std::vector<platforms::LogicalTarget> logical = logicalTargets(settings);
  targets_ = std::make_unique<PlannedTargets>(device, settings, logical, "deferred");
  const platforms::TargetPlan& plan = targets_->plan();
  rhi::ShaderCompileOptions options = targets_->shaderOptions(settings);
  if (withShadows_) {
    options.defines.push_back({"DEFERRED_SHADOWS", "1"});
    // Bindings 11 and 12 as the deferred shaders define them (3 and 4 hold the light volume
    // transforms and the G-buffer depth).
    shadowMaps_.prepare(device, *shaders_, shadowSettingsFor(settings), settings);
  }
  const rhi::Format depthFormat = attachmentFormat(plan, kDepth);

  rhi::PipelineDesc g;
  g.vertexShader = shaders_->load("forward/forward.vert", options);
  g.fragmentShader = shaders_->load("deferred/gbuffer.frag", options);
  scene::SceneGpu::describeVertexLayout(g);
  g.raster.cull = rhi::CullMode::Back;
  g.depthStencil.depthCompare = rhi::CompareOp::Less;
  g.depthStencil.depthWrite = true;
  g.colorTargets[0].format = attachmentFormat(plan, kNormals);
  g.colorTargets[1].format = attachmentFormat(plan, kDiffuse);
  g.colorTargets[2].format = attachmentFormat(plan, kSpecular);
  g.colorTargetCount = 3;
  g.depthStencilFormat = depthFormat;
  g.label = "deferred geometry";
  geometryPipeline_ = device.createPipeline(g);

  rhi::PipelineDesc a;
  a.vertexShader = shaders_->load("deferred/fullscreen_far.vert", options);
  a.fragmentShader = shaders_->load("deferred/ambient_directional.frag", options);
  a.depthStencil.depthCompare = rhi::CompareOp::Greater;  // only pixels the geometry pass covered
  a.colorTargets[0].format = attachmentFormat(plan, kAccumulation);
  enableAdditiveBlending(a.colorTargets[0]);
  a.colorTargetCount = 1;
  a.depthStencilFormat = depthFormat;
  a.label = "deferred ambient+directional";
  ambientDirectionalPipeline_ = device.createPipeline(a);

  rhi::PipelineDesc l;
  l.vertexShader = shaders_->load("deferred/light_volume.vert", options);
  l.fragmentShader = shaders_->load("deferred/light.frag", options);
  l.colorTargets[0].format = attachmentFormat(plan, kAccumulation);
  enableAdditiveBlending(l.colorTargets[0]);
  l.colorTargetCount = 1;
  l.depthStencilFormat = depthFormat;
  l.label = "deferred light volume";
  volumes_ = std::make_unique<LightVolumePass>(device, l);

  rhi::PipelineDesc c;
  c.vertexShader = shaders_->load("deferred/fullscreen_far.vert", options);
  c.fragmentShader = shaders_->load("deferred/compose.frag", options);
  c.colorTargets[0].format = attachmentFormat(plan, kOutputColor);
  c.colorTargetCount = 1;
  c.label = "deferred compose";
  composePipeline_ = device.createPipeline(c);
  if (!geometryPipeline_ || !ambientDirectionalPipeline_ || !volumes_->ok() || !composePipeline_)
    throw TechniqueError("deferred: the device rejected a pipeline");

}

rhi::TextureHandle DeferredShading::render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) {
  const float aspect = static_cast<float>(settings_.width) / static_cast<float>(settings_.height);
  scene.setCamera(camera, aspect);
  const scene::Scene& s = scene.scene();
  const scene::LightLists lists = scene::buildLightLists(s, camera.viewProjection(aspect));
  volumes_->upload(s);
  if (withShadows_) {
    shadowMaps_.beginFrame(device, scene);
    shadowMaps_.renderDirectional(device, scene);
  }

  // Geometry pass.
  rhi::PassDesc g;
  g.colors[0].texture = targets_->attachment(kNormals);
  g.colors[1].texture = targets_->attachment(kDiffuse);
  g.colors[2].texture = targets_->attachment(kSpecular);
  g.depthStencil.texture = targets_->attachment(kDepth);
  g.label = "geometry";
  device.beginPass(g);
  device.setPipeline(geometryPipeline_);
  for (uint32_t m : lists.visible) scene.drawMesh(s.meshes[m]);
  device.endPass();
  for (const char* name : {kNormals, kDiffuse, kSpecular, kDepth})
    targets_->resolve(name);

  const std::vector<rhi::ResourceBinding> gbuffer = {
      sampled(4, targets_->readTexture(kDepth)), sampled(5, targets_->readTexture(kNormals)),
      sampled(6, targets_->readTexture(kDiffuse)), sampled(7, targets_->readTexture(kSpecular))};

  // Lighting: ambient + directional over the full screen, then the light volumes, all added.
  rhi::PassDesc l;
  l.colors[0].texture = targets_->attachment(kAccumulation);
  l.depthStencil.texture = targets_->attachment(kDepth);  // sampled through its resolve or copy
  l.depthStencil.load = rhi::LoadOp::Load;
  l.label = "lighting";
  device.beginPass(l);
  device.setPipeline(ambientDirectionalPipeline_);
  device.setBindings(withSceneBuffers(gbuffer, scene));
  if (withShadows_) shadowMaps_.bindDirectional(device);
  drawFullScreenTriangle(device);
  if (!withShadows_) {
    volumes_->draw(scene, lists, camera, aspect, gbuffer);
    device.endPass();
  } else {
    // Unshadowed lights first, in this pass (their blocks turn the lookup off); then each
    // shadow-casting light: its map into the shared local map, its volume in a pass of its own.
    auto bindLight = [&](uint32_t i) { shadowMaps_.bindLocal(device, i); };
    volumes_->draw(scene, lists, camera, aspect, gbuffer, {[&](uint32_t i) { return !s.lights[i].castsShadows; }, bindLight});
    device.endPass();
    for (uint32_t i = 0; i < s.lights.size() && i < lists.perLight.size(); ++i) {
      if (!s.lights[i].castsShadows || lists.perLight[i].empty()) continue;
      shadowMaps_.renderLocal(device, scene, i);
      rhi::PassDesc lp = l;
      lp.colors[0].load = rhi::LoadOp::Load;
      lp.label = "light";
      device.beginPass(lp);
      volumes_->draw(scene, lists, camera, aspect, gbuffer, {[i](uint32_t j) { return j == i; }, bindLight});
      device.endPass();
    }
  }
  targets_->resolve(kAccumulation);

  // Compose.
  rhi::PassDesc c;
  c.colors[0].texture = targets_->attachment(kOutputColor);
  c.colors[0].clearColor = {0.0f, 0.0f, 0.0f, 1.0f};
  c.label = "compose";
  device.beginPass(c);
  device.setPipeline(composePipeline_);
  const rhi::ResourceBinding light = sampled(8, targets_->readTexture(kAccumulation));
  device.setBindings({&light, 1});
  device.draw(3);
  device.endPass();
  return targets_->present();
}

std::vector<NamedTarget> DeferredShading::targets() const {
  if (!targets_) return {};
  std::vector<NamedTarget> t = {{kDepth, targets_->attachment(kDepth)},
                                {kNormals, targets_->attachment(kNormals)},
                                {kDiffuse, targets_->attachment(kDiffuse)},
                                {kSpecular, targets_->attachment(kSpecular)},
                                {kAccumulation, targets_->attachment(kAccumulation)},
                                {kOutputColor, targets_->readTexture(kOutputColor)}};
  if (withShadows_) {
    t.insert(t.begin(), {"shadow.directional", shadowMaps_.directionalMap()});
    t.insert(t.end() - 1, {"shadow.local", shadowMaps_.localMap()});
  }
  return t;
}

void DeferredShading::release(rhi::Device& device) {
  volumes_.reset();
  if (withShadows_) shadowMaps_.release(device);
  device.destroy(geometryPipeline_);
  device.destroy(ambientDirectionalPipeline_);
  device.destroy(composePipeline_);
  targets_.reset();
  shaders_.reset();
}

}  // namespace parity::techniques
