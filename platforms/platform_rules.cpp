#include "platforms/platform_rules.h"

namespace parity::platforms {

std::string_view surfaceViewName(SurfaceView view) {
  switch (view) {
    case SurfaceView::Attachment: return "surface";
    case SurfaceView::Bits: return "integer view";
    case SurfaceView::ReadView: return "read view";
    case SurfaceView::Resolved: return "resolved texture";
  }
  return "?";
}

std::unique_ptr<PlatformRules> makePlatformRules(PlatformId platform, const PlatformParams& params) {
  switch (platform) {
    case PlatformId::Reference: break;
    case PlatformId::Dx10: return dx10::makeRules(params);
    case PlatformId::Ps3: return ps3::makeRules(params);
    case PlatformId::X360: return x360::makeRules(params);
  }
  return std::make_unique<PlatformRules>();
}

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
}  // namespace

BlendState ruleBlend(const rhi::BlendState& b) {
  BlendState r;
  r.enabled = b.enabled;
  r.srcColor = ruleFactor(b.srcColor);
  r.dstColor = ruleFactor(b.dstColor);
  r.srcAlpha = ruleFactor(b.srcAlpha);
  r.dstAlpha = ruleFactor(b.dstAlpha);
  return r;
}

}  // namespace parity::platforms
