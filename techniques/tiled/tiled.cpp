#include "techniques/tiled/tiled.h"

#include <algorithm>

#include <glm/glm.hpp>

#include "techniques/common/pass_helpers.h"
#include "techniques/tiled/cpu_light_culling.h"

namespace parity::techniques {

namespace {

// The G-buffer (deferred): world normal, diffuse colour + specular power, specular colour, each a
// Rgba16Hdr target (signed and beyond 1: FP16 on dx10 and ps3, one format for the MRT pass as
// RSX wants; k_16_16_16_16 on x360; float on the reference). Depth is the scene depth, read as
// the platform reads depth. Forward's pre-pass keeps its depth as a float colour too.
const char* const kNormal = "gbuffer.normal";
const char* const kDiffusePower = "gbuffer.diffuse";
const char* const kSpecular = "gbuffer.specular";
const char* const kSurfaceDepth = "prepass.depth";

}  // namespace

std::vector<PassInfo> TiledShading::passes() const {
  PassInfo cull{"light culling",
                "compute, one workgroup per 16x16 tile: world bounds of the tile's depth, lights whose sphere meets "
                "them listed in scene order (on the CPU against the tile's frustum where there is no compute)",
                {"tiles"}};
  if (mode_ == TiledMode::Deferred)
    return {{"g-buffer", "geometry once: depth, normal, diffuse colour + specular power, specular colour",
             {kNormal, kDiffusePower, kSpecular, "depth"}},
            cull,
            {"shade", "full screen: ambient + directional + the tile's lights per pixel, G-buffer read once", {"color"}}};
  return {{"depth pre-pass", "geometry depth only (and kept readable for the culling pass)", {"prepass.depth", "depth"}},
          cull,
          {"forward", "geometry with forward shading over the tile's lights", {"color", "depth"}}};
}

std::vector<PortPath> TiledShading::portPaths(const rhi::Capabilities& caps) const {
  if (caps.compute) return {};
  return {{"light culling",
           "on the CPU: each tile's frustum against every light's sphere, the lists uploaded each frame (every light "
           "that reaches the tile, the compute path's image bit for bit)",
           platforms::Capability::Compute}};
}

std::vector<platforms::LogicalTarget> TiledShading::logicalTargets(const RenderSettings& settings) const {
  using platforms::LogicalFormat;
  using platforms::TargetRole;
  if (mode_ == TiledMode::Deferred)
    return {sceneDepthTarget("g-buffer", true),
            {kNormal, LogicalFormat::Rgba16Hdr, true, TargetRole::GBuffer, "g-buffer"},
            {kDiffusePower, LogicalFormat::Rgba16Hdr, true, TargetRole::GBuffer, "g-buffer"},
            {kSpecular, LogicalFormat::Rgba16Hdr, true, TargetRole::GBuffer, "g-buffer"},
            outputColorTarget(settings, "shade")};
  return {sceneDepthTarget("depth pre-pass"),
          {kSurfaceDepth, LogicalFormat::R32Float, true, TargetRole::Plain, "depth pre-pass"},
          outputColorTarget(settings, "forward")};
}

std::vector<NamedTarget> TiledShading::targets() const {
  if (!targets_) return {};
  const NamedTarget color{kOutputColor, targets_->readTexture(kOutputColor)};
  const NamedTarget depth{kSceneDepth, targets_->attachment(kSceneDepth)};
  if (mode_ == TiledMode::Deferred)
    return {{kNormal, targets_->attachment(kNormal)},
            {kDiffusePower, targets_->attachment(kDiffusePower)},
            {kSpecular, targets_->attachment(kSpecular)},
            color,
            depth};
  return {{kSurfaceDepth, targets_->readTexture(kSurfaceDepth)}, color, depth};
}

void TiledShading::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  settings_.capabilities = runnableCapabilities(device, settings);
  shaders_ = std::make_unique<ShaderLibrary>(device);
  const bool deferred = mode_ == TiledMode::Deferred;
  targets_ = std::make_unique<PlannedTargets>(device, settings, logicalTargets(settings), name());
  const rhi::ShaderCompileOptions options = targets_->shaderOptions(settings);

  rhi::PipelineDesc p;
  p.vertexShader = shaders_->load("forward/forward.vert", options);
  p.fragmentShader =
      shaders_->load(deferred ? "tiled/gbuffer.frag" : "tiled/depth_prepass.frag", options);
  scene::SceneGpu::describeVertexLayout(p);
  p.raster.cull = rhi::CullMode::Back;
  p.depthStencil.depthCompare = rhi::CompareOp::Less;
  p.depthStencil.depthWrite = true;
  if (deferred) {
    p.colorTargets[0].format = targets_->format(kNormal);
    p.colorTargets[1].format = targets_->format(kDiffusePower);
    p.colorTargets[2].format = targets_->format(kSpecular);
    p.colorTargetCount = 3;
  } else {
    p.colorTargets[0].format = targets_->format(kSurfaceDepth);
    p.colorTargetCount = 1;
  }
  p.depthStencilFormat = targets_->format(kSceneDepth);
  p.label = name() + (deferred ? " g-buffer" : " depth pre-pass");
  geometryPipeline_ = device.createPipeline(p);

  if (deferred) {
    rhi::PipelineDesc s;
    s.vertexShader = shaders_->load("platforms/fullscreen.vert", options);
    s.fragmentShader = shaders_->load("tiled/tiled_deferred.frag", options);
    s.colorTargets[0].format = targets_->format(kOutputColor);
    s.colorTargetCount = 1;
    s.label = name() + " shade";
    shadePipeline_ = device.createPipeline(s);
  } else {
    // Same vertex shader and depth format as the pre-pass: EQUAL keeps the visible surface.
    p.fragmentShader = shaders_->load("tiled/tiled_forward.frag", options);
    p.depthStencil.depthCompare = rhi::CompareOp::Equal;
    p.depthStencil.depthWrite = false;
    p.colorTargets[0].format = targets_->format(kOutputColor);
    p.colorTargetCount = 1;
    p.label = name() + " forward";
    shadePipeline_ = device.createPipeline(p);
  }
  if (settings_.capabilities.compute) {
    rhi::ComputePipelineDesc c;
    rhi::ShaderCompileOptions cull = options;
    if (deferred) cull.defines.push_back({"TILED_PLATFORM_DEPTH", "1"});  // the scene depth, not a float copy
    c.computeShader = shaders_->load("tiled/light_cull.comp", cull);
    c.label = name() + " light culling";
    cullPipeline_ = device.createComputePipeline(c);
    if (!cullPipeline_) throw TechniqueError(name() + ": the device rejected the culling pipeline");
  }
  if (!geometryPipeline_ || !shadePipeline_) throw TechniqueError(name() + ": the device rejected a pipeline");
}

rhi::TextureHandle TiledShading::render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) {
  const float aspect = static_cast<float>(settings_.width) / static_cast<float>(settings_.height);
  scene.setCamera(camera, aspect);
  const scene::Scene& s = scene.scene();
  const uint32_t lightCount = static_cast<uint32_t>(s.lights.size());
  if (lightCount > kMaxLights)
    throw TechniqueError(name() + ": " + std::to_string(lightCount) + " lights, at most " + std::to_string(kMaxLights));

  // A tile can list every light: stride lightCount + 1 (the count first).
  uint32_t stride = lightCount + 1;
  if (stride != stride_ || !tileLists_) {
    if (tileLists_) device.destroy(tileLists_);
    if (tileParams_) device.destroy(tileParams_);
    rhi::BufferDesc b;
    b.size = static_cast<size_t>(tilesX()) * tilesY() * stride * sizeof(uint32_t);
    b.usage = rhi::BufferUsage_Storage;
    b.label = name() + " tile light lists";
    tileLists_ = device.createBuffer(b);
    glm::uvec4 params(stride, tilesX(), tilesY(), 0);
    rhi::BufferDesc u;
    u.size = sizeof(params);
    u.usage = rhi::BufferUsage_Uniform;
    u.initialData = &params;
    u.label = name() + " tile parameters";
    tileParams_ = device.createBuffer(u);
    if (!tileLists_ || !tileParams_) throw TechniqueError(name() + ": cannot create the tile light lists");
    stride_ = stride;
  }

  // 1. G-buffer or depth pre-pass.
  rhi::PassDesc geometry;
  if (mode_ == TiledMode::Deferred) {
    geometry.colors[0].texture = targets_->attachment(kNormal);
    geometry.colors[1].texture = targets_->attachment(kDiffusePower);
    geometry.colors[2].texture = targets_->attachment(kSpecular);
  } else {
    geometry.colors[0].texture = targets_->attachment(kSurfaceDepth);
    geometry.colors[0].clearColor = {1.0f, 0.0f, 0.0f, 0.0f};
  }
  geometry.depthStencil.texture = targets_->attachment(kSceneDepth);
  geometry.label = mode_ == TiledMode::Deferred ? "g-buffer" : "depth pre-pass";
  device.beginPass(geometry);
  device.setPipeline(geometryPipeline_);
  for (const scene::Mesh& mesh : s.meshes) scene.drawMesh(mesh);
  device.endPass();
  const char* const depthRead = mode_ == TiledMode::Deferred ? kSceneDepth : kSurfaceDepth;
  targets_->resolve(depthRead);
  if (mode_ == TiledMode::Deferred)
    for (const char* t : {kNormal, kDiffusePower, kSpecular}) targets_->resolve(t);

  // 2. Light culling per tile.
  rhi::ResourceBinding b[5];
  b[0].binding = 0;
  b[0].kind = rhi::BindingKind::UniformBuffer;
  b[0].buffer = scene.frameBuffer();
  b[1].binding = 1;
  b[1].kind = rhi::BindingKind::StorageBuffer;
  b[1].buffer = scene.lightBuffer();
  b[2] = sampled(4, targets_->readTexture(depthRead));
  b[3].binding = 8;
  b[3].kind = rhi::BindingKind::StorageBuffer;
  b[3].buffer = tileLists_;
  b[4].binding = 9;
  b[4].kind = rhi::BindingKind::UniformBuffer;
  b[4].buffer = tileParams_;
  // scene_data.glsl declares the material push-constant block in every shader that includes it.
  scene::GpuMaterial unused{};
  if (cullPipeline_) {
    device.setComputePipeline(cullPipeline_);
    device.setBindings(b);
    device.pushConstants(&unused, sizeof(unused));
    device.dispatch(tilesX(), tilesY());
  } else {  // the port's path: the lists built on the CPU (cpu_light_culling.h)
    const std::vector<uint32_t> lists =
        cullLightsPerTile(s.lights, camera.viewProjection(aspect), settings_.width, settings_.height, kTileSize, stride);
    device.writeBuffer(tileLists_, 0, lists.data(), lists.size() * sizeof(uint32_t));
  }

  // 3. Shading over the tile lists.
  rhi::PassDesc shade;
  shade.colors[0].texture = targets_->attachment(kOutputColor);
  shade.colors[0].clearColor = {0.0f, 0.0f, 0.0f, 1.0f};
  if (mode_ == TiledMode::Forward) {
    shade.depthStencil.texture = targets_->attachment(kSceneDepth);
    shade.depthStencil.load = rhi::LoadOp::Load;
  }
  shade.label = mode_ == TiledMode::Deferred ? "shade" : "forward";
  device.beginPass(shade);
  device.setPipeline(shadePipeline_);
  if (mode_ == TiledMode::Deferred) {
    rhi::ResourceBinding g[4] = {sampled(4, targets_->readTexture(kSceneDepth)),
                                 sampled(5, targets_->readTexture(kNormal)),
                                 sampled(6, targets_->readTexture(kDiffusePower)),
                                 sampled(7, targets_->readTexture(kSpecular))};
    device.setBindings(b);  // frame, lights, lists, parameters (4 is replaced next)
    device.setBindings(g);
    device.pushConstants(&unused, sizeof(unused));
    device.draw(3);
  } else {
    rhi::ResourceBinding lists[2] = {b[3], b[4]};
    device.setBindings(lists);
    for (const scene::Mesh& mesh : s.meshes) scene.drawMesh(mesh);
  }
  device.endPass();
  return targets_->present();
}

std::vector<std::vector<uint32_t>> TiledShading::readTileLists(rhi::Device& device) const {
  std::vector<std::vector<uint32_t>> out;
  if (!tileLists_) return out;
  const rhi::BufferDesc* desc = device.describe(tileLists_);
  std::vector<uint8_t> bytes = device.readBuffer(tileLists_, 0, desc->size);
  const uint32_t* words = reinterpret_cast<const uint32_t*>(bytes.data());
  for (uint32_t t = 0; t < tilesX() * tilesY(); ++t) {
    const uint32_t* entry = words + static_cast<size_t>(t) * stride_;
    out.emplace_back(entry + 1, entry + 1 + std::min(entry[0], stride_ - 1));
  }
  return out;
}

void TiledShading::release(rhi::Device& device) {
  device.destroy(geometryPipeline_);
  device.destroy(shadePipeline_);
  if (cullPipeline_) device.destroy(cullPipeline_);
  cullPipeline_ = {};
  targets_.reset();
  if (tileLists_) device.destroy(tileLists_);
  if (tileParams_) device.destroy(tileParams_);
  tileLists_ = tileParams_ = {};
  stride_ = 0;
  shaders_.reset();
}

}  // namespace parity::techniques
