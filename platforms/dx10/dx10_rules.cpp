// DX10 rules over a frame's command stream (platform_rules.h): depth is read only through an
// R24_UNORM_X8_TYPELESS view of a single-sample R24G8_TYPELESS resource, never while bound as
// the depth-stencil view, and after the copy (the plan's resolve) that follows its last depth
// write (D1).
#include "platforms/dx10/depth_read.h"
#include "platforms/platform_rules.h"

namespace parity::platforms::dx10 {

namespace {

class Rules final : public PlatformRules {
 public:
  void draw(const DrawState& d, DiagnosticList& out) override {
    for (const SampledTexture& t : d.sampled) {
      const Surface* s = t.use.surface;
      const bool depthTarget = s && s->target.logical.format == LogicalFormat::Depth24Stencil8;
      const bool depthTexture = rhi::isDepthFormat(t.use.format);  // a depth surface sampled itself
      if ((!depthTexture && !depthTarget) || (depthTexture && t.integer)) continue;  // stencil reads are no depth reads
      DepthRead read;
      read.resource = t.use.label;
      // The planned depth is an R24G8_TYPELESS resource (its copy the R24X8 view); a depth texture
      // of the technique's own in another format is R32_TYPELESS or R16_TYPELESS, read as float.
      if (depthTexture && t.use.format != rhi::Format::D24S8) {
        read.resourceFormat = DxgiFormat::R32_TYPELESS;
        read.srvFormat = DxgiFormat::R32_FLOAT;
      }
      read.sampleCount = t.use.samples;
      // The pass binds the same resource as its depth-stencil view (D3D10 has no read-only DSV).
      read.boundAsDsv = d.pass && d.pass->depth.use.texture && d.pass->depth.use.root == t.use.root;
      // The platform's copy, made after the last depth write; the depth surface itself is not. (The
      // copy of a depth nothing has written yet is a placeholder binding: nothing to be stale.)
      read.resolvedSinceLastDepthWrite =
          depthTarget && t.use.view == SurfaceView::Resolved && (!s->written || (s->resolved && !s->writtenSinceResolve));
      checkDepthRead(read, out);
    }
  }

  void resolve(const ResolveEvent& e, DiagnosticList& out) override {
    const Surface& s = *e.surface;
    if (s.target.logical.format == LogicalFormat::Depth24Stencil8 && s.target.samples > 1) {
      DepthRead read;
      read.resource = s.name();
      read.sampleCount = s.target.samples;
      checkDepthRead(read, out);
    }
  }
};

}  // namespace

std::unique_ptr<PlatformRules> makeRules(const PlatformParams&) { return std::make_unique<Rules>(); }

}  // namespace parity::platforms::dx10
