#include "platforms/platform_device.h"

#include "platforms/platform_layer.h"
#include "platforms/ps3/packed16.h"
#include "platforms/x360/fixed16.h"

namespace parity::platforms {

namespace {

BlendFactor ruleFactor(rhi::BlendFactor f) {
  switch (f) {
    case rhi::BlendFactor::Zero: return BlendFactor::Zero;
    case rhi::BlendFactor::One: return BlendFactor::One;
    case rhi::BlendFactor::SrcColor: return BlendFactor::SrcColor;
    case rhi::BlendFactor::OneMinusSrcColor: return BlendFactor::OneMinusSrcColor;
    case rhi::BlendFactor::DstColor: return BlendFactor::DestColor;
    case rhi::BlendFactor::OneMinusDstColor: return BlendFactor::OneMinusDestColor;
    case rhi::BlendFactor::SrcAlpha: return BlendFactor::SrcAlpha;
    case rhi::BlendFactor::OneMinusSrcAlpha: return BlendFactor::OneMinusSrcAlpha;
    case rhi::BlendFactor::DstAlpha: return BlendFactor::DestAlpha;
    case rhi::BlendFactor::OneMinusDstAlpha: return BlendFactor::OneMinusDestAlpha;
    case rhi::BlendFactor::ConstantColor:
    case rhi::BlendFactor::OneMinusConstantColor: return BlendFactor::ConstantAlpha;
  }
  return BlendFactor::One;
}

BlendState ruleBlend(const rhi::BlendState& b) {
  BlendState r;
  r.enabled = b.enabled;
  r.srcColor = ruleFactor(b.srcColor);
  r.dstColor = ruleFactor(b.dstColor);
  r.srcAlpha = ruleFactor(b.srcAlpha);
  r.dstAlpha = ruleFactor(b.dstAlpha);
  return r;
}

}  // namespace

PlatformDevice::PlatformDevice(rhi::Device& host, PlatformId platform, const PlatformParams& params)
    : ForwardingDevice(host), platform_(platform), params_(params), offset_(hostPixelCenterOffset(platform, params)) {}

void PlatformDevice::registerTarget(rhi::TextureHandle texture, const std::string& name, LogicalFormat format,
                                    std::function<void()> afterPass, bool blendedOnly) {
  if (texture) targets_[texture.id] = {name, format, std::move(afterPass), blendedOnly};
}

rhi::PipelineHandle PlatformDevice::createPipeline(const rhi::PipelineDesc& d) {
  rhi::PipelineHandle h = inner().createPipeline(d);
  if (h) {
    auto& colors = pipelines_[h.id];
    for (uint32_t i = 0; i < rhi::kMaxColorTargets; ++i) colors[i] = i < d.colorTargetCount ? d.colorTargets[i] : rhi::ColorTargetState{};
  }
  return h;
}

void PlatformDevice::destroy(rhi::PipelineHandle h) {
  pipelines_.erase(h.id);
  inner().destroy(h);
}

rhi::TextureHandle PlatformDevice::createTexture(const rhi::TextureDesc& d) {
  rhi::TextureHandle h = inner().createTexture(d);
  if (h) ownTextures_[h.id] = d.label;
  return h;
}

rhi::TextureHandle PlatformDevice::createTextureView(const rhi::TextureViewDesc& d) {
  rhi::TextureHandle h = inner().createTextureView(d);
  if (h) ownTextures_[h.id] = d.label;
  return h;
}

void PlatformDevice::destroy(rhi::TextureHandle h) {
  ownTextures_.erase(h.id);
  inner().destroy(h);
}

void PlatformDevice::beginPass(const rhi::PassDesc& d) {
  auto noteUnplanned = [&](rhi::TextureHandle t) {
    auto own = ownTextures_.find(t.id);
    if (t && own != ownTextures_.end() && !targets_.count(t.id)) unplanned_.insert(d.label + ": " + own->second);
  };
  for (uint32_t i = 0; i < rhi::kMaxColorTargets; ++i) {
    passColors_[i] = d.colors[i].texture;
    noteUnplanned(d.colors[i].texture);
    noteUnplanned(d.colors[i].resolveTarget);
  }
  noteUnplanned(d.depthStencil.texture);
  afterPass_.clear();
  inner().beginPass(d);
}

void PlatformDevice::endPass() {
  inner().endPass();
  std::map<uint32_t, std::function<void()>> after;
  after.swap(afterPass_);
  for (const auto& [id, f] : after) f();  // outside the technique's pass
}

void PlatformDevice::draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) {
  checkDraw();
  inner().draw(vertexCount, instanceCount, firstVertex, firstInstance);
}

void PlatformDevice::drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                                 uint32_t firstInstance) {
  checkDraw();
  inner().drawIndexed(indexCount, instanceCount, firstIndex, vertexOffset, firstInstance);
}

// The draw-level rules of the platform on the bound pipeline and the pass's platform targets.
void PlatformDevice::checkDraw() {
  auto p = pipelines_.find(pipeline_);
  if (p == pipelines_.end()) return;
  DiagnosticList found;
  for (uint32_t i = 0; i < rhi::kMaxColorTargets; ++i) {
    if (!passColors_[i]) continue;
    auto t = targets_.find(passColors_[i].id);
    if (t == targets_.end()) continue;
    const rhi::ColorTargetState& state = p->second[i];
    if ((state.blend.enabled || !t->second.blendedOnly) && state.writeMask != 0 && t->second.afterPass)
      afterPass_[t->first] = t->second.afterPass;  // once per pass and target
    const bool twoChannels16 = t->second.format == LogicalFormat::Rg16Unorm;
    if (platform_ == PlatformId::Ps3 && twoChannels16) {
      ps3::PackedTargetDraw draw;
      draw.target = t->second.name;
      draw.blend = ruleBlend(state.blend);
      draw.writeMask = ps3::consoleWriteMaskOfHost(state.writeMask);  // the rule speaks of console channels
      ps3::checkPackedTargetDraw(draw, found);
    }
    const bool fixed16x4 = t->second.format == LogicalFormat::Rgba16Hdr && params_.hdrFormat == X360HdrFormat::Fixed16x4;
    if (platform_ == PlatformId::X360 && (twoChannels16 || fixed16x4))
      x360::checkFixed16Blend(t->second.name, ruleBlend(state.blend), x360::kGpuK16HostStorage, found);
  }
  report(found);
}

void PlatformDevice::setPipeline(rhi::PipelineHandle h) {
  pipeline_ = h.id;
  inner().setPipeline(h);  // resets the viewport to the whole pass...
  if (offset_ != 0) setViewport({});  // ...which moves with the pixel centres too
}

void PlatformDevice::setViewport(const rhi::Viewport& vp) {
  rhi::Viewport moved = vp;  // width and height 0 keep meaning "the whole attachment"
  moved.x += offset_;
  moved.y += offset_;
  inner().setViewport(moved);
}

void PlatformDevice::report(const DiagnosticList& found) {
  for (const Diagnostic& d : found.all()) {
    bool seen = false;
    for (const Diagnostic& e : diagnostics_.all()) seen = seen || (e.code == d.code && e.message == d.message);
    if (!seen) diagnostics_.report(d.code, d.targets, d.message);
  }
}

PlatformDevice* asPlatformDevice(rhi::Device& device) { return dynamic_cast<PlatformDevice*>(&device); }

rhi::Device& hostDevice(rhi::Device& device) {
  if (PlatformDevice* p = asPlatformDevice(device)) return p->inner();
  return device;
}

}  // namespace parity::platforms
