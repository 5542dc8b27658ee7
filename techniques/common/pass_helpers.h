// Small pieces of pass set-up every multi-pass technique repeats.
#pragma once

#include <vector>

#include "platforms/platform_layer.h"
#include "rhi/rhi.h"
#include "scene/scene_gpu.h"

namespace parity::techniques {

// A sampled-texture binding (set 0) for setBindings().
inline rhi::ResourceBinding sampled(uint32_t binding, rhi::TextureHandle texture) {
  rhi::ResourceBinding b;
  b.binding = binding;
  b.kind = rhi::BindingKind::SampledTexture;
  b.texture = texture;
  return b;
}

// A storage-buffer binding (set 0), the whole buffer.
inline rhi::ResourceBinding storageBuffer(uint32_t binding, rhi::BufferHandle buffer) {
  rhi::ResourceBinding b;
  b.binding = binding;
  b.kind = rhi::BindingKind::StorageBuffer;
  b.buffer = buffer;
  return b;
}

// The format a platform plan renders the logical target `name` into (Undefined if not planned).
inline rhi::Format attachmentFormat(const platforms::TargetPlan& plan, const char* name) {
  const platforms::PhysicalTarget* t = plan.find(name);
  return t ? t->attachmentFormat : rhi::Format::Undefined;
}

// ONE + ONE on colour and alpha: light accumulation.
inline void enableAdditiveBlending(rhi::ColorTargetState& target) {
  target.blend.enabled = true;
  target.blend.srcColor = target.blend.dstColor = rhi::BlendFactor::One;
  target.blend.srcAlpha = target.blend.dstAlpha = rhi::BlendFactor::One;
}

// `bindings` plus the scene's frame block (binding 0) and light buffer (binding 1), which
// scene_data.glsl declares in every shader.
inline std::vector<rhi::ResourceBinding> withSceneBuffers(std::vector<rhi::ResourceBinding> bindings,
                                                         scene::SceneGpu& scene) {
  rhi::ResourceBinding frame;
  frame.binding = 0;
  frame.kind = rhi::BindingKind::UniformBuffer;
  frame.buffer = scene.frameBuffer();
  bindings.push_back(frame);
  rhi::ResourceBinding lights;
  lights.binding = 1;
  lights.kind = rhi::BindingKind::StorageBuffer;
  lights.buffer = scene.lightBuffer();
  bindings.push_back(lights);
  return bindings;
}

// A full-screen triangle (its vertex shader builds it from the vertex index), no material.
inline void drawFullScreenTriangle(rhi::Device& device) {
  scene::GpuMaterial noMaterial{};
  device.pushConstants(&noMaterial, sizeof(noMaterial));
  device.draw(3);
}

}  // namespace parity::techniques
