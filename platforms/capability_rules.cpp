// The platform's capability table (capabilities.h) as a rule layer over the command stream: what
// a pass binds, what a pipeline's shaders need and what a draw or dispatch reads, against what
// the platform can run at all. A lacking capability is an error with the capability's code; one
// the platform only allows (DX10's optional features) is W_CAP_OPTIONAL, as a port needs a
// fallback for it.
#include <string>

#include "platforms/common/capabilities.h"
#include "platforms/platform_rules.h"
#include "platforms/x360/edram.h"

namespace parity::platforms {

namespace {

class CapabilityRules final : public PlatformRules {
 public:
  explicit CapabilityRules(const PlatformCapabilities& caps) : caps_(caps) {}

  void beginPass(const PassState& pass, DiagnosticList& out) override {
    const CapabilityRow& edram = caps_.row(Capability::EdramBytes);
    if (edram.limit == 0) return;
    uint64_t bytes = 0;
    std::vector<std::string> names;
    auto add = [&](const PassAttachment& a) {
      if (!a.use.texture) return;
      bytes += edramBytes(a.use);
      names.push_back(a.use.label);
    };
    for (const PassAttachment& a : pass.colors) add(a);
    add(pass.depth);
    if (bytes > edram.limit)
      out.report(capabilityCode(Capability::EdramBytes), names,
                 "EDRAM bytes: the pass binds " + std::to_string(bytes) + " bytes of render targets at once; " +
                     describeRow(caps_.platform, edram));
  }

  void draw(const DrawState& s, DiagnosticList& out) override {
    if (s.pipeline->compute)
      dispatch(*s.pipeline, out);
    else
      graphics(s, out);
    for (const SampledTexture& t : s.sampled) {
      const FormatRow* row = formatRow(t.use);
      if (!row) continue;
      if (t.filtered)
        formatUse(row->filter, "E_CAP_FILTER_FORMAT", "filter", t.use, "is sampled with a Linear filter", *row, out);
      if (t.vertexStage)
        formatUse(row->vertexFetch, "E_CAP_VERTEX_FETCH_FORMAT", "vertex fetch", t.use, "is read by a vertex shader",
                  *row, out);
    }
  }

 private:
  // Bytes of EDRAM an attachment takes: its tiles of 80x16 samples (X1), 64-bit formats twice.
  static uint64_t edramBytes(const TextureUse& use) {
    const uint32_t bpp = use.surface ? use.surface->target.mapping.consoleBytesPerPixel
                                     : rhi::formatInfo(use.format).bytesPerTexel;
    const x360::MsaaSamples msaa = use.samples >= 4 ? x360::MsaaSamples::k4X
                                   : use.samples == 2 ? x360::MsaaSamples::k2X
                                                      : x360::MsaaSamples::k1X;
    return uint64_t(x360::surfaceSizeTiles(use.width, use.height, msaa, bpp > 4)) * x360::kEdramTileSizeBytes;
  }

  const FormatRow* formatRow(const TextureUse& use) const {
    if (use.surface) return caps_.format(use.surface->target.mapping.consoleFormat, use.format);
    return caps_.format({}, use.format);
  }

  // Reports what `support` says of a need: an error `code` when None, W_CAP_OPTIONAL when
  // Optional. `what` names the need, `row` the platform's value.
  void need(Support support, std::string_view code, std::vector<std::string> targets, const std::string& what,
            const std::string& value, DiagnosticList& out) const {
    if (support == Support::Guaranteed) return;
    if (support == Support::None)
      out.report(code, std::move(targets), what + "; " + value);
    else
      out.report("W_CAP_OPTIONAL", std::move(targets), what + "; " + value + ": a port needs a fallback");
  }
  void needRow(Capability c, std::vector<std::string> targets, const std::string& what, DiagnosticList& out) const {
    const CapabilityRow& row = caps_.row(c);
    need(row.support, capabilityCode(c), std::move(targets), std::string(capabilityName(c)) + ": " + what,
         describeRow(caps_.platform, row), out);
  }
  // A count against a limit row (limit 0: none of the platform's own).
  void limit(Capability c, uint32_t amount, std::vector<std::string> targets, const std::string& what,
             DiagnosticList& out) const {
    const CapabilityRow& row = caps_.row(c);
    if (amount == 0) return;
    if (row.support == Support::None || (row.limit != 0 && amount > row.limit))
      out.report(capabilityCode(c), std::move(targets),
                 std::string(capabilityName(c)) + ": " + what + " " + std::to_string(amount) + "; " +
                     describeRow(caps_.platform, row));
    else if (row.support == Support::Optional)
      needRow(c, std::move(targets), what + " " + std::to_string(amount), out);
  }
  void formatUse(Support support, std::string_view code, std::string_view use, const TextureUse& t,
                 const std::string& how, const FormatRow& row, DiagnosticList& out) const {
    need(support, code, {t.label},
         std::string(use) + ": " + t.label + " (" + std::string(row.console) + ") " + how,
         std::string(row.console) + " " + (support == Support::None ? "cannot" : "may") + " on " +
             std::string(platformName(caps_.platform)) + " (" + std::string(row.source) + ")",
         out);
  }

  void dispatch(const PipelineState& p, DiagnosticList& out) const {
    const CapabilityRow& compute = caps_.row(Capability::Compute);
    if (compute.support == Support::None) {
      needRow(Capability::Compute, {p.label}, "the dispatch needs compute shaders", out);
      return;  // its limits say nothing more of a platform without compute
    }
    needRow(Capability::Compute, {p.label}, "the dispatch needs compute shaders", out);
    const auto& g = p.workgroupSize;
    limit(Capability::ComputeInvocations, g[0] * g[1] * g[2], {p.label}, "a workgroup of invocations", out);
    if (g[2] > 1) limit(Capability::ComputeWorkgroupDepth, g[2], {p.label}, "a workgroup of depth", out);
    limit(Capability::ComputeSharedMemory, p.sharedBytes, {p.label}, "workgroup-shared bytes", out);
    if (p.atomics) needRow(Capability::ComputeAtomics, {p.label}, "the shader uses atomic operations", out);
    limit(Capability::ComputeStorageBuffers, p.storageBuffersWritten, {p.label}, "storage buffers written", out);
    if (p.storageImagesWritten > 0)
      needRow(Capability::ComputeStorageImages, {p.label}, "the shader writes typed storage images", out);
  }

  void graphics(const DrawState& s, DiagnosticList& out) const {
    const PipelineState& p = *s.pipeline;
    limit(Capability::ColorTargets, p.colorCount, {p.label}, "colour targets written", out);
    limit(Capability::FragmentTextures, p.fragmentTextures, {p.label}, "textures read by the fragment shader", out);
    limit(Capability::VertexTextures, p.vertexTextures, {p.label}, "textures read before rasterisation", out);
    limit(Capability::Interpolators, p.interpolators, {p.label}, "interpolated vec4 inputs", out);
    if (p.geometryStage) needRow(Capability::GeometryShaders, {p.label}, "the pipeline has a geometry shader", out);
    if (p.tessellationStages)
      needRow(Capability::TessellationShaders, {p.label}, "the pipeline has tessellation shaders", out);
    if (p.graphicsStorageWrites)
      needRow(Capability::GraphicsStorageWrites, {p.label}, "a graphics shader writes storage buffers or images", out);
    if (!s.pass) return;
    auto attachment = [&](const TextureUse& t, bool blended) {
      if (!t.texture) return;
      if (t.samples > 1) limit(Capability::Multisampling, t.samples, {t.label}, "samples per pixel of " + t.label, out);
      const FormatRow* row = formatRow(t);
      if (!row) return;
      formatUse(row->render, "E_CAP_RENDER_FORMAT", "render", t, "is rendered to", *row, out);
      if (blended) formatUse(row->blend, "E_CAP_BLEND_FORMAT", "blend", t, "is blended into", *row, out);
      if (t.samples > 1)
        formatUse(row->multisample, "E_CAP_MULTISAMPLE_FORMAT", "multisample", t, "is multisampled", *row, out);
    };
    for (uint32_t i = 0; i < p.colorCount && i < rhi::kMaxColorTargets; ++i)
      if (p.colors[i].writeMask != 0) attachment(s.pass->colors[i].use, p.colors[i].blend.enabled);
    if (p.depthTest || p.depthWrite || p.stencilWrite) attachment(s.pass->depth.use, false);
  }

  const PlatformCapabilities& caps_;
};

}  // namespace

std::unique_ptr<PlatformRules> makeCapabilityRules(PlatformId platform) {
  return std::make_unique<CapabilityRules>(platformCapabilities(platform));
}

}  // namespace parity::platforms
