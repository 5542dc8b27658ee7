// Shadow maps for the directional light and for point and spot lights (thesis §3.1): the
// directional map is orthographic over the scene's bounds (2048^2 in the thesis; a parameter
// here), a spot light gets one 512^2 perspective map over its cone, a point light a cube of six
// 512^2 faces rendered face by face. Only lights with scene::Light::castsShadows get a map (the
// directional light: scene::Scene::directionalCastsShadows, on by default), and one local map
// is reused from light to light, as the thesis's renderer does: render the light's map, shade
// with it, move on. The maps are the platform's depth targets (a plan per map size: D24S8 on the
// consoles, resolved or copied to be readable), and lookups filter percentage-closer in the
// shader on depth read as the platform reads it, with a texel-sized world-space depth bias
// (shaders/effects/shadow.glsl).
#pragma once

#include <array>
#include <memory>

#include <glm/glm.hpp>

#include "rhi/rhi.h"
#include "scene/scene.h"
#include "scene/scene_gpu.h"
#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace parity::techniques::effects {

struct ShadowSettings {
  uint32_t directionalSize = 2048;  // the thesis's size; smaller keeps CI fast
  uint32_t localSize = 512;         // spot map and each point-cube face
  // Where the lookups find ShadowData and the map (SHADOW_DATA_BINDING / SHADOW_MAP_BINDING of
  // shaders/effects/shadow.glsl, which must be defined to the same numbers when they differ).
  uint32_t dataBinding = 3, mapBinding = 4;
};

// std140 mirror of ShadowData in shaders/effects/shadow.glsl.
struct ShadowBlock {
  std::array<glm::mat4, 6> faces{};
  glm::vec4 params{0.0f};
  glm::vec4 lightPos{0.0f};
  glm::vec4 toLight{0.0f};
};
static_assert(sizeof(ShadowBlock) == 432, "ShadowBlock must match shadow.glsl");

// The shadow views of one light, computed on the CPU (tests project with the same matrices).
ShadowBlock directionalShadowBlock(const scene::Scene& scene, uint32_t mapSize);
ShadowBlock localShadowBlock(const scene::Light& light, uint32_t mapSize);
// A block that turns shadowing off (a light without castsShadows).
ShadowBlock noShadowBlock();

class ShadowMaps {
 public:
  // The maps' plans: the directional map, and the local map (a spot's, or a point light's six
  // faces as layers), each a depth target of its own size.
  static std::vector<Technique::SizedTargets> targetPlans(const ShadowSettings& settings);
  // Creates the maps (through the platform of `render`), the depth-only pipeline and one uniform
  // slot per shadow view of a frame.
  void prepare(rhi::Device& device, ShaderLibrary& shaders, const ShadowSettings& settings,
               const RenderSettings& render);
  // Computes the blocks of this frame (slot 0: directional, 1 + i: local light i) and uploads
  // them; call before any pass of the frame.
  void beginFrame(rhi::Device& device, const scene::SceneGpu& scene);
  // Renders the directional map (when the scene has a directional light that casts shadows;
  // otherwise clears it).
  void renderDirectional(rhi::Device& device, const scene::SceneGpu& scene);
  // Renders light i's map into the shared local map (when the light casts shadows).
  void renderLocal(rhi::Device& device, const scene::SceneGpu& scene, uint32_t lightIndex);
  // ShadowData and shadowMap (ShadowSettings::dataBinding, mapBinding) for shading with the directional light or light i.
  void bindDirectional(rhi::Device& device) const;
  void bindLocal(rhi::Device& device, uint32_t lightIndex) const;
  rhi::TextureHandle directionalMap() const { return directional_ ? directional_->attachment(kDirectional) : rhi::TextureHandle{}; }
  rhi::TextureHandle localMap() const { return local_ ? local_->attachment(kLocal) : rhi::TextureHandle{}; }
  static constexpr const char* kDirectional = "shadow.directional";
  static constexpr const char* kLocal = "shadow.local";
  void release(rhi::Device& device);

 private:
  void renderFaces(rhi::Device& device, const scene::SceneGpu& scene, PlannedTargets& map, const char* name,
                   const ShadowBlock& block, const char* label);
  void bind(rhi::Device& device, size_t slot, rhi::TextureHandle map) const;

  ShadowSettings settings_;
  rhi::PipelineHandle pipeline_;
  std::unique_ptr<PlannedTargets> directional_, local_;  // one plan per map size
  rhi::BufferHandle blocks_;
  size_t slotCount_ = 0;
  std::vector<ShadowBlock> frameBlocks_;
};

}  // namespace parity::techniques::effects
