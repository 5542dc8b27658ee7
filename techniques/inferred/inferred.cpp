#include "techniques/inferred/inferred.h"
#include "techniques/common/pass_helpers.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numeric>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "techniques/inferred/normal_groups.h"

namespace parity::techniques {

namespace {

// Logical target names (also the names `--passes` dumps use).
const char* const kNormals = "gbuffer.normals";
const char* const kDsf = "gbuffer.dsf";
const char* const kSpecular = "gbuffer.specular";
const char* const kDepth = "gbuffer.depth";
const char* const kLBuffer = "lbuffer";

// A scene vertex plus the normal-group ID of the triangles that use it (stride 36).
struct GroupedVertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec2 uv;
  uint32_t normalGroup;
};
static_assert(sizeof(GroupedVertex) == 36, "layout is shared with shaders/inferred/scene.vert");

// std140 mirror of InferredParams in shaders/inferred/inferred.glsl.
struct GpuParams {
  glm::vec4 sizes;  // xy output size, zw L-buffer size
  glm::vec4 dsf;    // x relative depth threshold
};

// Relative linear-depth difference under which an L-buffer sample still counts as the surface
// being shaded (§3.1: "depth must also match within an adjustable threshold"). The object and
// normal-group IDs do most of the work; depth only has to separate a surface from another part
// of itself further back, and must tolerate the slope of a grazing surface across one L-buffer
// texel (1.6 output pixels).
constexpr float kDsfDepthThreshold = 0.1f;

bool hasDefine(const rhi::ShaderCompileOptions& o, const std::string& name, std::string* value = nullptr) {
  for (const auto& [k, v] : o.defines)
    if (k == name) {
      if (value) *value = v;
      return true;
    }
  return false;
}

// Stipple pattern p (1..3) covers the L-buffer texels (x, y) with (x & 1, y & 1) = (p & 1, p >> 1);
// pattern 0 (every texel) is the opaque layer.
constexpr uint32_t kStipplePatterns = 3;

}  // namespace

uint32_t InferredLighting::reducedSize(uint32_t size, float scale) {
  return std::max(1u, static_cast<uint32_t>(std::floor(static_cast<double>(size) * scale)));
}

float InferredLighting::effectiveScale(const RenderSettings& settings) const {
  std::string value;
  if (hasDefine(settings.shaderOptions, "INFERRED_LBUFFER_SCALE", &value)) {
    float s = std::strtof(value.c_str(), nullptr);
    if (!(s > 0.0f && s <= 1.0f))
      throw TechniqueError("inferred: INFERRED_LBUFFER_SCALE must be in (0, 1], got '" + value + "'");
    return s;
  }
  return scale_;
}

std::vector<PassInfo> InferredLighting::passes() const {
  return {
      {"geometry",
       "G-buffers at the L-buffer resolution: view-space normals (half-sphere mapping, eq. 1-3), DSF data (linear "
       "depth; object ID << 8 | normal-group ID), specular power, depth-stencil; opaque polygons, then alpha polygons "
       "in 2x2 stipple patterns (one pattern per layer, up to 3 layers over the opaque one); then the platform's "
       "resolves",
       {kNormals, kDsf, kSpecular, kDepth}},
      {"light",
       "L-buffer (diffuse RGB, specular intensity A) at the reduced resolution: ambient and directional light, then "
       "per light a scissor rectangle, the depth-fail stencil volume and a full-screen quad adding its light",
       {kLBuffer}},
      {"material",
       "full resolution: opaque polygons with their materials, lighting inferred from the L-buffer with the "
       "discontinuity sensitive bilinear filter (regular bilinear when no sample matches); alpha polygons sorted back "
       "to front, lit with a small cone filter over the four nearest samples of their stipple pattern",
       {"color", "depth"}},
  };
}

std::vector<platforms::LogicalTarget> InferredLighting::logicalTargets(const RenderSettings&) const {
  using platforms::LogicalFormat;
  using platforms::TargetRole;
  // Lifetimes (X4): the G-buffer colour targets are resolved after the geometry pass; depth stays
  // live into the light pass (stencil volumes test against it), so the L-buffer may take the
  // colour targets' EDRAM tiles but not the depth's.
  auto livingIn = [](platforms::LogicalTarget t, std::vector<std::string> passes) {
    t.livePasses = std::move(passes);
    return t;
  };
  return {
      {kNormals, LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"},
      {kDsf, LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"},
      {kSpecular, LogicalFormat::Rgba8Unorm, true, TargetRole::GBuffer, "geometry"},
      livingIn({kDepth, LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer, "geometry"}, {"geometry", "light"}),
      livingIn({kLBuffer, LogicalFormat::Rgba16Hdr, true, TargetRole::LBuffer, "light"}, {"light"}),
  };
}

std::vector<Technique::SizedTargets> InferredLighting::furtherTargetPlans(const RenderSettings& settings) const {
  return {{"material", {settings.width, settings.height}, {outputColorTarget(settings, "material"), sceneDepthTarget("material")}}};
}

TargetExtent InferredLighting::logicalTargetExtent(const RenderSettings& settings) const {
  const float scale = effectiveScale(settings);
  return {reducedSize(settings.width, scale), reducedSize(settings.height, scale)};
}

void InferredLighting::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  const TargetExtent reduced = logicalTargetExtent(settings);
  reducedWidth_ = reduced.width;
  reducedHeight_ = reduced.height;
  std::vector<platforms::LogicalTarget> logical = logicalTargets(settings);
  gpuTargets_ = std::make_unique<PlannedTargets>(device, settings, logical, "inferred", reduced);
  const platforms::TargetPlan& p = gpuTargets_->plan();

  // The depth-fail stencil optimisation binds the G-buffer depth-stencil surface while the light
  // shader samples the depth: possible where the plan gives the surface a stencil and a separate
  // read texture (a resolve or copy), so the light pass never samples what it has bound.
  const platforms::PhysicalTarget* depthTarget = p.find(kDepth);
  stencilVolumes_ = rhi::hasStencil(depthTarget->attachmentFormat) &&
                    gpuTargets_->readTexture(kDepth) != gpuTargets_->attachment(kDepth);

  rhi::ShaderCompileOptions options = gpuTargets_->shaderOptions(settings);
  if (!dsfFilter_ && !hasDefine(options, "INFERRED_PLAIN_BILINEAR")) options.defines.push_back({"INFERRED_PLAIN_BILINEAR", "1"});
  shaders_ = std::make_unique<ShaderLibrary>(device);
  rhi::ShaderHandle sceneVs = shaders_->load("inferred/scene.vert", options);
  rhi::ShaderHandle fullscreenVs = shaders_->load("platforms/fullscreen.vert", options);

  auto sceneLayout = [](rhi::PipelineDesc& d) {
    d.vertexBuffers[0].stride = sizeof(GroupedVertex);
    d.attributes[0] = {0, rhi::VertexFormat::Float3, offsetof(GroupedVertex, position), 0};
    d.attributes[1] = {1, rhi::VertexFormat::Float3, offsetof(GroupedVertex, normal), 0};
    d.attributes[2] = {2, rhi::VertexFormat::Float2, offsetof(GroupedVertex, uv), 0};
    d.attributes[3] = {3, rhi::VertexFormat::UInt, offsetof(GroupedVertex, normalGroup), 0};
    d.attributeCount = 4;
  };
  auto create = [&](const rhi::PipelineDesc& d) {
    rhi::PipelineHandle h = device.createPipeline(d);
    if (!h) throw TechniqueError("inferred: the device rejected the pipeline '" + d.label + "'");
    return h;
  };

  // Geometry pass.
  {
    rhi::PipelineDesc d;
    d.vertexShader = sceneVs;
    d.fragmentShader = shaders_->load("inferred/geometry.frag", options);
    sceneLayout(d);
    d.raster.cull = rhi::CullMode::Back;
    d.depthStencil.depthCompare = rhi::CompareOp::Less;
    d.depthStencil.depthWrite = true;
    const char* names[] = {kNormals, kDsf, kSpecular};
    for (uint32_t i = 0; i < 3; ++i) d.colorTargets[i].format = p.find(names[i])->attachmentFormat;
    d.colorTargetCount = 3;
    d.depthStencilFormat = depthTarget->attachmentFormat;
    d.label = "inferred geometry (opaque)";
    geometryOpaque_ = create(d);
    d.raster.cull = rhi::CullMode::None;  // alpha polygons are seen from both sides
    d.label = "inferred geometry (alpha, stippled)";
    geometryAlpha_ = create(d);
  }

  // Light pass.
  const rhi::Format lbufferFormat = p.find(kLBuffer)->attachmentFormat;
  {
    rhi::PipelineDesc d;
    d.vertexShader = fullscreenVs;
    d.fragmentShader = shaders_->load("inferred/light.frag", options);
    d.colorTargets[0].format = lbufferFormat;
    d.colorTargets[0].blend.enabled = true;  // lights accumulate: One + One
    d.colorTargets[0].blend.srcColor = d.colorTargets[0].blend.dstColor = rhi::BlendFactor::One;
    d.colorTargets[0].blend.srcAlpha = d.colorTargets[0].blend.dstAlpha = rhi::BlendFactor::One;
    d.colorTargetCount = 1;
    d.raster.scissorEnabled = true;
    if (stencilVolumes_) d.depthStencilFormat = depthTarget->attachmentFormat;
    d.label = "inferred ambient and directional light";
    globalLightPipeline_ = create(d);
    if (stencilVolumes_) {
      // Only where the light's volume contains visible geometry (stencil != 0), clearing the
      // mark for the next light as it goes.
      d.depthStencil.stencilEnabled = true;
      d.depthStencil.front.compare = d.depthStencil.back.compare = rhi::CompareOp::NotEqual;
      d.depthStencil.front.pass = d.depthStencil.back.pass = rhi::StencilOp::Zero;
    }
    d.label = "inferred light";
    lightPipeline_ = create(d);

    if (stencilVolumes_) {
      rhi::PipelineDesc s;
      s.vertexShader = shaders_->load("inferred/volume.vert", options);
      s.fragmentShader = shaders_->load("inferred/volume.frag", options);
      LightVolumes::describeVertexLayout(s);
      s.colorTargets[0].format = lbufferFormat;
      s.colorTargets[0].writeMask = 0;
      s.colorTargetCount = 1;
      s.depthStencilFormat = depthTarget->attachmentFormat;
      // Depth-fail (Kwoon 2004): a back face behind the scene increments, a front face behind it
      // decrements; the sum is non-zero exactly where scene geometry lies inside the volume,
      // also when the camera is inside it.
      s.depthStencil.depthCompare = rhi::CompareOp::Less;
      s.depthStencil.depthWrite = false;
      s.depthStencil.stencilEnabled = true;
      s.depthStencil.front.depthFail = rhi::StencilOp::DecrementWrap;
      s.depthStencil.back.depthFail = rhi::StencilOp::IncrementWrap;
      s.raster.cull = rhi::CullMode::None;
      s.raster.scissorEnabled = true;
      s.label = "inferred light volume stencil";
      stencilVolume_ = create(s);
      volumes_ = std::make_unique<LightVolumes>(device);
    }
  }

  // Material pass: at the output size, so its colour and depth are a plan of their own (a plan
  // has one size; the G-buffers' is the reduced one).
  const SizedTargets output = furtherTargetPlans(settings)[0];
  output_ = std::make_unique<PlannedTargets>(device, settings, output.targets, name(), output.extent);
  {
    rhi::PipelineDesc d;
    d.vertexShader = sceneVs;
    d.fragmentShader = shaders_->load("inferred/material.frag", options);
    sceneLayout(d);
    d.raster.cull = rhi::CullMode::Back;
    d.depthStencil.depthCompare = rhi::CompareOp::Less;
    d.depthStencil.depthWrite = true;
    d.colorTargets[0].format = output_->format(kOutputColor);
    d.colorTargetCount = 1;
    d.depthStencilFormat = output_->format(kSceneDepth);
    d.label = "inferred material (opaque)";
    materialOpaque_ = create(d);
    d.raster.cull = rhi::CullMode::None;
    d.depthStencil.depthWrite = false;
    d.colorTargets[0].blend.enabled = true;
    d.colorTargets[0].blend.srcColor = rhi::BlendFactor::SrcAlpha;
    d.colorTargets[0].blend.dstColor = rhi::BlendFactor::OneMinusSrcAlpha;
    d.colorTargets[0].blend.srcAlpha = rhi::BlendFactor::Zero;  // keep the opaque alpha (1)
    d.colorTargets[0].blend.dstAlpha = rhi::BlendFactor::One;
    d.label = "inferred material (alpha)";
    materialAlpha_ = create(d);
  }

  GpuParams params{glm::vec4(float(settings.width), float(settings.height), float(reducedWidth_), float(reducedHeight_)),
                   glm::vec4(kDsfDepthThreshold, 0.0f, 0.0f, 0.0f)};
  rhi::BufferDesc b;
  b.size = sizeof(params);
  b.usage = rhi::BufferUsage_Uniform;
  b.initialData = &params;
  b.label = "inferred params";
  params_ = device.createBuffer(b);
  if (!params_) throw TechniqueError("inferred: cannot create its parameter buffer");
}

void InferredLighting::uploadScene(rhi::Device& device, const scene::Scene& s) {
  if (uploadedScene_ == &s) return;
  if (vertices_) device.destroy(vertices_);
  if (indices_) device.destroy(indices_);
  std::vector<GroupedVertex> vertices;
  std::vector<uint32_t> indices(s.indices.size(), 0);
  for (const scene::Mesh& mesh : s.meshes) {
    std::vector<uint8_t> groups = inferred::normalGroups(s, mesh);
    std::map<std::pair<uint32_t, uint8_t>, uint32_t> split;  // (scene vertex, group) -> vertex
    for (uint32_t i = 0; i < mesh.indexCount; ++i) {
      uint32_t original = s.indices[mesh.firstIndex + i];
      uint8_t group = groups[i / 3];
      auto [it, inserted] = split.emplace(std::make_pair(original, group), static_cast<uint32_t>(vertices.size()));
      if (inserted) {
        const scene::Vertex& v = s.vertices[original];
        vertices.push_back({v.position, v.normal, v.uv, group});
      }
      indices[mesh.firstIndex + i] = it->second;
    }
  }
  if (vertices.empty()) vertices.push_back({});
  if (indices.empty()) indices.push_back(0);
  rhi::BufferDesc v;
  v.size = vertices.size() * sizeof(GroupedVertex);
  v.usage = rhi::BufferUsage_Vertex;
  v.initialData = vertices.data();
  v.label = "inferred vertices (with normal groups)";
  vertices_ = device.createBuffer(v);
  rhi::BufferDesc ib;
  ib.size = indices.size() * sizeof(uint32_t);
  ib.usage = rhi::BufferUsage_Index;
  ib.initialData = indices.data();
  ib.label = "inferred indices";
  indices_ = device.createBuffer(ib);
  if (!vertices_ || !indices_) throw TechniqueError("inferred: cannot upload the scene");
  uploadedScene_ = &s;
}

void InferredLighting::drawMesh(rhi::Device& device, scene::SceneGpu& scene, uint32_t meshIndex,
                                uint32_t stipplePattern) {
  const scene::Mesh& mesh = scene.scene().meshes[meshIndex];
  rhi::ResourceBinding b[5];
  b[0].binding = 0;
  b[0].kind = rhi::BindingKind::UniformBuffer;
  b[0].buffer = scene.frameBuffer();
  b[1].binding = 1;  // declared by scene_data.glsl, which the scene shaders include
  b[1].kind = rhi::BindingKind::StorageBuffer;
  b[1].buffer = scene.lightBuffer();
  b[2] = sampled(2, scene.diffuseTexture(mesh.material));
  b[2].sampler = scene.materialSampler();
  b[3].binding = 3;
  b[3].kind = rhi::BindingKind::UniformBuffer;
  b[3].buffer = params_;
  b[4] = sampled(scene::kNormalMapBinding, scene.normalTexture(mesh.material));
  b[4].sampler = scene.materialSampler();
  device.setBindings(b);
  scene::GpuMaterial m = scene.material(mesh.material);
  // Object ID (§3.1): 8 bits per renderable, 0 left to the cleared background.
  m.flags.y = (meshIndex % 255u) + 1u;
  m.flags.z = stipplePattern;
  float opacity = mesh.material >= 0 && size_t(mesh.material) < scene.scene().materials.size()
                      ? scene.scene().materials[mesh.material].opacity
                      : 1.0f;
  m.flags.w = glm::floatBitsToUint(opacity);
  device.pushConstants(&m, sizeof(m));
  device.setVertexBuffer(0, vertices_);
  device.setIndexBuffer(indices_, rhi::IndexType::UInt32);
  device.drawIndexed(mesh.indexCount, 1, mesh.firstIndex);
}

rhi::TextureHandle InferredLighting::render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) {
  const scene::Scene& s = scene.scene();
  const float aspect = static_cast<float>(settings_.width) / static_cast<float>(settings_.height);
  scene.setCamera(camera, aspect);
  uploadScene(device, s);
  const glm::mat4 viewProj = camera.viewProjection(aspect);
  const glm::mat4 view = glm::lookAtRH(camera.position, camera.target, camera.up);

  // Opaque meshes, and alpha meshes sorted by the view depth of their bounds' centres. Stipple
  // patterns go to alpha layers by depth, nearest first (§4: "dynamically based on the depth"),
  // so the nearest three layers never share a pattern; further ones reuse them in turn.
  std::vector<uint32_t> opaque, alpha;
  for (uint32_t i = 0; i < s.meshes.size(); ++i) {
    int mat = s.meshes[i].material;
    bool translucent = mat >= 0 && size_t(mat) < s.materials.size() && s.materials[mat].opacity < 1.0f;
    (translucent ? alpha : opaque).push_back(i);
  }
  auto viewDepth = [&](uint32_t i) {
    glm::vec3 c = 0.5f * (s.meshes[i].boundsMin + s.meshes[i].boundsMax);
    return -(view * glm::vec4(c, 1.0f)).z;
  };
  std::sort(alpha.begin(), alpha.end(), [&](uint32_t a, uint32_t b) { return viewDepth(a) < viewDepth(b); });
  std::map<uint32_t, uint32_t> pattern;
  for (size_t k = 0; k < alpha.size(); ++k) pattern[alpha[k]] = 1 + static_cast<uint32_t>(k % kStipplePatterns);

  // --- geometry pass ---
  {
    rhi::PassDesc pass;
    const char* names[] = {kNormals, kDsf, kSpecular};
    for (int i = 0; i < 3; ++i) pass.colors[i].texture = gpuTargets_->attachment(names[i]);
    pass.depthStencil.texture = gpuTargets_->attachment(kDepth);
    pass.depthStencil.clearStencil = 0;
    pass.label = "geometry";
    device.beginPass(pass);
    device.setPipeline(geometryOpaque_);
    for (uint32_t i : opaque) drawMesh(device, scene, i, 0);
    if (!alpha.empty()) {
      device.setPipeline(geometryAlpha_);
      for (uint32_t i : alpha) drawMesh(device, scene, i, pattern[i]);
    }
    device.endPass();
    for (const char* name : {kNormals, kDsf, kSpecular, kDepth})
      gpuTargets_->resolve(name);
  }

  // --- light pass ---
  {
    rhi::PassDesc pass;
    pass.colors[0].texture = gpuTargets_->attachment(kLBuffer);
    if (stencilVolumes_) {
      pass.depthStencil.texture = gpuTargets_->attachment(kDepth);
      pass.depthStencil.load = rhi::LoadOp::Load;  // scene depth for the volumes, stencil 0
    }
    pass.label = "light";
    device.beginPass(pass);
    rhi::ResourceBinding b[6];
    b[0].binding = 0;
    b[0].kind = rhi::BindingKind::UniformBuffer;
    b[0].buffer = scene.frameBuffer();
    b[1].binding = 1;
    b[1].kind = rhi::BindingKind::StorageBuffer;
    b[1].buffer = scene.lightBuffer();
    b[2].binding = 3;
    b[2].kind = rhi::BindingKind::UniformBuffer;
    b[2].buffer = params_;
    b[3] = sampled(4, gpuTargets_->readTexture(kNormals));
    b[4] = sampled(5, gpuTargets_->readTexture(kDepth));
    b[5] = sampled(6, gpuTargets_->readTexture(kSpecular));
    const rhi::Rect full{0, 0, reducedWidth_, reducedHeight_};
    auto lightQuad = [&](rhi::PipelineHandle pipeline, uint32_t lightIndex, uint32_t kind, const rhi::Rect& rect) {
      device.setPipeline(pipeline);
      device.setScissor(rect);
      device.setStencilReference(0);
      device.setBindings(b);
      scene::GpuMaterial m{};
      m.flags = glm::uvec4(0u, lightIndex, kind, 0u);
      device.pushConstants(&m, sizeof(m));
      device.draw(3);
    };
    // Ambient and directional light reach every pixel: no volume, no stencil test.
    lightQuad(globalLightPipeline_, 0, 1, full);
    for (uint32_t l = 0; l < s.lights.size(); ++l) {
      const scene::Light& light = s.lights[l];
      ScissorRect r = lightScissor(light, camera, settings_.width, settings_.height);
      if (r.empty()) continue;
      // Output pixels -> L-buffer texels, rounded outwards.
      const double sx = double(reducedWidth_) / settings_.width, sy = double(reducedHeight_) / settings_.height;
      int32_t x0 = std::clamp(int32_t(std::floor(r.x * sx)), 0, int32_t(reducedWidth_));
      int32_t y0 = std::clamp(int32_t(std::floor(r.y * sy)), 0, int32_t(reducedHeight_));
      int32_t x1 = std::clamp(int32_t(std::ceil((r.x + int32_t(r.width)) * sx)), 0, int32_t(reducedWidth_));
      int32_t y1 = std::clamp(int32_t(std::ceil((r.y + int32_t(r.height)) * sy)), 0, int32_t(reducedHeight_));
      if (x1 <= x0 || y1 <= y0) continue;
      const rhi::Rect rect{x0, y0, uint32_t(x1 - x0), uint32_t(y1 - y0)};
      if (stencilVolumes_) {
        device.setPipeline(stencilVolume_);
        device.setScissor(rect);
        glm::mat4 clipFromObject = viewProj * LightVolumes::model(light);
        device.pushConstants(&clipFromObject, sizeof(clipFromObject));
        volumes_->draw(light);
      }
      lightQuad(lightPipeline_, l, 0, rect);
    }
    device.endPass();
    gpuTargets_->resolve(kLBuffer);
  }

  // --- material pass ---
  {
    rhi::PassDesc pass;
    pass.colors[0].texture = output_->attachment(kOutputColor);
    pass.colors[0].clearColor = {0.0f, 0.0f, 0.0f, 1.0f};
    pass.depthStencil.texture = output_->attachment(kSceneDepth);
    pass.label = "material";
    device.beginPass(pass);
    rhi::ResourceBinding b[3];
    b[0].binding = 3;
    b[0].kind = rhi::BindingKind::UniformBuffer;
    b[0].buffer = params_;
    b[1] = sampled(4, gpuTargets_->readTexture(kLBuffer));
    b[2] = sampled(5, gpuTargets_->readTexture(kDsf));
    device.setPipeline(materialOpaque_);
    device.setBindings(b);
    for (uint32_t i : opaque) drawMesh(device, scene, i, 0);
    if (!alpha.empty()) {
      device.setPipeline(materialAlpha_);
      device.setBindings(b);
      for (auto it = alpha.rbegin(); it != alpha.rend(); ++it) drawMesh(device, scene, *it, pattern[*it]);
    }
    device.endPass();
  }
  return output_->present();
}

std::vector<NamedTarget> InferredLighting::targets() const {
  std::vector<NamedTarget> t;
  if (gpuTargets_)
    for (const char* name : {kNormals, kDsf, kSpecular, kDepth, kLBuffer}) t.push_back({name, gpuTargets_->attachment(name)});
  if (output_) {
    t.push_back({kOutputColor, output_->readTexture(kOutputColor)});
    t.push_back({kSceneDepth, output_->attachment(kSceneDepth)});
  }
  return t;
}

void InferredLighting::release(rhi::Device& device) {
  for (rhi::PipelineHandle* p : {&geometryOpaque_, &geometryAlpha_, &globalLightPipeline_, &lightPipeline_, &stencilVolume_, &materialOpaque_, &materialAlpha_})
    if (*p) {
      device.destroy(*p);
      *p = {};
    }
  output_.reset();
  for (rhi::BufferHandle* b : {&params_, &vertices_, &indices_})
    if (*b) {
      device.destroy(*b);
      *b = {};
    }
  uploadedScene_ = nullptr;
  volumes_.reset();
  gpuTargets_.reset();
  shaders_.reset();
}

}  // namespace parity::techniques
