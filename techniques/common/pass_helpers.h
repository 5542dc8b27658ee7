// Small pieces of pass set-up every multi-pass technique repeats.
#pragma once

#include "platforms/platform_layer.h"
#include "rhi/rhi.h"

namespace parity::techniques {

// A sampled-texture binding (set 0) for setBindings().
inline rhi::ResourceBinding sampled(uint32_t binding, rhi::TextureHandle texture) {
  rhi::ResourceBinding b;
  b.binding = binding;
  b.kind = rhi::BindingKind::SampledTexture;
  b.texture = texture;
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

}  // namespace parity::techniques
