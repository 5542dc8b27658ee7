// The light volume part of the deferred techniques (thesis §3.1.4, "crude light volume geometry
// ... for point and spot lights"): every point light is drawn as a sphere, every spot light as a
// cone (techniques/common/light_volumes.h), so that only the pixels the light can reach run its
// shader. Deferred shading and the light pre-pass share it; they differ only in the fragment
// shader and the targets.
//
// Face set and depth test per light, against the scene's depth (depth writes off):
//   camera outside the volume: front faces, LESS_EQUAL: the surface lies behind the volume's
//     near side (a surface in front of the whole volume is rejected);
//   camera inside it (the near plane may cut the front faces away): back faces, GREATER_EQUAL:
//     the surface lies in front of the volume's far side.
// Either way every surface point within the light's reach is covered: the meshes enclose the
// exact volume, and the shader's attenuation and spot factor are 0 outside it.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rhi/rhi.h"
#include "scene/culling.h"
#include "scene/scene.h"
#include "scene/scene_gpu.h"
#include "techniques/common/light_volumes.h"

namespace parity::techniques {

class LightVolumePass {
 public:
  // `base` carries the shaders (vertex: deferred/light_volume.vert), colour targets with their
  // additive blending and the depth-stencil format; the face set and depth test are set here.
  LightVolumePass(rhi::Device& device, rhi::PipelineDesc base);
  ~LightVolumePass();
  LightVolumePass(const LightVolumePass&) = delete;
  LightVolumePass& operator=(const LightVolumePass&) = delete;

  bool ok() const { return outside_ && inside_ && volumes_; }

  // Outside a pass, once per frame: uploads every light's volume transform (binding 3 of
  // light_volume.vert) and resets the counts below.
  void upload(const scene::Scene& scene);
  // Which lights a draw() covers, and what runs before each of them (a per-light binding, such as
  // deferred-shadows' shadow block); empty: every light, nothing.
  struct LightFilter {
    std::function<bool(uint32_t light)> include;
    std::function<void(uint32_t light)> beforeDraw;
  };
  // Inside the pass: draws the volume of every light whose light list is not empty (a light that
  // reaches no visible mesh adds nothing). `bindings` are the fragment shader's resources; the
  // frame block (0), lights (1) and volume transforms (3) are bound here.
  void draw(scene::SceneGpu& scene, const scene::LightLists& lists, const scene::Camera& camera, float aspect,
            const std::vector<rhi::ResourceBinding>& bindings, const LightFilter& filter = {});

  // Lights drawn since the last upload(), and how many of them with the camera inside their volume.
  uint32_t drawnCount() const { return drawn_; }
  uint32_t insideCount() const { return inside_count_; }

 private:
  rhi::Device& device_;
  std::unique_ptr<LightVolumes> volumes_;
  rhi::PipelineHandle outside_, inside_;
  rhi::BufferHandle transforms_;
  size_t transformCapacity_ = 0;
  uint32_t drawn_ = 0, inside_count_ = 0;
};

}  // namespace parity::techniques
