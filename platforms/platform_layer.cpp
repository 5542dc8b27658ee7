#include "platforms/platform_layer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>

#include "platforms/platform_device.h"
#include "platforms/platforms.h"
#include "platforms/ps3/remap.h"
#include "platforms/x360/edram.h"
#include "platforms/x360/fixed16.h"
#include "platforms/x360/float7e3.h"
#include "platforms/x360/pixel_center.h"
#include "platforms/x360/resolve.h"

namespace parity::platforms {

namespace {
std::vector<float> asFloatTexels(const std::vector<uint8_t>& bytes) {
  std::vector<float> f(bytes.size() / 4);
  std::memcpy(f.data(), bytes.data(), f.size() * 4);
  return f;
}

// x360 4x: which host sample of the MSAA attachment holds each guest sample (X1), as defines.
void addHostSampleDefines(std::vector<std::pair<std::string, std::string>>& defines) {
  for (uint32_t s = 0; s < 4; ++s)
    defines.push_back({"PARITY_HOST_SAMPLE_" + std::to_string(s),
                       std::to_string(x360::hostSampleIndex(x360::MsaaSamples::k4X, s))});
}

// A platform pass's shader counts into the PlatformDevice's counters (GpuTargets::countingInto).
bool counting(const std::vector<std::pair<std::string, std::string>>& defines) {
  return std::find(defines.begin(), defines.end(), std::pair<std::string, std::string>{"PARITY_COUNT", "1"}) !=
         defines.end();
}

// An x360 Rgba16Hdr target under x360.hdr_format = k_2_10_10_10_float.
bool isFloat7e3(const TargetPlan& plan, const PhysicalTarget& t) {
  return plan.platform == PlatformId::X360 && t.logical.format == LogicalFormat::Rgba16Hdr &&
         plan.params.hdrFormat == X360HdrFormat::Float7e3;
}

// The samples of `t` and how a later pass reads them (LogicalTarget::samples, readSamples).
void planSamples(PlatformId platform, PhysicalTarget& t) {
  t.samples = t.logical.samples == 4 ? 4 : 1;
  if (t.samples == 1) return;
  const std::string perPixel = t.resolve.description;
  if (t.logical.readSamples && platform == PlatformId::X360) {
    t.resolve.needed = t.logical.readLater;
    t.resolve.description = "one point resolve per sample (copy_sample_select k0..k3) into the layers of an array "
                            "texture; each: " + perPixel;
  } else if (t.logical.readSamples) {
    t.resolve = {false, "none: a later pass reads each sample of the multisampled texture", t.resolve.effectiveBits};
  } else if (platform == PlatformId::X360) {
    t.resolve.description += "; the 4 samples averaged (copy_sample_select k0123)";
  } else {
    t.resolve.needed = t.logical.readLater;
    t.resolve.description = "the host's MSAA resolve (the average of the 4 samples)";
    if (platform == PlatformId::Ps3)
      t.resolve.description += "; RSX keeps 4x as a 2W x 2H surface (SQUARE_CENTERED_4, P5), the host at its own "
                               "sample positions";
  }
}
}  // namespace

const PhysicalTarget* TargetPlan::find(const std::string& name) const {
  for (const PhysicalTarget& t : targets)
    if (t.logical.name == name) return &t;
  return nullptr;
}

void applyTargetRow(const TargetRow& row, PhysicalTarget& t) {
  const rhi::Format host = row.format == LogicalFormat::Output ? t.logical.outputFormat : row.hostFormat;
  t.mapping = {row.format, std::string(row.consoleFormat), row.consoleBytesPerPixel, host, std::string(row.write),
               std::string(row.read), std::string(row.source)};
  t.attachmentFormat = host;
  t.readFormat = row.readFormat == rhi::Format::Undefined ? host : row.readFormat;
  t.readViewFormat = row.readViewFormat;
  t.rawViewFormat = row.rawViewFormat;
  t.writeFormat = row.writeFormat == rhi::Format::Undefined ? host : row.writeFormat;
  t.resolve = {row.resolvedWhenRead && t.logical.readLater, std::string(row.resolve), row.effectiveBits};
}

namespace {
// `l` as `platform` plans it on its own: its row, what the parameters add, its samples.
PhysicalTarget planTarget(PlatformId platform, const LogicalTarget& l, const PlatformParams& params) {
  PhysicalTarget t;
  t.logical = l;
  switch (platform) {
    case PlatformId::Reference: reference::planTarget(t, params); break;
    case PlatformId::Dx10: dx10::planTarget(t, params); break;
    case PlatformId::Ps3: ps3::planTarget(t, params); break;
    case PlatformId::X360: x360::planTarget(t, params); break;
  }
  planSamples(platform, t);
  return t;
}

PhysicalTarget planFormat(PlatformId platform, LogicalFormat format, const PlatformParams& params) {
  LogicalTarget l;
  l.format = format;
  return planTarget(platform, l, params);
}
}  // namespace

TargetMapping mapTarget(PlatformId platform, LogicalFormat logical, const PlatformParams& params) {
  return planFormat(platform, logical, params).mapping;
}

double rg16EffectiveBits(PlatformId platform, const PlatformParams& params) {
  return planFormat(platform, LogicalFormat::Rg16Unorm, params).resolve.effectiveBits;
}

double depthEffectiveBits(PlatformId platform) {
  return planFormat(platform, LogicalFormat::Depth24Stencil8, {}).resolve.effectiveBits;
}

float hostPixelCenterOffset(PlatformId platform, const PlatformParams& params) {
  if (platform != PlatformId::X360) return 0.0f;
  return x360::hostWindowOffset(x360::pixelCenterFor(params.halfPixelOffset, params));
}

TargetPlan planTargets(PlatformId platform, std::span<const LogicalTarget> targets, uint32_t width, uint32_t height,
                       const PlatformParams& params) {
  TargetPlan plan;
  plan.platform = platform;
  plan.params = params;
  plan.width = width;
  plan.height = height;
  plan.pixelCenterOffset = hostPixelCenterOffset(platform, params);
  for (const LogicalTarget& l : targets) plan.targets.push_back(planTarget(platform, l, params));
  switch (platform) {
    case PlatformId::Reference: reference::shaderDefines(params, plan.shaderDefines); break;
    case PlatformId::Dx10: dx10::shaderDefines(params, plan.shaderDefines); break;
    case PlatformId::Ps3:
      ps3::shaderDefines(params, plan.shaderDefines);
      break;
    case PlatformId::X360:
      x360::shaderDefines(params, plan.shaderDefines);
      x360::checkPlan(plan);
      break;
  }
  return plan;
}

std::string platformShaderDirectory() { return rhi::shaderDirectory() + "/platforms"; }

rhi::ShaderCompileOptions platformShaderOptions(const TargetPlan& plan) {
  rhi::ShaderCompileOptions o;
  o.includeDirs.push_back(platformShaderDirectory());
  o.defines = plan.shaderDefines;
  return o;
}

// ---------------------------------------------------------------------------------------------
// GpuTargets
// ---------------------------------------------------------------------------------------------

GpuTargets::GpuTargets(rhi::Device& device, const TargetPlan& plan) : dev_(hostDevice(device)), plan_(plan) {
  diagnosticsSink_ = asPlatformDevice(device);
  if (diagnosticsSink_) {
    diagnosticsSink_->report(plan_.diagnostics);
    planId_ = diagnosticsSink_->newPlanId();
  }
  for (const PhysicalTarget& t : plan_.targets) {
    Entry e;
    e.target = &t;
    rhi::TextureDesc d;
    d.format = t.attachmentFormat;
    d.width = plan_.width;
    d.height = plan_.height;
    d.samples = t.samples;
    if (t.logical.arrayLayers > 0) {
      d.type = rhi::TextureType::Tex2DArray;
      d.layers = t.logical.arrayLayers;
    }
    d.label = t.logical.name;
    e.attachment = dev_.createTexture(d);
    // A view of `parent` in `format`, labelled "<name> (<what>)"; none when the plan names no format.
    auto viewIn = [&](rhi::TextureHandle parent, rhi::Format format, const char* what) {
      if (format == rhi::Format::Undefined) return rhi::TextureHandle{};
      rhi::TextureViewDesc v;
      v.parent = parent;
      v.format = format;
      v.label = t.logical.name + " (" + what + ")";
      return dev_.createTextureView(v);
    };
    if (t.logical.arrayLayers > 0 && t.resolve.needed)
      for (uint32_t layer = 0; layer < t.logical.arrayLayers; ++layer) {
        rhi::TextureViewDesc v;
        v.parent = e.attachment;
        v.baseLayer = layer;
        v.layerCount = 1;
        v.label = t.logical.name + " (layer " + std::to_string(layer) + ")";
        e.attachmentLayers.push_back(dev_.createTextureView(v));
      }
    e.rawView = viewIn(e.attachment, t.rawViewFormat, "bits");
    bool separateRead = t.resolve.needed || (t.inEdram && t.logical.format != LogicalFormat::Depth24Stencil8 &&
                                             t.readFormat != t.attachmentFormat);
    if (t.resolve.needed || separateRead) {
      rhi::TextureDesc r = d;
      r.format = t.readFormat;
      r.samples = 1;  // a resolve writes single-sample texels
      if (t.logical.readSamples && t.samples > 1) {  // one layer per sample
        r.type = rhi::TextureType::Tex2DArray;
        r.layers = t.samples;
      }
      r.label = t.logical.name + " (resolved)";
      e.read = dev_.createTexture(r);
      e.readRawView = viewIn(e.read, t.rawViewFormat, "resolved bits");
    } else {
      e.read = e.attachment;
    }
    e.readView = viewIn(e.read, t.readViewFormat, "read view");
    if (diagnosticsSink_) {
      // The textures through which the technique's calls reach the surface, and the pass the
      // platform stores its values with after every pass that draws into it: the shaders write
      // x360 fixed point and 7e3 unclamped (and unrounded), the render backend's store is this pass.
      const std::string name = t.logical.name;
      std::function<void()> afterPass;
      if (isFloat7e3(plan_, t))
        afterPass = [this, name] { quantiseFloat7e3(name); };
      else if (plan_.platform == PlatformId::X360 && t.logical.format == LogicalFormat::Rgba16Hdr)
        afterPass = [this, name] { clampFixedPoint(name); };
      PlatformDevice::SurfaceTextures textures;
      textures.attachment = e.attachmentLayers;
      textures.attachment.insert(textures.attachment.begin(), e.attachment);
      textures.bits = e.rawView;
      if (e.read != e.attachment) {
        textures.resolved = e.read;
        textures.resolvedViews = {e.readView, e.readRawView};
      } else {
        textures.readView = e.readView;
      }
      e.surface = diagnosticsSink_->registerSurface(planId_, t, plan_.width, plan_.height, textures, std::move(afterPass));
    }
    entries_[t.logical.name] = e;
  }
}

GpuTargets::~GpuTargets() {
  for (auto& [name, p] : pipelines_) dev_.destroy(p);
  for (rhi::ShaderHandle s : shaders_) dev_.destroy(s);
  if (diagnosticsSink_) diagnosticsSink_->forgetPlan(planId_);  // the handles may be reused once destroyed
  for (auto& [name, e] : entries_) {
    for (rhi::TextureHandle v : e.attachmentLayers) dev_.destroy(v);
    if (e.readView) dev_.destroy(e.readView);
    if (e.readRawView) dev_.destroy(e.readRawView);
    if (e.rawView) dev_.destroy(e.rawView);
    if (e.read && e.read != e.attachment) dev_.destroy(e.read);
    if (e.scratch) dev_.destroy(e.scratch);
    if (e.attachment) dev_.destroy(e.attachment);
  }
}

rhi::TextureHandle GpuTargets::attachment(const std::string& name) const {
  auto it = entries_.find(name);
  return it == entries_.end() ? rhi::TextureHandle{} : it->second.attachment;
}

rhi::TextureHandle GpuTargets::writeTarget(const std::string& name) const {
  auto it = entries_.find(name);
  if (it == entries_.end()) return {};
  const Entry& e = it->second;
  return e.target->writeFormat == e.target->rawViewFormat && e.rawView ? e.rawView : e.attachment;
}

rhi::TextureHandle GpuTargets::readTexture(const std::string& name) const {
  auto it = entries_.find(name);
  if (it == entries_.end()) return {};
  return it->second.readView ? it->second.readView : it->second.read;
}

rhi::PipelineHandle GpuTargets::pipeline(const std::string& fragmentFile, rhi::Format colorFormat,
                                         std::vector<std::pair<std::string, std::string>> defines,
                                         const rhi::BlendState& blend, uint32_t samples) {
  std::string key = fragmentFile + "|" + std::to_string(int(colorFormat)) + "|" + std::to_string(samples) + "|" +
                    std::to_string(int(blend.enabled)) + std::to_string(int(blend.colorOp)) +
                    std::to_string(int(blend.alphaOp));
  for (const auto& [k, v] : defines) key += "|" + k + "=" + v;
  auto it = pipelines_.find(key);
  if (it != pipelines_.end()) return it->second;
  rhi::ShaderCompileOptions options;
  options.defines = std::move(defines);
  const std::string dir = platformShaderDirectory();
  rhi::CompiledShader vs = rhi::compileGlslFile(dir + "/fullscreen.vert", rhi::ShaderStage::Vertex, options);
  rhi::CompiledShader fs = rhi::compileGlslFile(dir + "/" + fragmentFile, rhi::ShaderStage::Fragment, options);
  if (!vs.ok() || !fs.ok()) {
    error_ = vs.error + fs.error;
    return {};
  }
  rhi::ShaderDesc sd;
  sd.stage = rhi::ShaderStage::Vertex;
  sd.spirv = vs.spirv;
  sd.label = "fullscreen.vert";
  rhi::ShaderHandle v = dev_.createShader(sd);
  sd.stage = rhi::ShaderStage::Fragment;
  sd.spirv = fs.spirv;
  sd.label = fragmentFile;
  rhi::ShaderHandle f = dev_.createShader(sd);
  shaders_.push_back(v);
  shaders_.push_back(f);
  rhi::PipelineDesc pd;
  pd.vertexShader = v;
  pd.fragmentShader = f;
  pd.colorTargets[0].format = colorFormat;
  pd.colorTargets[0].blend = blend;
  pd.colorTargetCount = 1;
  pd.samples = samples;
  pd.label = fragmentFile;
  rhi::PipelineHandle p = dev_.createPipeline(pd);
  pipelines_[key] = p;
  return p;
}

std::array<float, 4> GpuTargets::clearColor(const std::string& name, const std::array<float, 4>& v) const {
  const PhysicalTarget* t = plan_.find(name);
  if (!t || plan_.platform != PlatformId::X360 || t->logical.format != LogicalFormat::Rgba16Hdr) return v;
  if (isFloat7e3(plan_, *t))
    return x360::unpackFloat7e3x3Unorm2(x360::packFloat7e3x3Unorm2(v));  // the value a 7e3 surface holds
  std::array<float, 4> host{};  // as parityWriteRgba16Hdr stores it
  for (size_t c = 0; c < 4; ++c) host[c] = static_cast<float>(x360::encodeFixed16(v[c]).value) * (1.0f / 32768.0f);
  return host;
}

std::vector<std::pair<std::string, std::string>> GpuTargets::countingInto(const Entry& e, TexelCounters::Slot slot,
                                                                         std::vector<rhi::ResourceBinding>* bindings,
                                                                         uint32_t* index) {
  TexelCounters* counters = diagnosticsSink_ ? diagnosticsSink_->counters() : nullptr;
  if (!counters) return {{"PARITY_COUNT", "0"}};
  slot.target = e.target->logical.name;
  if (slot.pass.empty()) slot.pass = diagnosticsSink_->lastPassOf(e.surface);
  *index = counters->open(std::move(slot));
  if (!counters->buffer()) return {{"PARITY_COUNT", "0"}};
  rhi::ResourceBinding b;
  b.binding = TexelCounters::kBinding;
  b.kind = rhi::BindingKind::StorageBuffer;
  b.buffer = counters->buffer();
  bindings->push_back(b);
  return {{"PARITY_COUNT", "1"}};
}

void GpuTargets::storeThrough(Entry& e, const std::string& what, const std::string& fragmentFile,
                              TexelCounters::Slot slot) {
  const PhysicalTarget& t = *e.target;
  if (!e.scratch) {  // a copy of the surface to read while the pass rewrites it
    rhi::TextureDesc d;
    d.format = t.attachmentFormat;
    d.width = plan_.width;
    d.height = plan_.height;
    d.samples = t.samples;
    d.label = t.logical.name + " (copy for the platform's store)";
    e.scratch = dev_.createTexture(d);
  }
  rhi::ResourceBinding source;
  source.binding = 0;
  source.kind = rhi::BindingKind::SampledTexture;
  source.texture = e.scratch;
  std::vector<rhi::ResourceBinding> bindings = {source};
  uint32_t index = 0;
  std::vector<std::pair<std::string, std::string>> defines = countingInto(e, std::move(slot), &bindings, &index);
  if (t.samples > 1) defines.push_back({"PARITY_STORE_MSAA", "1"});
  rhi::PipelineHandle p = pipeline(fragmentFile, t.attachmentFormat, defines, {}, t.samples);
  if (!p || !e.scratch) return;
  if (t.samples == 1) {
    dev_.copyTexture(e.attachment, e.scratch);
  } else {  // the RHI copies no multisampled texture: a pass copies it sample by sample
    rhi::PipelineHandle copy = pipeline("x360/copy_samples.frag", t.attachmentFormat, {}, {}, t.samples);
    if (!copy) return;
    rhi::PassDesc c;
    c.colors[0].texture = e.scratch;
    c.colors[0].load = rhi::LoadOp::DontCare;
    c.label = "copy of " + t.logical.name;
    rhi::ResourceBinding surface = source;
    surface.texture = e.attachment;
    dev_.beginPass(c);
    dev_.setPipeline(copy);
    dev_.setBindings({&surface, 1});
    dev_.draw(3);
    dev_.endPass();
  }
  rhi::PassDesc pass;
  pass.colors[0].texture = e.attachment;
  pass.colors[0].load = rhi::LoadOp::DontCare;
  pass.label = what + " of " + t.logical.name;
  dev_.beginPass(pass);
  dev_.setPipeline(p);
  dev_.setBindings(bindings);
  if (counting(defines)) dev_.pushConstants(&index, sizeof(index));
  dev_.draw(3);
  dev_.endPass();
}

void GpuTargets::quantiseFloat7e3(const std::string& name) {
  auto it = entries_.find(name);
  if (it == entries_.end() || !isFloat7e3(plan_, *it->second.target)) return;
  TexelCounters::Slot slot;
  slot.codes[0] = "W_FLOAT7E3_RANGE_CLAMP";
  slot.what[0] = "samples of " + name + " hold a colour outside k_2_10_10_10_FLOAT's [0, 31.875] (or NaN): stored "
                 "as 0 below, 31.875 above (X2)";
  storeThrough(it->second, "7e3 rounding", "x360/float7e3_quantise.frag", std::move(slot));
}

void GpuTargets::clampFixedPoint(const std::string& name) {
  auto it = entries_.find(name);
  if (it == entries_.end() || plan_.platform != PlatformId::X360) return;
  if (it->second.target->logical.format != LogicalFormat::Rgba16Hdr || isFloat7e3(plan_, *it->second.target)) return;
  TexelCounters::Slot slot;
  slot.codes = {"W_FIXED16_RANGE_CLAMP", "W_FIXED16_NAN"};
  slot.what[0] = "samples of " + name + " hold a value beyond k_16_16_16_16's -32...32: clamped to +-32 (X2)";
  slot.what[1] = "samples of " + name + " hold NaN: stored as 0 (X2)";
  storeThrough(it->second, "fixed-point clamp", "x360/fixed16_clamp.frag", std::move(slot));
}

bool GpuTargets::resolve(const std::string& name, uint32_t sourceSamples, const rhi::Rect& rect) {
  auto it = entries_.find(name);
  if (it == entries_.end()) return false;
  Entry& e = it->second;
  const PhysicalTarget& t = *e.target;
  if (!t.resolve.needed) return true;
  const bool whole = rect.width == 0 || rect.height == 0;
  if (!whole && (rect.x < 0 || rect.y < 0 || uint64_t(rect.x) + rect.width > plan_.width ||
                 uint64_t(rect.y) + rect.height > plan_.height)) {
    error_ = "resolve rectangle (" + std::to_string(rect.x) + ", " + std::to_string(rect.y) + ") " +
             std::to_string(rect.width) + "x" + std::to_string(rect.height) + " lies outside " + name + " (" +
             std::to_string(plan_.width) + "x" + std::to_string(plan_.height) + ")";
    return false;
  }
  if (diagnosticsSink_) {  // the platform's rules see the resolve as the technique asked for it
    ResolveEvent event;
    event.whole = whole;
    event.rect = whole ? rhi::Rect{0, 0, plan_.width, plan_.height} : rect;
    event.averaging = (t.samples > 1 && !t.logical.readSamples) || sourceSamples > 1;
    diagnosticsSink_->resolved(e.surface, event);
  }
  if (!recordResolve(e, name, sourceSamples, whole || plan_.platform != PlatformId::X360 ? rhi::Rect{} : rect)) {
    if (plan_.platform == PlatformId::Dx10 && t.samples > 1 && t.logical.format == LogicalFormat::Depth24Stencil8)
      error_ += " (E_DX10_MSAA_DEPTH_READ)";
    return false;
  }
  return true;
}

bool GpuTargets::recordResolve(Entry& e, const std::string& name, uint32_t sourceSamples, const rhi::Rect& rect) {
  const PhysicalTarget& t = *e.target;
  const bool partial = rect.width != 0;
  if (partial && (sourceSamples > 1 || (t.samples > 1 && t.logical.readSamples) || t.logical.arrayLayers > 0)) {
    error_ = "x360: no rectangle resolve of " + name + " (Xenos 2x rows, per-sample or layered targets resolve whole)";
    return false;
  }
  if (t.logical.arrayLayers > 0 && t.logical.format != LogicalFormat::Depth24Stencil8) {
    error_ = "no resolve of a layered " + std::string(logicalFormatName(t.logical.format)) + " target (" + name + ")";
    return false;
  }
  if (t.samples > 1 && plan_.platform != PlatformId::X360) {
    if (t.logical.format == LogicalFormat::Depth24Stencil8) {
      error_ = std::string(platformName(plan_.platform)) + ": no resolve of a multisampled depth (" + name + ")";
      return false;
    }
    rhi::PassDesc pass;  // the host's MSAA resolve at the end of an empty pass
    pass.colors[0].texture = e.attachment;
    pass.colors[0].load = rhi::LoadOp::Load;
    pass.colors[0].resolveTarget = e.read;
    pass.label = "resolve " + name;
    dev_.beginPass(pass);
    dev_.endPass();
    return true;
  }
  if (t.samples > 1 && t.logical.readSamples) return resolveEachSample(e, name);
  std::string file;
  rhi::Format outFormat = rhi::Format::Undefined;
  rhi::TextureHandle out = e.read;
  std::vector<rhi::ResourceBinding> bindings;
  std::vector<std::pair<std::string, std::string>> defines;
  uint32_t countSlot = 0;  // pushed to every resolve shader (those that count read it)
  auto sampled = [](uint32_t binding, rhi::TextureHandle tex) {
    rhi::ResourceBinding b;
    b.binding = binding;
    b.kind = rhi::BindingKind::SampledTexture;
    b.texture = tex;
    return b;
  };
  switch (plan_.platform) {
    case PlatformId::Reference:
      if (t.logical.format == LogicalFormat::Depth24Stencil8)  // the copy the reference reads depth through
        for (uint32_t layer = 0; layer < std::max(1u, t.logical.arrayLayers); ++layer) {
          rhi::ReadbackRegion r;
          r.layer = layer;
          dev_.copyTexture(e.attachment, e.read, r, r);
        }
      return true;
    case PlatformId::Dx10:
      if (t.logical.format != LogicalFormat::Depth24Stencil8) return true;
      file = "dx10/depth_to_r24x8.frag";
      outFormat = rhi::Format::R32_UINT;
      bindings.push_back(sampled(0, e.attachment));
      break;
    case PlatformId::Ps3:
      if (t.logical.format != LogicalFormat::Depth24Stencil8) return true;
      file = "ps3/depth_as_argb8.frag";
      outFormat = rhi::Format::RGBA8;
      bindings.push_back(sampled(0, e.attachment));
      bindings.push_back(sampled(1, e.attachment));
      break;
    case PlatformId::X360:
      if (t.samples == 4 && t.logical.format == LogicalFormat::Depth24Stencil8) {
        error_ = "x360: no GPU resolve of a 4x depth surface (" + name + ")";
        return false;
      }
      if (t.logical.format == LogicalFormat::Depth24Stencil8) {
        file = "x360/resolve_depth.frag";
        outFormat = rhi::Format::R32_UINT;
        bindings.push_back(sampled(0, e.attachment));
        bindings.push_back(sampled(1, e.attachment));
      } else if (t.logical.format == LogicalFormat::Rg16Unorm) {
        x360::DsfPathSpec path = x360::dsfPath(plan_.params.dsfResolvePath);
        const bool signedDest = path.destNumber == x360::SurfaceNumberFormat::kSignedRepeatingFraction;
        file = "x360/resolve_k16.frag";
        outFormat = rhi::Format::RG16_UINT;
        out = e.readRawView;
        bindings.push_back(sampled(0, e.rawView));
        defines = {{"PARITY_K16_UNPACK_MIN",
                    plan_.params.k16UnpackClamp == K16UnpackClamp::Minus1 ? "-1.0" : "-32.0"},
                   {"PARITY_RESOLVE_SAMPLES", t.samples == 4 ? "4" : sourceSamples >= 2 ? "2" : "1"},
                   {"PARITY_RESOLVE_EXP_BIAS", std::to_string(path.destExpBias)},
                   {"PARITY_RESOLVE_SIGNED", signedDest ? "1" : "0"},
                   {"PARITY_SIGNED_K16_RESOLVE", std::to_string(int(plan_.params.signedK16Resolve))}};
        if (t.samples == 4) addHostSampleDefines(defines);
        // An unsigned destination clamps what it cannot hold: counted per texel (X3).
        const bool unsignedDest = !signedDest || plan_.params.signedK16Resolve == SignedK16Resolve::UnsignedSaturate;
        if (unsignedDest) {
          TexelCounters::Slot slot;
          slot.pass = "resolve " + name;
          slot.codes = {"W_RESOLVE_SIGN_LOSS", "W_RESOLVE_RANGE_CLAMP"};
          slot.what[0] = "texels of " + name + " hold negative values, resolved into an unsigned k_16_16 texture: "
                         "clamped to 0 (X3, path " + std::string(path.name) + ")";
          slot.what[1] = "texels of " + name + " exceed 1 after the resolve's exponent bias " +
                         std::to_string(path.destExpBias) + ", resolved into an unsigned k_16_16 texture: clamped "
                         "to 1 (X3, path " + std::string(path.name) + ")";
          for (auto& d : countingInto(e, std::move(slot), &bindings, &countSlot)) defines.push_back(d);
        }
      } else if (isFloat7e3(plan_, t) && t.samples == 1 && !partial) {
        dev_.copyTexture(e.attachment, e.read);  // k_2_10_10_10_FLOAT -> k_2_10_10_10_FLOAT: a bit copy
        return true;
      } else if (isFloat7e3(plan_, t)) {
        file = "x360/resolve_average.frag";  // the samples' values averaged, then stored as 7e3
        outFormat = t.readFormat;
        bindings.push_back(sampled(0, e.attachment));
        defines = {{"PARITY_RESOLVE_UNORM8", "0"}, {"PARITY_RESOLVE_7E3", "1"}};
        addHostSampleDefines(defines);
      } else if (t.logical.format == LogicalFormat::Rgba16Hdr) {
        file = "x360/resolve_k16x4.frag";
        outFormat = rhi::Format::RGBA32F;
        bindings.push_back(sampled(0, e.attachment));
        if (t.samples == 4) {
          defines = {{"PARITY_RESOLVE_SAMPLES", "4"},
                     {"PARITY_K16_UNPACK_MIN",
                      plan_.params.k16UnpackClamp == K16UnpackClamp::Minus1 ? "-1.0" : "-32.0"}};
        }
      } else if (t.samples == 4) {
        // k_8_8_8_8 (R8 in its red) or k_32_FLOAT, averaged. Bytes are averaged as the resolve
        // packs them; a float host surface (k_32_FLOAT, or an Output the harness asked for in
        // float) keeps the float average.
        file = "x360/resolve_average.frag";
        outFormat = t.readFormat;
        bindings.push_back(sampled(0, e.attachment));
        const bool bytes = t.attachmentFormat == rhi::Format::RGBA8 || t.attachmentFormat == rhi::Format::R8;
        defines = {{"PARITY_RESOLVE_UNORM8", bytes ? "1" : "0"}};
        addHostSampleDefines(defines);
      } else if (partial) {
        // k_8_8_8_8, k_32_FLOAT and 7e3 without conversion, a rectangle of them: a copy pass.
        file = "x360/resolve_copy.frag";
        outFormat = t.readFormat;
        bindings.push_back(sampled(0, e.attachment));
      } else {
        // k_8_8_8_8 and k_32_FLOAT resolve without conversion: a copy.
        dev_.copyTexture(e.attachment, e.read);
        return true;
      }
      break;
  }
  rhi::PipelineHandle p = pipeline(file, outFormat, defines);
  if (!p) return false;
  // An array resolves layer by layer: each pass reads one layer's view and writes that layer.
  const uint32_t layers = std::max(1u, uint32_t(e.attachmentLayers.size()));
  for (uint32_t layer = 0; layer < layers; ++layer) {
    std::vector<rhi::ResourceBinding> layerBindings = bindings;
    if (!e.attachmentLayers.empty())
      for (rhi::ResourceBinding& b : layerBindings)
        if (b.texture == e.attachment) b.texture = e.attachmentLayers[layer];
    rhi::PassDesc pass;
    pass.colors[0].texture = out;
    pass.colors[0].layer = layer;
    pass.colors[0].load = partial ? rhi::LoadOp::Load : rhi::LoadOp::Clear;  // a rectangle keeps the rest
    pass.label = "resolve " + name;
    dev_.beginPass(pass);
    dev_.setPipeline(p);
    if (sourceSamples >= 2) {
      rhi::Viewport vp;
      vp.width = float(plan_.width);
      vp.height = float(plan_.height / 2);
      dev_.setViewport(vp);
    } else if (partial) {  // the shaders read gl_FragCoord: the viewport is the rectangle
      rhi::Viewport vp;
      vp.x = float(rect.x);
      vp.y = float(rect.y);
      vp.width = float(rect.width);
      vp.height = float(rect.height);
      dev_.setViewport(vp);
    }
    dev_.setBindings(layerBindings);
    if (counting(defines)) dev_.pushConstants(&countSlot, sizeof(countSlot));
    dev_.draw(3);
    dev_.endPass();
  }
  return true;
}

bool GpuTargets::resolveEachSample(Entry& e, const std::string& name) {
  const PhysicalTarget& t = *e.target;
  std::string file;
  if (isFloat7e3(plan_, t)) {
    file = "x360/resolve_average.frag";  // one sample selected: a bit copy of its 7e3 values
  } else if (t.logical.format == LogicalFormat::Rgba16Hdr) {
    file = "x360/resolve_k16x4.frag";  // the raw int16 of the sample, as a one-sample resolve keeps
  } else if (t.logical.format == LogicalFormat::Rgba8Unorm || t.logical.format == LogicalFormat::Rgba8Bits ||
             t.logical.format == LogicalFormat::R8Unorm || t.logical.format == LogicalFormat::R32Float) {
    file = "x360/resolve_average.frag";  // with one sample selected: a bit copy
  } else {
    error_ = "x360: no per-sample resolve of a " + std::string(logicalFormatName(t.logical.format)) + " surface (" +
             name + ")";
    return false;
  }
  rhi::ResourceBinding source;
  source.binding = 0;
  source.kind = rhi::BindingKind::SampledTexture;
  source.texture = e.attachment;
  for (uint32_t s = 0; s < t.samples; ++s) {
    const std::string host = std::to_string(x360::hostSampleIndex(x360::MsaaSamples::k4X, s));
    rhi::PipelineHandle p = pipeline(file, t.readFormat, {{"PARITY_RESOLVE_SAMPLE", host}});
    if (!p) return false;
    rhi::PassDesc pass;
    pass.colors[0].texture = e.read;
    pass.colors[0].layer = s;
    pass.colors[0].load = rhi::LoadOp::DontCare;
    pass.label = "resolve " + name + " sample " + std::to_string(s);
    dev_.beginPass(pass);
    dev_.setPipeline(p);
    dev_.setBindings({&source, 1});
    dev_.draw(3);
    dev_.endPass();
  }
  return true;
}

std::vector<uint8_t> GpuTargets::consoleBytes(const std::string& name, bool afterResolve) {
  auto it = entries_.find(name);
  if (it == entries_.end()) return {};
  Entry& e = it->second;
  const PhysicalTarget& t = *e.target;
  const size_t n = size_t(plan_.width) * plan_.height;
  if (t.samples > 1 && !afterResolve) return {};  // MSAA cannot be read back (edramBytes() can)
  if (t.logical.format == LogicalFormat::Depth24Stencil8 && !afterResolve) {
    // The depth-stencil surface itself: (D24 << 8) | stencil, in the console's byte order.
    rhi::ReadbackRegion rd;
    rd.aspect = rhi::TextureAspect::Depth;
    std::vector<uint8_t> depth = dev_.readTexture(e.attachment, rd);
    std::vector<uint8_t> stencil;
    if (rhi::hasStencil(t.attachmentFormat)) {
      rhi::ReadbackRegion rs;
      rs.aspect = rhi::TextureAspect::Stencil;
      stencil = dev_.readTexture(e.attachment, rs);
    }
    std::vector<uint8_t> out(n * 4);
    for (size_t i = 0; i < n && i * 4 + 4 <= depth.size(); ++i) {
      float d;
      std::memcpy(&d, depth.data() + i * 4, 4);
      uint32_t word;
      if (t.attachmentFormat == rhi::Format::D32F) {
        std::memcpy(&word, &d, 4);
      } else {
        uint32_t d24 = uint32_t(std::nearbyint(double(d) * 16777215.0));
        word = d24 << 8 | (i < stencil.size() ? stencil[i] : 0);
      }
      const bool bigEndian = plan_.platform == PlatformId::Ps3;
      for (int b = 0; b < 4; ++b) out[i * 4 + b] = uint8_t(word >> (bigEndian ? 24 - 8 * b : 8 * b));
    }
    return out;
  }
  if (isFloat7e3(plan_, t)) {
    // EDRAM and resolved alike: RGBA32F 7e3 values -> one little-endian dword per pixel.
    std::vector<float> f = asFloatTexels(dev_.readTexture(afterResolve ? e.read : e.attachment));
    std::vector<uint8_t> out;
    for (size_t i = 0; i + 4 <= f.size(); i += 4) {
      const uint32_t word = x360::packFloat7e3x3Unorm2({f[i], f[i + 1], f[i + 2], f[i + 3]});
      for (int b = 0; b < 4; ++b) out.push_back(uint8_t(word >> (8 * b)));
    }
    return out;
  }
  if (plan_.platform == PlatformId::X360 && t.logical.format == LogicalFormat::Rgba16Hdr) {
    // EDRAM: RGBA32F s * 2^-15, clamped to the encode's range as the blender's re-encode does;
    // resolved: RGBA32F float(s). Either way 4 int16 per pixel, little-endian, R first.
    std::vector<float> f = asFloatTexels(dev_.readTexture(afterResolve ? e.read : e.attachment));
    const double scale = afterResolve ? 1.0 : 32768.0;
    std::vector<uint8_t> out(f.size() * 2);
    for (size_t i = 0; i < f.size(); ++i) {
      double s = std::nearbyint(double(f[i]) * scale);
      uint16_t word = uint16_t(int16_t(std::clamp(s, -32767.0, 32767.0)));
      out[i * 2] = uint8_t(word & 255);
      out[i * 2 + 1] = uint8_t(word >> 8);
    }
    return out;
  }
  rhi::TextureHandle src = afterResolve ? (e.readRawView ? e.readRawView : e.read) : (e.rawView ? e.rawView : e.attachment);
  std::vector<uint8_t> bytes = dev_.readTexture(src);
  const bool ps3Argb8 = t.logical.format == LogicalFormat::Rg16Unorm ||
                        (t.logical.format == LogicalFormat::Depth24Stencil8 && afterResolve);
  if (plan_.platform == PlatformId::Ps3 && ps3Argb8) {
    // The host texel order of emulated A8R8G8B8 surfaces (ps3/remap.h) back to memory order.
    for (size_t i = 0; i + 4 <= bytes.size(); i += 4) {
      const ps3::Argb8Bytes console = ps3::argb8OfHostTexel({bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]});
      std::copy(console.begin(), console.end(), bytes.begin() + i);
    }
  } else if (plan_.platform == PlatformId::Ps3 && t.attachmentFormat == rhi::Format::RGBA8) {
    // A colour surface holds the shader's (r, g, b, a) as A8R8G8B8: memory [A, R, G, B].
    for (size_t i = 0; i + 4 <= bytes.size(); i += 4) std::rotate(bytes.begin() + i, bytes.begin() + i + 3, bytes.begin() + i + 4);
  }
  return bytes;
}

std::vector<uint8_t> GpuTargets::edramBytes(const std::string& name) {
  auto it = entries_.find(name);
  if (it == entries_.end() || plan_.platform != PlatformId::X360) return {};
  Entry& e = it->second;
  const PhysicalTarget& t = *e.target;
  const bool depth = t.logical.format == LogicalFormat::Depth24Stencil8;
  // A surface of more than 2048 tiles overlaps itself (E_EDRAM_SURFACE_TOO_LARGE): no image.
  if (t.edramTiles == 0 || t.edramTiles > x360::kEdramTileCount) return {};
  const bool float7e3 = isFloat7e3(plan_, t);
  const bool is64bpp = t.logical.format == LogicalFormat::Rgba16Hdr && !float7e3;
  const x360::MsaaSamples msaa = t.samples == 4 ? x360::MsaaSamples::k4X : x360::MsaaSamples::k1X;
  const char* source = t.logical.format == LogicalFormat::Rg16Unorm   ? "0"
                       : float7e3                                     ? "5"
                       : t.logical.format == LogicalFormat::Rgba16Hdr ? "1"
                       : t.logical.format == LogicalFormat::R32Float  ? "4"
                       : depth                                        ? "3"
                                                                      : "2";
  std::vector<std::pair<std::string, std::string>> defines = {
      {"PARITY_EDRAM_SOURCE", source},
      {"PARITY_EDRAM_MSAA4", t.samples == 4 ? "1" : "0"},
      {"PARITY_EDRAM_WIDTH", std::to_string(plan_.width) + "u"},
      {"PARITY_EDRAM_HEIGHT", std::to_string(plan_.height) + "u"},
      {"PARITY_EDRAM_PITCH_TILES", std::to_string(x360::surfacePitchTiles(plan_.width, msaa, is64bpp)) + "u"},
      {"PARITY_EDRAM_IS64", is64bpp ? "1u" : "0u"},
      {"PARITY_EDRAM_SAMPLE_ORDER", std::to_string(int(plan_.params.msaa4xSampleOrder))},
      {"PARITY_EDRAM_64BPP_LAYOUT", std::to_string(int(plan_.params.edram64bppTileLayout))}};
  if (t.samples == 4) addHostSampleDefines(defines);
  rhi::PipelineHandle p = pipeline("x360/edram_store.frag", rhi::Format::R32_UINT, defines);
  if (!p) return {};
  rhi::TextureDesc d;
  d.format = rhi::Format::R32_UINT;
  d.width = x360::kEdramTileSizeDwords;
  d.height = t.edramTiles;
  d.label = name + " (EDRAM image)";
  rhi::TextureHandle image = dev_.createTexture(d);
  rhi::PassDesc pass;
  pass.colors[0].texture = image;
  pass.label = "EDRAM image of " + name;
  dev_.beginPass(pass);
  dev_.setPipeline(p);
  rhi::ResourceBinding b[2];
  b[0].binding = 0;
  b[0].kind = rhi::BindingKind::SampledTexture;
  b[0].texture = t.logical.format == LogicalFormat::Rg16Unorm ? e.rawView : e.attachment;
  b[1] = b[0];
  b[1].binding = 1;  // depth: the stencil aspect of the same surface
  dev_.setBindings({b, depth ? 2u : 1u});
  dev_.draw(3);
  dev_.endPass();
  std::vector<uint8_t> bytes = dev_.readTexture(image);  // R32_UINT: little-endian dwords, as EDRAM
  dev_.destroy(image);
  return bytes;
}

}  // namespace parity::platforms
