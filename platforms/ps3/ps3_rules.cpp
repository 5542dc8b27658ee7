// PS3 rules over a frame's command stream (platform_rules.h): one colour format (or one bits per
// pixel) for the targets a pass binds and one blend function for them (P1), RSX's missing
// two-channel 16-bit surface (P1), packed16x2 targets written, read, filtered and resolved (P2,
// P3), depth read through its A8R8G8B8 view (P4).
#include "platforms/platform_rules.h"
#include "platforms/ps3/depth_read.h"
#include "platforms/ps3/packed16.h"
#include "platforms/ps3/surface.h"

namespace parity::platforms::ps3 {

namespace {

// What RSX allocates for a planned target, or for a texture the technique created itself (by
// its host format); nullopt for a format outside the rules (depth, formats without an RSX row).
std::optional<ColorSurface> rsxSurface(const TextureUse& use, DiagnosticList& out) {
  SurfaceRequest r;
  r.name = use.label;
  LogicalFormat logical;
  if (use.surface) {
    logical = use.surface->target.logical.format;
  } else {
    switch (use.format) {
      case rhi::Format::RGBA8:
      case rhi::Format::RGBA8_SRGB: logical = LogicalFormat::Rgba8Unorm; break;
      case rhi::Format::RGBA16F: logical = LogicalFormat::Rgba16Hdr; break;
      case rhi::Format::R8: logical = LogicalFormat::R8Unorm; break;
      case rhi::Format::R32F: logical = LogicalFormat::R32Float; break;
      case rhi::Format::RGBA32F:
        r.bitsPerChannel = 32;
        r.isFloat = true;
        return requestColorSurface(r, out);
      case rhi::Format::RG16_UNORM:
      case rhi::Format::RG16_SNORM:
      case rhi::Format::RG16_UINT:
      case rhi::Format::RG16_FLOAT:
        // A two-channel 16-bit texture of the technique's own: no RSX surface, and no packing.
        r.channels = 2;
        r.bitsPerChannel = 16;
        r.isFloat = use.format == rhi::Format::RG16_FLOAT;
        r.allowPacking = false;
        return requestColorSurface(r, out);
      default: return std::nullopt;
    }
  }
  switch (logical) {
    case LogicalFormat::Rg16Unorm:
      r.channels = 2;
      r.bitsPerChannel = 16;
      break;
    case LogicalFormat::Rgba16Hdr:
      r.bitsPerChannel = 16;
      r.isFloat = true;
      break;
    case LogicalFormat::R8Unorm: r.channels = 1; break;
    case LogicalFormat::R32Float:
      r.channels = 1;
      r.bitsPerChannel = 32;
      r.isFloat = true;
      break;
    case LogicalFormat::Depth24Stencil8: return std::nullopt;
    default: break;
  }
  return requestColorSurface(r, out);
}

bool packed(const Surface* s) { return s && s->target.logical.format == LogicalFormat::Rg16Unorm; }
bool depth(const Surface* s) { return s && s->target.logical.format == LogicalFormat::Depth24Stencil8; }

class Rules final : public PlatformRules {
 public:
  explicit Rules(const PlatformParams& params) : params_(params) {}

  void beginPass(const PassState& pass, DiagnosticList& out) override {
    surfaces_.clear();
    slots_.clear();
    for (uint32_t i = 0; i < rhi::kMaxColorTargets; ++i) {
      const PassAttachment& a = pass.colors[i];
      if (!a.use.texture) continue;
      if (std::optional<ColorSurface> s = rsxSurface(a.use, out)) {
        surfaces_.push_back(*s);
        slots_.push_back(i);
      }
      if (packed(a.use.surface) && a.use.samples > 1 && a.resolvesTo)
        checkPackedResolve(a.use.label, true, a.use.samples, true, out);
    }
    checkMrt(pass.label, surfaces_, params_.ps3MrtRule, out);
  }

  void draw(const DrawState& d, DiagnosticList& out) override {
    for (const SampledTexture& t : d.sampled) sampled(d, t, out);
    if (!d.pass) return;
    const PipelineState& p = *d.pipeline;
    for (uint32_t i = 0; i < rhi::kMaxColorTargets; ++i) {
      const TextureUse& target = d.pass->colors[i].use;
      if (!packed(target.surface) || p.colors[i].writeMask == 0) continue;
      PackedTargetDraw draw;
      draw.target = target.label;
      draw.blend = ruleBlend(p.colors[i].blend);
      draw.writeMask = consoleWriteMaskOfHost(p.colors[i].writeMask);  // the rule speaks of console channels
      checkPackedTargetDraw(draw, out);
    }
    // One blend function for every target of the pass (P1).
    std::vector<ColorSurface> blended = surfaces_;
    for (size_t k = 0; k < blended.size(); ++k) blended[k].blend = ruleBlend(p.colors[slots_[k]].blend);
    checkSharedBlend(d.pass->label, blended, out);
  }

  void resolve(const ResolveEvent& e, DiagnosticList& out) override {
    if (packed(e.surface)) checkPackedResolve(e.surface->name(), true, e.surface->target.samples, e.averaging, out);
  }

 private:
  void sampled(const DrawState& d, const SampledTexture& t, DiagnosticList& out) {
    const Surface* s = t.use.surface;
    if (packed(s) && t.use.view == SurfaceView::Attachment) {
      // The A8R8G8B8 bytes of packed data instead of its Y16_X16 view.
      PackedTextureRead read;
      read.texture = s->name();
      read.viewFormat = kTextureA8R8G8B8;
      read.filter = t.filtered ? Filter::Linear : Filter::Nearest;
      checkPackedTextureRead(read, out);
    }
    if (depth(s)) {
      DepthAsColorRead read;
      read.surface = s->name();
      // Filtering is the trap of the A8R8G8B8 view (the depth surface sampled as depth filters
      // depth values, PCF among them).
      read.minFilter = read.magFilter = t.filtered && t.use.view != SurfaceView::Attachment ? Filter::Linear : Filter::Nearest;
      // The depth surface is bound for depth writes by the draw that reads it (its A8R8G8B8 view
      // is the same memory on RSX; the host reads a copy, so only the rule can see it).
      read.boundForDepthWrite = d.pass && d.pass->depth.use.surface == s && d.pipeline->depthWrite;
      checkDepthAsColorRead(read, out);
    }
  }

  PlatformParams params_;
  std::vector<ColorSurface> surfaces_;  // the pass's colour targets as RSX surfaces
  std::vector<uint32_t> slots_;         // the attachment slot of each
};

}  // namespace

std::unique_ptr<PlatformRules> makeRules(const PlatformParams& params) { return std::make_unique<Rules>(params); }

}  // namespace parity::platforms::ps3
