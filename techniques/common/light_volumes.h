// Light volumes for the deferred techniques (thesis §3.1.2: a sphere per point light, a cone per
// spot light, rasterised so that only the pixels a light can reach are shaded).
//
// The meshes are unit shapes that ENCLOSE the exact volume (a sphere tessellated coarsely lies
// inside the sphere it approximates, which would drop lit pixels at the rim; these are scaled out
// so that every face lies outside it). Draw them with lightVolumeModel() and
// cameraInsideLightVolume() to pick the face set: outside, front faces with depth test LESS_EQUAL;
// inside (the near plane cuts the volume), back faces with depth test GREATER_EQUAL and no depth
// clipping concerns, so the light still reaches every pixel it covers.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "rhi/rhi.h"
#include "scene/scene.h"

namespace parity::techniques {

class LightVolumes {
 public:
  explicit LightVolumes(rhi::Device& device);
  ~LightVolumes();
  LightVolumes(const LightVolumes&) = delete;
  LightVolumes& operator=(const LightVolumes&) = delete;

  // Vertex layout: one vec3 position at location 0, slot 0, stride 12.
  static void describeVertexLayout(rhi::PipelineDesc& desc);
  // Binds the vertex and index buffers of the light's shape and draws it (pipeline, bindings and
  // push constants are the caller's). Instance count 1.
  void draw(const scene::Light& light);

  // Object-to-world matrix of the light's volume: unit sphere scaled by the radius; unit cone
  // (apex at the origin, axis +Z, length 1, base radius tan(outer angle)) rotated to the spot
  // direction and scaled by the radius.
  static glm::mat4 model(const scene::Light& light);

 private:
  rhi::Device& device_;
  rhi::BufferHandle vertices_, indices_;
  uint32_t sphereFirstIndex_ = 0, sphereIndexCount_ = 0, sphereBaseVertex_ = 0;
  uint32_t coneFirstIndex_ = 0, coneIndexCount_ = 0, coneBaseVertex_ = 0;
};

// True when the camera's near plane may intersect the light's volume (the camera is inside it or
// closer to it than the near plane's half-diagonal), so its front faces can be clipped away:
// render back faces with an inverted depth test instead. Conservative: it may say true for a
// camera just outside.
bool cameraInsideLightVolume(const scene::Light& light, const scene::Camera& camera, float aspect);

// Screen rectangle (pixels, top-left origin, clamped to the image) that bounds the light's
// volume, for per-light scissoring (inferred lighting §3, Trebilco §2). The whole image when the
// camera is inside the volume.
struct ScissorRect {
  int32_t x = 0, y = 0;
  uint32_t width = 0, height = 0;
  bool empty() const { return width == 0 || height == 0; }
};
ScissorRect lightScissor(const scene::Light& light, const scene::Camera& camera, uint32_t width, uint32_t height);

}  // namespace parity::techniques
