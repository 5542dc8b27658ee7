// Xbox 360 rules over a frame's command stream (platform_rules.h): EDRAM is reachable only by the
// RB stage and resolves (X1); the surfaces a pass binds share RB_SURFACE_INFO, must fit and must
// not overlap, and a pass's writes clobber other surfaces' tiles (X1, X4: EdramFrame, one per
// plan, as each plan is placed on its own); multiplicative blending of fixed point (X2); the
// resolve rectangle and destination (X3); the pixel centres of screen-space passes (X5).
#include <cmath>
#include <map>
#include <optional>

#include "platforms/platform_rules.h"
#include "platforms/x360/edram_frame.h"
#include "platforms/x360/fixed16.h"
#include "platforms/x360/pixel_center.h"
#include "platforms/x360/resolve.h"
#include "platforms/x360/x360_platform.h"

namespace parity::platforms::x360 {

namespace {

bool fixedPoint(const Surface& s, const PlatformParams& params) {
  const LogicalFormat f = s.target.logical.format;
  return f == LogicalFormat::Rg16Unorm || (f == LogicalFormat::Rgba16Hdr && params.hdrFormat == X360HdrFormat::Fixed16x4);
}

class Rules final : public PlatformRules {
 public:
  explicit Rules(const PlatformParams& params) : params_(params) {}

  void beginPass(const PassState& pass, DiagnosticList& out) override {
    passCentre_.reset();
    modeChangeReported_ = false;
    depthWritten_ = false;
    std::map<uint32_t, std::vector<EdramFrame::Binding>> byPlan;
    auto bind = [&](const PassAttachment& a, bool depth) {
      if (!a.use.surface) return;
      // Colour targets are written by the pass; depth when the pass clears it (a draw that
      // writes a loaded depth is write() below).
      const bool loads = a.load == rhi::LoadOp::Load;
      byPlan[a.use.surface->plan].push_back({a.use.surface->name(), loads, !depth || !loads});
      frameOf(*a.use.surface);
    };
    for (const PassAttachment& a : pass.colors) bind(a, false);
    bind(pass.depth, true);
    for (const auto& [plan, bound] : byPlan) frames_.at(plan).pass(pass.label, bound, out);
  }

  void draw(const DrawState& d, DiagnosticList& out) override {
    for (const SampledTexture& s : d.sampled) sampled(d, s, out);
    if (!d.pass) return;
    const PipelineState& p = *d.pipeline;
    for (uint32_t i = 0; i < rhi::kMaxColorTargets; ++i) {
      const Surface* s = d.pass->colors[i].use.surface;
      if (s && fixedPoint(*s, params_) && p.colors[i].writeMask != 0)
        checkFixed16Blend(s->name(), ruleBlend(p.colors[i].blend), kGpuK16HostStorage, out);
    }
    const Surface* depth = d.pass->depth.use.surface;
    if (depth && !depthWritten_ && d.pass->depth.load == rhi::LoadOp::Load && (p.depthWrite || p.stencilWrite)) {
      depthWritten_ = true;
      frames_.at(depth->plan).write(d.pass->label, depth->name(), out);
    }
    pixelCentres(d, out);
  }

  void copy(const TextureUse& from, const TextureUse& to, DiagnosticList& out) override {
    if (!from.surface && from.renderedOutsidePlan)
      out.report("E_EDRAM_NOT_READABLE", {from.label},
                 "copyTexture reads " + from.label + ", a texture of the technique's own that a pass rendered into: "
                 "on the console an EDRAM surface, reachable only through a resolve (X1)");
    if (from.surface && from.view != SurfaceView::Resolved)
      out.report("E_EDRAM_NOT_READABLE", {from.surface->name()},
                 "copyTexture reads render target " + from.surface->name() + " (" +
                     std::string(surfaceViewName(from.view)) + ") into " + to.label +
                     "; EDRAM is only reachable by the RB stage and resolves (X1)");
  }

  void resolve(const ResolveEvent& e, DiagnosticList& out) override {
    const Surface& s = *e.surface;
    EdramFrame& frame = frameOf(s);
    // The padded surface's rectangle, or the one the technique asked for, into the destination
    // texture as the port allocates it.
    ResolveRequest request = wholeSurfaceResolve(s.width, s.height);
    if (!e.whole) request.rect = {e.rect.x, e.rect.y, e.rect.width, e.rect.height};
    if (e.averaging) request.sampleSelect = CopySampleSelect::k0123;
    frame.resolve(s.name(), request, s.name() + " (resolved)", out);
  }

  void forgetPlan(uint32_t plan) override { frames_.erase(plan); }

 private:
  EdramFrame& frameOf(const Surface& s) {
    EdramFrame& f = frames_.try_emplace(s.plan, params_).first->second;
    if (!f.has(s.name())) {
      EdramSurface e = edramSurface(s.target, s.width, s.height, params_);
      f.declare(e, !e.isDepth && s.target.logical.readLater);
    }
    return f;
  }

  // A texture read by a shader: EDRAM (the surface or a view of it) is unreachable, a resolved
  // texture must hold what the surface holds now. (A resolved texture of a surface nothing has
  // rendered yet is a placeholder binding, such as a shadow map bound for a light that casts
  // none: whether the shader reads it is its branch's business, so it is not reported.)
  void sampled(const DrawState& d, const SampledTexture& t, DiagnosticList& out) {
    const Surface* s = t.use.surface;
    const std::string where = d.pass ? d.pass->label : d.pipeline->label;
    if (!s && t.use.renderedOutsidePlan && !t.storage) {
      out.report("E_EDRAM_NOT_READABLE", {t.use.label},
                 where + " samples " + t.use.label + ", a texture of the technique's own that a pass rendered into: "
                         "on the console that render target is an EDRAM surface, reachable only through a resolve; plan "
                         "it (GpuTargets) and sample its resolved texture (X1)");
      return;
    }
    if (!s) return;
    if (t.use.view != SurfaceView::Resolved) {
      out.report("E_EDRAM_NOT_READABLE", {s->name()},
                 where + " samples render target " + s->name() + " (its " + std::string(surfaceViewName(t.use.view)) +
                     ") at binding " + std::to_string(t.binding) +
                     "; EDRAM is only reachable by the RB stage and resolves: resolve it and sample the texture (X1)");
    } else if (s->written && !s->resolved) {
      out.report("E_EDRAM_NOT_READABLE", {s->name()},
                 where + " samples the resolved texture of " + s->name() + " at binding " + std::to_string(t.binding) +
                     " before any resolve of it: the texture holds nothing the surface rendered (X1)");
    } else if (s->writtenSinceResolve) {
      out.report("E_EDRAM_NOT_READABLE", {s->name()},
                 where + " samples the resolved texture of " + s->name() + " at binding " + std::to_string(t.binding) +
                     ", but " + s->name() + " was rendered to after its last resolve: the texture holds the older "
                     "contents; resolve it again first (X1)");
    }
  }

  // X5: a screen-space pass that samples coordinates interpolated from its vertices, at D3D9
  // centres without the -0.5 a D3D9 port adds; and the convention changing within a pass.
  void pixelCentres(const DrawState& d, DiagnosticList& out) {
    if (d.pixelCenterOffset == 0) return;  // HALFPIXELOFFSET: the host's centres
    const float frac = d.viewportX - std::floor(d.viewportX);
    const bool d3d9 = std::fabs(frac - d.pixelCenterOffset) < 1e-3f;
    if (passCentre_ && *passCentre_ != d3d9 && !modeChangeReported_) {
      modeChangeReported_ = true;
      out.report("I_HALFPIXEL_MODE_CHANGE", {},
                 d.pass->label + ": the draws of the pass use both pixel-centre conventions (some viewports offset by "
                                 "-0.5 to D3D10 centres, some not): PIX_CENTER flips within the pass (X5)");
    }
    passCentre_ = d3d9;
    const PipelineState& p = *d.pipeline;
    // Screen space: positions made from the vertex index, or a quad or triangle of at most six
    // vertices drawn once without a depth test or stencil writes (a post-process quad from a
    // vertex buffer; the A-buffer's stencil-routed translucent quad is scene geometry).
    const bool screenSpace =
        p.screenSpace || (d.vertices <= 6 && d.instances == 1 && !p.depthTest && !p.stencilWrite);
    if (!d3d9 || !screenSpace || !p.samplesInterpolatedCoordinates) return;
    std::vector<std::string> textures;
    for (const SampledTexture& t : d.sampled)
      if (!t.storage) textures.push_back(t.use.label);
    if (textures.empty()) return;
    std::string list;
    for (const std::string& t : textures) list += (list.empty() ? "" : ", ") + t;
    out.report("W_D3D9_PIXEL_CENTER", textures,
               p.label + " is a screen-space draw at D3D9 pixel centres (PIX_CENTER = 0) that samples " + list +
                   " at coordinates interpolated from its vertices, with no -0.5 offset: every pixel samples a texel "
                   "corner; offset its viewport by -TargetPlan::pixelCenterOffset (X5)");
  }

  PlatformParams params_;
  std::map<uint32_t, EdramFrame> frames_;
  std::optional<bool> passCentre_;
  bool modeChangeReported_ = false;
  bool depthWritten_ = false;
};

}  // namespace

std::unique_ptr<PlatformRules> makeRules(const PlatformParams& params) { return std::make_unique<Rules>(params); }

}  // namespace parity::platforms::x360
