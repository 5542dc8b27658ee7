#include "techniques/effects/shadow_maps.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

namespace parity::techniques::effects {

namespace {

// Uniform-buffer offsets must be multiples of the strictest alignment either API asks for.
constexpr size_t kSlotBytes = 512;

// Vulkan-style projection (rhi.h conventions), as scene::Camera::viewProjection builds it.
glm::mat4 flipY(glm::mat4 proj) {
  proj[1][1] = -proj[1][1];
  return proj;
}

glm::vec3 anyPerpendicular(glm::vec3 d) {
  return std::abs(d.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
}

}  // namespace

ShadowBlock noShadowBlock() { return ShadowBlock{}; }

ShadowBlock directionalShadowBlock(const scene::Scene& scene, uint32_t mapSize) {
  ShadowBlock b;
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const scene::Mesh& m : scene.meshes) lo = glm::min(lo, m.boundsMin), hi = glm::max(hi, m.boundsMax);
  if (scene.meshes.empty()) lo = hi = glm::vec3(0.0f);
  glm::vec3 center = (lo + hi) * 0.5f;
  float radius = std::max(glm::length(hi - lo) * 0.5f, 1e-3f);
  glm::vec3 dir = glm::normalize(scene.directionalDir);
  glm::mat4 view = glm::lookAtRH(center - dir * (radius * 2.0f), center, anyPerpendicular(dir));
  // A square fitted around the bounding sphere: the map covers every caster and receiver.
  glm::mat4 proj = flipY(glm::orthoRH_ZO(-radius, radius, -radius, radius, radius, radius * 3.0f));
  b.faces[0] = proj * view;
  b.params = glm::vec4(1.0f, 2.0f * radius / static_cast<float>(mapSize), 0.0f, 0.0f);
  b.toLight = glm::vec4(-dir, 1.0f);
  return b;
}

ShadowBlock localShadowBlock(const scene::Light& light, uint32_t mapSize) {
  ShadowBlock b;
  float nearPlane = std::max(light.radius * 1e-3f, 1e-3f);
  if (light.type == scene::LightType::Spot) {
    float halfAngle = std::acos(std::clamp(light.cosOuter, -1.0f, 1.0f));
    halfAngle = std::min(halfAngle * 1.05f + 0.02f, glm::radians(85.0f));  // margin for PCF at the cone's edge
    glm::vec3 dir = glm::normalize(light.direction);
    glm::mat4 view = glm::lookAtRH(light.position, light.position + dir, anyPerpendicular(dir));
    glm::mat4 proj = flipY(glm::perspectiveRH_ZO(2.0f * halfAngle, 1.0f, nearPlane, light.radius));
    b.faces[0] = proj * view;
    b.params = glm::vec4(1.0f, 2.0f * std::tan(halfAngle) / static_cast<float>(mapSize), 0.0f, 0.0f);
  } else {
    // Slightly wider than 90 degrees so that PCF at a face's border reads texels of that face.
    float halfAngle = std::atan(1.0f + 2.0f / static_cast<float>(mapSize));
    glm::mat4 proj = flipY(glm::perspectiveRH_ZO(2.0f * halfAngle, 1.0f, nearPlane, light.radius));
    const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int f = 0; f < 6; ++f)
      b.faces[f] = proj * glm::lookAtRH(light.position, light.position + axes[f], anyPerpendicular(axes[f]));
    b.params = glm::vec4(6.0f, 2.0f * std::tan(halfAngle) / static_cast<float>(mapSize), 0.0f, 0.0f);
  }
  b.lightPos = glm::vec4(light.position, 1.0f);
  return b;
}

std::vector<Technique::SizedTargets> ShadowMaps::targetPlans(const ShadowSettings& settings) {
  auto map = [](const char* name, const char* pass, uint32_t size, uint32_t layers) {
    platforms::LogicalTarget t = sceneDepthTarget(pass, true);
    t.name = name;
    t.arrayLayers = layers;
    return Technique::SizedTargets{pass, {size, size}, {t}};
  };
  return {map(kDirectional, "shadow directional", settings.directionalSize, 1),
          map(kLocal, "shadow local", settings.localSize, 6)};
}

void ShadowMaps::prepare(rhi::Device& device, ShaderLibrary& shaders, const ShadowSettings& settings,
                         const RenderSettings& render) {
  settings_ = settings;
  const std::vector<Technique::SizedTargets> plans = targetPlans(settings);
  directional_ = std::make_unique<PlannedTargets>(device, render, plans[0].targets, "shadows", plans[0].extent);
  local_ = std::make_unique<PlannedTargets>(device, render, plans[1].targets, "shadows", plans[1].extent);
  rhi::PipelineDesc p;
  p.vertexShader = shaders.load("effects/shadow_depth.vert");
  p.fragmentShader = shaders.load("effects/shadow_depth.frag");
  scene::SceneGpu::describeVertexLayout(p);
  // Both faces: closed meshes and single-sided occluders (a floating quad) both cast.
  p.raster.cull = rhi::CullMode::None;
  p.depthStencil.depthCompare = rhi::CompareOp::Less;
  p.depthStencil.depthWrite = true;
  p.depthStencilFormat = directional_->format(kDirectional);
  p.label = "shadow depth";
  pipeline_ = device.createPipeline(p);
  if (!pipeline_) throw TechniqueError("shadows: the device rejected the shadow-map pipeline");
}

void ShadowMaps::beginFrame(rhi::Device& device, const scene::SceneGpu& scene) {
  const scene::Scene& sc = scene.scene();
  frameBlocks_.assign(1 + sc.lights.size(), noShadowBlock());
  bool directional = glm::length(sc.directionalColor) > 0.0f && sc.directionalCastsShadows;
  if (directional) frameBlocks_[0] = directionalShadowBlock(sc, settings_.directionalSize);
  for (size_t i = 0; i < sc.lights.size(); ++i)
    if (sc.lights[i].castsShadows) frameBlocks_[1 + i] = localShadowBlock(sc.lights[i], settings_.localSize);
  if (frameBlocks_.size() > slotCount_) {
    if (blocks_) device.destroy(blocks_);
    rhi::BufferDesc b;
    b.size = kSlotBytes * frameBlocks_.size();
    b.usage = rhi::BufferUsage_Uniform;
    b.label = "shadow blocks";
    blocks_ = device.createBuffer(b);
    if (!blocks_) throw TechniqueError("shadows: cannot create the shadow uniform buffer");
    slotCount_ = frameBlocks_.size();
  }
  std::vector<uint8_t> bytes(kSlotBytes * frameBlocks_.size(), 0);
  for (size_t i = 0; i < frameBlocks_.size(); ++i) std::memcpy(bytes.data() + i * kSlotBytes, &frameBlocks_[i], sizeof(ShadowBlock));
  device.writeBuffer(blocks_, 0, bytes.data(), bytes.size());
}

void ShadowMaps::renderFaces(rhi::Device& device, const scene::SceneGpu& scene, PlannedTargets& map, const char* name,
                             const ShadowBlock& block, const char* label) {
  uint32_t faces = static_cast<uint32_t>(block.params.x + 0.5f);
  for (uint32_t f = 0; f < faces; ++f) {
    rhi::PassDesc pass;
    pass.depthStencil.texture = map.attachment(name);
    pass.depthStencil.layer = f;
    pass.label = label;
    device.beginPass(pass);
    device.setPipeline(pipeline_);
    device.pushConstants(&block.faces[f], sizeof(glm::mat4));
    device.setVertexBuffer(0, scene.vertexBuffer());
    device.setIndexBuffer(scene.indexBuffer(), rhi::IndexType::UInt32);
    for (const scene::Mesh& mesh : scene.scene().meshes) device.drawIndexed(mesh.indexCount, 1, mesh.firstIndex);
    device.endPass();
  }
  map.resolve(name);  // x360: out of EDRAM; dx10: the R24X8 copy; ps3: the ARGB8 view
}

void ShadowMaps::renderDirectional(rhi::Device& device, const scene::SceneGpu& scene) {
  const ShadowBlock& block = frameBlocks_.at(0);
  if (block.params.x > 0.5f) {
    renderFaces(device, scene, *directional_, kDirectional, block, "shadow directional");
    return;
  }
  // No lookup reads the map then, but it is still a listed target: clear it to "nothing casts"
  // rather than leave a previous frame's casters in it.
  rhi::PassDesc pass;
  pass.depthStencil.texture = directional_->attachment(kDirectional);
  pass.label = "shadow directional";
  device.beginPass(pass);
  device.endPass();
  directional_->resolve(kDirectional);
}

void ShadowMaps::renderLocal(rhi::Device& device, const scene::SceneGpu& scene, uint32_t lightIndex) {
  renderFaces(device, scene, *local_, kLocal, frameBlocks_.at(1 + lightIndex), "shadow local");
}

void ShadowMaps::bind(rhi::Device& device, size_t slot, rhi::TextureHandle map) const {
  rhi::ResourceBinding b[2];
  b[0].binding = settings_.dataBinding;
  b[0].kind = rhi::BindingKind::UniformBuffer;
  b[0].buffer = blocks_;
  b[0].offset = slot * kSlotBytes;
  b[0].size = sizeof(ShadowBlock);
  b[1].binding = settings_.mapBinding;
  b[1].kind = rhi::BindingKind::SampledTexture;
  b[1].texture = map;  // texelFetch only: no sampler state applies
  device.setBindings(b);
}

void ShadowMaps::bindDirectional(rhi::Device& device) const { bind(device, 0, directional_->readTexture(kDirectional)); }
void ShadowMaps::bindLocal(rhi::Device& device, uint32_t lightIndex) const {
  bind(device, 1 + lightIndex, local_->readTexture(kLocal));
}

void ShadowMaps::release(rhi::Device& device) {
  device.destroy(pipeline_);
  directional_.reset();
  local_.reset();
  if (blocks_) device.destroy(blocks_);
  blocks_ = {};
  slotCount_ = 0;
}

}  // namespace parity::techniques::effects
