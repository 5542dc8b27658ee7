#include "techniques/abuffer/abuffer.h"
#include "techniques/common/pass_helpers.h"

#include <glm/glm.hpp>

namespace parity::techniques {

namespace {

float opacityOf(const scene::Scene& s, int material) {
  return material >= 0 && size_t(material) < s.materials.size() ? s.materials[size_t(material)].opacity : 1.0f;
}

}  // namespace

std::vector<PassInfo> OrderIndependentTransparency::passes() const {
  if (mode_ == TransparencyMode::StencilRouted)
    return {{"opaque", "opaque meshes, forward shaded", {"opaque.color", "opaque.depth"}},
            {"route", "per sample of the 4x MSAA stencil: its routing value (sample mask, stencil REPLACE)", {"abuffer.stencil"}},
            {"store", "translucent meshes: stencil EQUAL 2 routes each fragment to its own sample, then DECR",
             {"abuffer.colors", "abuffer.depths"}},
            {"resolve", "per pixel: samples sorted by depth, blended back to front over the opaque image", {"color"}}};
  return {{"opaque", "opaque meshes, forward shaded", {"opaque.color", "opaque.depth"}},
          {"peel", "4 passes: the nearest translucent fragment behind the previous layer", {"peel.layers"}},
          {"composite", "the layers blended back to front over the opaque image", {"color"}}};
}

TransparencyMode OrderIndependentTransparency::runs(const rhi::Capabilities& caps) const {
  return mode_ == TransparencyMode::StencilRouted && caps.maxSamples < kLayers ? TransparencyMode::DepthPeeling : mode_;
}

std::vector<PortPath> OrderIndependentTransparency::portPaths(const rhi::Capabilities& caps) const {
  if (runs(caps) == mode_) return {};
  return {{"store", "depth peeling, " + std::to_string(kLayers) + " layers (the A-buffer's reference: the same layers, "
                    "blended alike) without the multisampled routing stencil",
           platforms::Capability::Multisampling}};
}

std::vector<platforms::LogicalTarget> OrderIndependentTransparency::logicalTargets(const RenderSettings& settings) const {
  const TransparencyMode runs = this->runs(settings.capabilities);
  using platforms::LogicalFormat;
  using platforms::TargetRole;
  auto depth = [](const std::string& name, const std::string& pass) {
    platforms::LogicalTarget t = sceneDepthTarget(pass, true);
    t.name = name;
    return t;
  };
  std::vector<platforms::LogicalTarget> t = {{kOpaqueColor, LogicalFormat::Rgba16Hdr, true, TargetRole::Plain, "opaque"},
                                             depth(kOpaqueDepth, "opaque")};
  if (runs == TransparencyMode::StencilRouted) {
    // 4x on every platform; the colours and depths are read sample by sample (on x360 through one
    // resolve per sample), the stencil only routes.
    platforms::LogicalTarget routing = sceneDepthTarget("route", false, true);
    routing.name = kRouting;
    routing.samples = kLayers;
    routing.livePasses = {"route", "store"};
    t.push_back(routing);
    for (auto [name, format] : {std::pair{kFragmentColors, LogicalFormat::Rgba16Hdr},
                                std::pair{kFragmentDepths, LogicalFormat::R32Float}}) {
      platforms::LogicalTarget fragments{name, format, true, TargetRole::Plain, "store", kLayers};
      fragments.readSamples = true;
      t.push_back(fragments);
    }
  }
  if (runs == TransparencyMode::DepthPeeling) {
    // Each layer's colour (blended over the opaque image like it) and the depth the next layer
    // peels behind; the first layer peels behind a depth cleared to 0.
    t.push_back(depth(kNoLayerDepth, "peel clear"));
    for (uint32_t k = 0; k < kLayers; ++k) {
      t.push_back({peelColor(k), LogicalFormat::Rgba16Hdr, true, TargetRole::Plain, "peel " + std::to_string(k)});
      t.push_back(depth(peelDepth(k), "peel " + std::to_string(k)));
    }
  }
  t.push_back(outputColorTarget(settings, runs == TransparencyMode::StencilRouted ? "resolve" : "composite"));
  return t;
}

void OrderIndependentTransparency::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  settings_.capabilities = runnableCapabilities(device, settings);
  running_ = runs(settings_.capabilities);  // without 4x MSAA the A-buffer's port peels instead
  shaders_ = std::make_unique<ShaderLibrary>(device);
  targets_ = std::make_unique<PlannedTargets>(device, settings_, logicalTargets(settings_), name());
  const rhi::ShaderCompileOptions options = targets_->shaderOptions(settings_);
  rhi::ShaderCompileOptions opaqueOptions = options;
  opaqueOptions.defines.push_back({"FORWARD_HDR_TARGET", "1"});

  rhi::PipelineDesc o;
  o.vertexShader = shaders_->load("forward/forward.vert", options);
  o.fragmentShader = shaders_->load("forward/forward_single_pass.frag", opaqueOptions);
  scene::SceneGpu::describeVertexLayout(o);
  o.raster.cull = rhi::CullMode::Back;
  o.depthStencil.depthCompare = rhi::CompareOp::Less;
  o.depthStencil.depthWrite = true;
  o.colorTargets[0].format = targets_->format(kOpaqueColor);
  o.colorTargetCount = 1;
  o.depthStencilFormat = targets_->format(kOpaqueDepth);
  o.label = "oit opaque";
  opaque_ = device.createPipeline(o);


  rhi::PipelineDesc full;
  full.vertexShader = shaders_->load("platforms/fullscreen.vert", options);
  full.colorTargetCount = 1;
  full.colorTargets[0].format = targets_->format(kOutputColor);

  rhi::PipelineDesc t;  // translucent geometry: both faces, no depth buffer test (the shader tests opaque depth)
  t.vertexShader = o.vertexShader;
  scene::SceneGpu::describeVertexLayout(t);
  if (running_ == TransparencyMode::StencilRouted) {
    rhi::PipelineDesc r;
    r.vertexShader = full.vertexShader;
    r.fragmentShader = shaders_->load("effects/abuffer_route.frag", options);
    r.samples = kLayers;
    r.depthStencilFormat = targets_->format(kRouting);
    r.depthStencil.stencilEnabled = true;
    r.depthStencil.front.compare = rhi::CompareOp::Always;
    r.depthStencil.front.pass = rhi::StencilOp::Replace;
    r.depthStencil.back = r.depthStencil.front;
    r.label = "abuffer route";
    route_ = device.createPipeline(r);

    t.fragmentShader = shaders_->load("effects/abuffer_store.frag", options);
    t.samples = kLayers;
    t.colorTargetCount = 2;
    t.colorTargets[0].format = targets_->format(kFragmentColors);
    t.colorTargets[1].format = targets_->format(kFragmentDepths);
    t.depthStencilFormat = targets_->format(kRouting);
    t.depthStencil.stencilEnabled = true;
    t.depthStencil.front.compare = rhi::CompareOp::Equal;
    t.depthStencil.front.pass = rhi::StencilOp::DecrementClamp;
    t.depthStencil.front.fail = rhi::StencilOp::DecrementClamp;
    t.depthStencil.back = t.depthStencil.front;
    t.label = "abuffer store";
    store_ = device.createPipeline(t);

    full.fragmentShader = shaders_->load("effects/abuffer_resolve.frag", options);
    full.label = "abuffer resolve";
    resolve_ = device.createPipeline(full);
    if (!opaque_ || !route_ || !store_ || !resolve_) throw TechniqueError("abuffer: the device rejected a pipeline");
  } else {
    t.fragmentShader = shaders_->load("effects/peel_layer.frag", options);
    t.colorTargets[0].format = targets_->format(peelColor(0));
    t.colorTargetCount = 1;
    t.depthStencilFormat = targets_->format(peelDepth(0));
    t.depthStencil.depthCompare = rhi::CompareOp::Less;
    t.depthStencil.depthWrite = true;
    t.label = "peel layer";
    peel_ = device.createPipeline(t);
    full.fragmentShader = shaders_->load("effects/peel_composite.frag", options);
    full.label = "peel composite";
    composite_ = device.createPipeline(full);
    if (!opaque_ || !peel_ || !composite_) throw TechniqueError("depth-peeling: the device rejected a pipeline");
  }
}

void OrderIndependentTransparency::drawMeshes(rhi::Device& device, scene::SceneGpu& scene, bool translucent) const {
  const scene::Scene& s = scene.scene();
  for (const scene::Mesh& mesh : s.meshes) {
    float opacity = opacityOf(s, mesh.material);
    if ((opacity < 1.0f) != translucent) continue;
    if (!translucent) {
      scene.drawMesh(mesh);
      continue;
    }
    rhi::ResourceBinding b[3];
    b[0].binding = 0;
    b[0].kind = rhi::BindingKind::UniformBuffer;
    b[0].buffer = scene.frameBuffer();
    b[1].binding = 1;
    b[1].kind = rhi::BindingKind::StorageBuffer;
    b[1].buffer = scene.lightBuffer();
    b[2] = sampled(2, scene.diffuseTexture(mesh.material));
    b[2].sampler = scene.materialSampler();
    device.setBindings(b);
    scene::GpuMaterial m = scene.material(mesh.material);
    m.flags.w = glm::floatBitsToUint(opacity);  // translucent_shading.glsl reads the opacity here
    device.pushConstants(&m, sizeof(m));
    device.setVertexBuffer(0, scene.vertexBuffer());
    device.setIndexBuffer(scene.indexBuffer(), rhi::IndexType::UInt32);
    device.drawIndexed(mesh.indexCount, 1, mesh.firstIndex);
  }
}

rhi::TextureHandle OrderIndependentTransparency::render(rhi::Device& device, scene::SceneGpu& scene,
                                                        const scene::Camera& camera) {
  scene.setCamera(camera, static_cast<float>(settings_.width) / static_cast<float>(settings_.height));
  rhi::PassDesc o;
  o.colors[0].texture = targets_->attachment(kOpaqueColor);
  o.colors[0].clearColor = targets_->gpu().clearColor(kOpaqueColor, {0.0f, 0.0f, 0.0f, 1.0f});
  o.depthStencil.texture = targets_->attachment(kOpaqueDepth);
  o.label = "opaque";
  device.beginPass(o);
  device.setPipeline(opaque_);
  drawMeshes(device, scene, false);
  device.endPass();
  targets_->resolve(kOpaqueColor);
  targets_->resolve(kOpaqueDepth);
  const rhi::TextureHandle opaqueColor = targets_->readTexture(kOpaqueColor);
  const rhi::TextureHandle opaqueDepth = targets_->readTexture(kOpaqueDepth);

  rhi::PassDesc f;
  f.colors[0].texture = targets_->attachment(kOutputColor);
  f.colors[0].load = rhi::LoadOp::DontCare;

  if (running_ == TransparencyMode::StencilRouted) {
    rhi::PassDesc r;
    r.depthStencil.texture = targets_->attachment(kRouting);
    r.depthStencil.clearStencil = 0;
    r.label = "route";
    device.beginPass(r);
    device.setPipeline(route_);
    for (uint32_t sample = 0; sample < kLayers; ++sample) {
      const uint32_t push[4] = {sample, 0, 0, 0};
      device.pushConstants(push, sizeof(push));
      device.setStencilReference(static_cast<uint8_t>(sample + 2));
      device.draw(3);
    }
    device.endPass();

    rhi::PassDesc st;
    st.colors[0].texture = targets_->attachment(kFragmentColors);
    st.colors[1].texture = targets_->attachment(kFragmentDepths);
    st.depthStencil.texture = targets_->attachment(kRouting);
    st.depthStencil.load = rhi::LoadOp::Load;
    st.label = "store";
    device.beginPass(st);
    device.setPipeline(store_);
    device.setStencilReference(2);
    const rhi::ResourceBinding od[] = {sampled(5, opaqueDepth)};
    device.setBindings(od);
    drawMeshes(device, scene, true);
    device.endPass();
    targets_->resolve(kFragmentColors);  // x360: one resolve per sample; elsewhere read in place
    targets_->resolve(kFragmentDepths);
    f.label = "resolve";
    device.beginPass(f);
    device.setPipeline(resolve_);
    const rhi::ResourceBinding rb[] = {sampled(4, targets_->readTexture(kFragmentColors)),
                                       sampled(5, targets_->readTexture(kFragmentDepths)), sampled(6, opaqueColor)};
    device.setBindings(rb);
    device.draw(3);
    device.endPass();
    return targets_->present();
  }

  rhi::PassDesc z;
  z.depthStencil.texture = targets_->attachment(kNoLayerDepth);
  z.depthStencil.clearDepth = 0.0f;
  z.label = "peel clear";
  device.beginPass(z);
  device.endPass();
  targets_->resolve(kNoLayerDepth);
  for (uint32_t k = 0; k < kLayers; ++k) {
    rhi::PassDesc p;
    p.colors[0].texture = targets_->attachment(peelColor(k));
    p.colors[0].clearColor = targets_->gpu().clearColor(peelColor(k), {0.0f, 0.0f, 0.0f, 0.0f});
    p.depthStencil.texture = targets_->attachment(peelDepth(k));
    p.label = "peel";
    device.beginPass(p);
    device.setPipeline(peel_);
    const rhi::ResourceBinding pb[] = {sampled(4, targets_->readTexture(k == 0 ? kNoLayerDepth : peelDepth(k - 1))),
                                       sampled(5, opaqueDepth)};
    device.setBindings(pb);
    drawMeshes(device, scene, true);
    device.endPass();
    targets_->resolve(peelColor(k));
    targets_->resolve(peelDepth(k));
  }
  f.label = "composite";
  device.beginPass(f);
  device.setPipeline(composite_);
  auto layer = [&](uint32_t k) { return targets_->readTexture(peelColor(k)); };
  const rhi::ResourceBinding cb[] = {sampled(4, layer(0)), sampled(5, layer(1)), sampled(6, layer(2)), sampled(7, layer(3)),
                                     sampled(8, opaqueColor)};
  device.setBindings(cb);
  device.draw(3);
  device.endPass();
  return targets_->present();
}

std::vector<NamedTarget> OrderIndependentTransparency::targets() const {
  if (!targets_) return {};
  std::vector<NamedTarget> t = {{kOpaqueColor, targets_->attachment(kOpaqueColor)},
                                {kOpaqueDepth, targets_->attachment(kOpaqueDepth)}};
  if (running_ == TransparencyMode::DepthPeeling)
    for (uint32_t k = 0; k < kLayers; ++k) t.push_back({peelColor(k), targets_->attachment(peelColor(k))});
  t.push_back({kOutputColor, targets_->readTexture(kOutputColor)});
  return t;
}

void OrderIndependentTransparency::release(rhi::Device& device) {
  for (rhi::PipelineHandle p : {opaque_, route_, store_, resolve_, peel_, composite_})
    if (p) device.destroy(p);
  targets_.reset();
  shaders_.reset();
}

}  // namespace parity::techniques
