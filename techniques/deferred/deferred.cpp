#include "techniques/deferred/deferred.h"
#include "techniques/common/pass_helpers.h"

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
  return {{"geometry", "geometry pass over the camera visibility list: the G-buffer gets normals, diffuse colour, "
                       "specular colour and power; depth from rasterisation",
           {kDepth, kNormals, kDiffuse, kSpecular}},
          {"ambient+directional", "full-screen pass: ambient and directional light from the G-buffer into the light "
                                  "accumulation target",
           {kAccumulation}},
          {"lights", "one light volume per point (sphere) and spot (cone) light, shaded from the G-buffer and added; "
                     "back faces with an inverted depth test when the camera is inside the volume",
           {kAccumulation}},
          {"compose", "full-screen pass: the accumulated light becomes the final colour", {"color"}}};
}

std::vector<platforms::LogicalTarget> DeferredShading::logicalTargets(const RenderSettings&) const {
  using platforms::LogicalFormat;
  using platforms::TargetRole;
  return {{kNormals, LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"},
          {kDiffuse, LogicalFormat::Rgba8Unorm, true, TargetRole::GBuffer, "geometry"},
          {kSpecular, LogicalFormat::Rgba8Unorm, true, TargetRole::GBuffer, "geometry"},
          {kDepth, LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer, "geometry"},
          {kAccumulation, LogicalFormat::Rgba16Hdr, true, TargetRole::LBuffer, "lighting"}};
}

void DeferredShading::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  shaders_ = std::make_unique<ShaderLibrary>(device);
  std::vector<platforms::LogicalTarget> logical = logicalTargets(settings);
  platforms::TargetPlan plan =
      platforms::planTargets(settings.platform, logical, settings.width, settings.height, settings.platformParams);
  targets_ = std::make_unique<platforms::GpuTargets>(device, plan);
  for (const platforms::LogicalTarget& t : logical)
    if (!targets_->attachment(t.name) || !targets_->readTexture(t.name))
      throw TechniqueError("deferred: cannot create target '" + t.name + "'");
  const rhi::ShaderCompileOptions options =
      mergeShaderOptions(settings.shaderOptions, platforms::platformShaderOptions(plan));
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
  c.colorTargets[0].format = settings.colorFormat;
  c.colorTargetCount = 1;
  c.label = "deferred compose";
  composePipeline_ = device.createPipeline(c);
  if (!geometryPipeline_ || !ambientDirectionalPipeline_ || !volumes_->ok() || !composePipeline_)
    throw TechniqueError("deferred: the device rejected a pipeline");

  rhi::TextureDesc d;
  d.format = depthFormat;
  d.width = settings.width;
  d.height = settings.height;
  d.label = "deferred light test depth";
  lightTestDepth_ = device.createTexture(d);
  rhi::TextureDesc cd = d;
  cd.format = settings.colorFormat;
  cd.label = "deferred color";
  color_ = device.createTexture(cd);
  if (!lightTestDepth_ || !color_) throw TechniqueError("deferred: cannot create render targets");
}

rhi::TextureHandle DeferredShading::render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) {
  const float aspect = static_cast<float>(settings_.width) / static_cast<float>(settings_.height);
  scene.setCamera(camera, aspect);
  const scene::Scene& s = scene.scene();
  const scene::LightLists lists = scene::buildLightLists(s, camera.viewProjection(aspect));
  volumes_->upload(s);

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
  device.copyTexture(targets_->attachment(kDepth), lightTestDepth_);
  for (const char* name : {kNormals, kDiffuse, kSpecular, kDepth})
    if (!targets_->resolve(name)) throw TechniqueError("deferred: resolve of '" + std::string(name) + "' failed: " + targets_->error());

  const std::vector<rhi::ResourceBinding> gbuffer = {
      sampled(4, targets_->readTexture(kDepth)), sampled(5, targets_->readTexture(kNormals)),
      sampled(6, targets_->readTexture(kDiffuse)), sampled(7, targets_->readTexture(kSpecular))};

  // Lighting: ambient + directional over the full screen, then the light volumes, all added.
  rhi::PassDesc l;
  l.colors[0].texture = targets_->attachment(kAccumulation);
  l.depthStencil.texture = lightTestDepth_;
  l.depthStencil.load = rhi::LoadOp::Load;
  l.label = "lighting";
  device.beginPass(l);
  device.setPipeline(ambientDirectionalPipeline_);
  device.setBindings(withSceneBuffers(gbuffer, scene));
  drawFullScreenTriangle(device);
  volumes_->draw(scene, lists, camera, aspect, gbuffer);
  device.endPass();
  if (!targets_->resolve(kAccumulation))
    throw TechniqueError("deferred: resolve of the light accumulation failed: " + targets_->error());

  // Compose.
  rhi::PassDesc c;
  c.colors[0].texture = color_;
  c.colors[0].clearColor = {0.0f, 0.0f, 0.0f, 1.0f};
  c.label = "compose";
  device.beginPass(c);
  device.setPipeline(composePipeline_);
  const rhi::ResourceBinding light = sampled(8, targets_->readTexture(kAccumulation));
  device.setBindings({&light, 1});
  device.draw(3);
  device.endPass();
  return color_;
}

std::vector<NamedTarget> DeferredShading::targets() const {
  if (!targets_) return {};
  return {{kDepth, targets_->attachment(kDepth)},
          {kNormals, targets_->attachment(kNormals)},
          {kDiffuse, targets_->attachment(kDiffuse)},
          {kSpecular, targets_->attachment(kSpecular)},
          {kAccumulation, targets_->attachment(kAccumulation)},
          {"color", color_}};
}

void DeferredShading::release(rhi::Device& device) {
  volumes_.reset();
  device.destroy(geometryPipeline_);
  device.destroy(ambientDirectionalPipeline_);
  device.destroy(composePipeline_);
  device.destroy(lightTestDepth_);
  device.destroy(color_);
  targets_.reset();
  shaders_.reset();
}

}  // namespace parity::techniques
