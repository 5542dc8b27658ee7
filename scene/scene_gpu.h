// A scene uploaded to one device: vertex/index buffers, the per-frame uniform block and the
// light storage buffer whose layouts shaders/include/scene_data.glsl declares.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "rhi/rhi.h"
#include "scene/scene.h"

namespace parity::scene {

// std140 mirror of FrameData in scene_data.glsl.
struct FrameData {
  glm::mat4 viewProj;
  glm::vec4 cameraPos;
  glm::vec4 ambient;
  glm::vec4 directionalDir;
  glm::vec4 directionalColor;
  glm::uvec4 counts;
  glm::mat4 view;         // world -> view (right-handed, camera looks down -z)
  glm::mat4 invViewProj;  // clip -> world, for reconstructing positions from depth
  glm::vec4 nearFar;      // x near, y far
};
static_assert(sizeof(FrameData) == 288, "FrameData must match scene_data.glsl");

// std430 mirror of Light in scene_data.glsl.
struct GpuLight {
  glm::vec4 positionRadius;
  glm::vec4 colorK;
  glm::vec4 directionType;
  glm::vec4 cone;
};
static_assert(sizeof(GpuLight) == 64, "GpuLight must match scene_data.glsl");

// Push constants of scene_data.glsl's Material block.
struct GpuMaterial {
  glm::vec4 diffuse;
  glm::vec4 specular;
  glm::uvec4 flags;  // x: kMaterialDiffuseTexture | kMaterialNormalMap; y, z, w: per technique
};
static_assert(sizeof(GpuMaterial) == 48, "GpuMaterial must match scene_data.glsl");

// Bits of GpuMaterial::flags.x (MATERIAL_DIFFUSE_TEXTURE, MATERIAL_NORMAL_MAP in scene_data.glsl).
constexpr uint32_t kMaterialDiffuseTexture = 1u;
constexpr uint32_t kMaterialNormalMap = 2u;

// Binding of the material's normal map (normal_mapping.glsl); above every binding a technique
// uses for its own resources, so drawMesh() can bind it for every pass.
constexpr uint32_t kNormalMapBinding = 10;

class SceneGpu {
 public:
  SceneGpu(rhi::Device& device, const Scene& scene);
  ~SceneGpu();
  SceneGpu(const SceneGpu&) = delete;
  SceneGpu& operator=(const SceneGpu&) = delete;

  // Writes the frame block for a camera and output aspect ratio.
  void setCamera(const Camera& camera, float aspect);

  const Scene& scene() const { return scene_; }
  rhi::BufferHandle vertexBuffer() const { return vertices_; }
  rhi::BufferHandle indexBuffer() const { return indices_; }
  rhi::BufferHandle frameBuffer() const { return frame_; }
  rhi::BufferHandle lightBuffer() const { return lights_; }
  GpuMaterial material(int index) const;
  // The material's diffuse texture, or a 1x1 white texture.
  rhi::TextureHandle diffuseTexture(int materialIndex) const;
  // The material's normal map, or a 1x1 flat one (never sampled: flags.x says there is none).
  rhi::TextureHandle normalTexture(int materialIndex) const;
  rhi::SamplerHandle materialSampler() const { return sampler_; }

  // Vertex layout of scene::Vertex for PipelineDesc (locations 0, 1, 2 in slot 0).
  static void describeVertexLayout(rhi::PipelineDesc& desc);

  // Binds frame block (0), lights (1), the mesh's diffuse texture (2) and normal map
  // (kNormalMapBinding), pushes its material and draws it. The pipeline must be set.
  void drawMesh(const Mesh& mesh);
  // The same with the index of one light in the material block's flags.y, for techniques that
  // shade one light per pass (scene_data.glsl).
  void drawMesh(const Mesh& mesh, uint32_t lightIndex);

 private:
  rhi::Device& device_;
  const Scene& scene_;
  rhi::BufferHandle vertices_, indices_, frame_, lights_;
  std::vector<rhi::TextureHandle> textures_;
  rhi::TextureHandle white_, flatNormal_;
  rhi::SamplerHandle sampler_;
};

}  // namespace parity::scene
