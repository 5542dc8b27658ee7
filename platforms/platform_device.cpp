#include "platforms/platform_device.h"

#include <algorithm>

#include "platforms/common/capabilities.h"
#include "platforms/platform_layer.h"
#include "platforms/shader_use.h"

namespace parity::platforms {

struct PlatformDevice::PipelineInfo {
  PipelineState state;
  std::map<uint32_t, rhi::ShaderResource> resources;  // by binding, every stage's
  std::vector<rhi::SeparatePair> pairs;
  std::set<uint32_t> preRasterBindings;  // bindings the stages before rasterisation use
};

namespace {

bool filters(const rhi::SamplerDesc& s) {
  return s.minFilter == rhi::Filter::Linear || s.magFilter == rhi::Filter::Linear || s.mipFilter == rhi::MipFilter::Linear;
}

bool isTexture(rhi::BindingKind k) {
  return k == rhi::BindingKind::SampledTexture || k == rhi::BindingKind::SeparateTexture ||
         k == rhi::BindingKind::StorageTexture;
}

// What a shader's code writes and reads, added to its pipeline's needs (capability_rules.cpp).
void addNeeds(const ShaderUse& use, PipelineState& s) {
  s.atomics = s.atomics || use.atomics;
  for (uint32_t b : use.writtenBindings)
    for (const rhi::ShaderResource& r : use.resources)
      if (r.binding == b) {
        if (r.kind == rhi::BindingKind::StorageBuffer)
          ++s.storageBuffersWritten;
        else
          ++s.storageImagesWritten;
      }
}

bool writesStencil(const rhi::DepthStencilState& d) {
  auto writes = [](const rhi::StencilFaceState& f) {
    return f.fail != rhi::StencilOp::Keep || f.depthFail != rhi::StencilOp::Keep || f.pass != rhi::StencilOp::Keep;
  };
  return d.stencilEnabled && d.stencilWriteMask != 0 && (writes(d.front) || writes(d.back));
}

}  // namespace

PlatformDevice::PlatformDevice(rhi::Device& host, PlatformId platform, const PlatformParams& params, bool countValues)
    : ForwardingDevice(host),
      platform_(platform),
      params_(params),
      offset_(hostPixelCenterOffset(platform, params)),
      countValues_(countValues),
      info_(host.info()),
      rules_(makePlatformRules(platform, params)),
      capabilityRules_(makeCapabilityRules(platform)) {
  info_.caps = publishedCapabilities(platform, host.info().caps);
}

PlatformDevice::~PlatformDevice() = default;

TexelCounters* PlatformDevice::counters() {
  if (!countValues_) return nullptr;
  if (!counters_) counters_ = std::make_unique<TexelCounters>(inner());
  return counters_.get();
}

DiagnosticList PlatformDevice::diagnostics() {
  DiagnosticList all = diagnostics_;
  if (counters_) counters_->collect(all);
  return all;
}

void PlatformDevice::report(const DiagnosticList& found) {
  for (const Diagnostic& d : found.all()) {
    bool seen = false;
    for (const Diagnostic& e : diagnostics_.all())
      seen = seen || (e.code == d.code && e.message == d.message && e.pass == d.pass && e.pipeline == d.pipeline);
    if (!seen) diagnostics_.report(d.code, d.targets, d.message, {d.pass, d.pipeline, d.count});
  }
}

template <class F>
void PlatformDevice::run(const std::string& pipeline, F&& rule) {
  DiagnosticList found;
  rule(found);
  DiagnosticSite site;
  site.pass = inPass_ ? pass_.label : std::string();
  site.pipeline = pipeline;
  found.locate(0, site);
  report(found);
}

// --- platform targets -------------------------------------------------------------------------

uint32_t PlatformDevice::registerSurface(uint32_t plan, const PhysicalTarget& target, uint32_t width, uint32_t height,
                                         const SurfaceTextures& textures, std::function<void()> afterPass) {
  const uint32_t id = ++nextSurface_;
  SurfaceRecord& r = surfaces_[id];
  r.surface.id = id;
  r.surface.plan = plan;
  r.surface.target = target;
  r.surface.width = width;
  r.surface.height = height;
  r.afterPass = std::move(afterPass);
  auto add = [&](rhi::TextureHandle t, SurfaceView view) {
    if (t && !platformTextures_.count(t.id)) platformTextures_[t.id] = {id, view};
  };
  for (rhi::TextureHandle t : textures.attachment) add(t, SurfaceView::Attachment);
  add(textures.bits, SurfaceView::Bits);
  add(textures.resolved, SurfaceView::Resolved);
  for (rhi::TextureHandle t : textures.resolvedViews) add(t, SurfaceView::Resolved);
  add(textures.readView, SurfaceView::ReadView);
  return id;
}

void PlatformDevice::forgetPlan(uint32_t plan) {
  for (auto it = surfaces_.begin(); it != surfaces_.end();) {
    if (it->second.surface.plan != plan) {
      ++it;
      continue;
    }
    const uint32_t id = it->first;
    std::erase_if(platformTextures_, [&](const auto& e) { return e.second.surface == id; });
    afterPass_.erase(id);
    it = surfaces_.erase(it);
  }
  rules_->forgetPlan(plan);
}

void PlatformDevice::resolved(uint32_t surface, const ResolveEvent& event) {
  auto it = surfaces_.find(surface);
  if (it == surfaces_.end()) return;
  ResolveEvent e = event;
  e.surface = &it->second.surface;
  DiagnosticList found;
  rules_->resolve(e, found);
  found.locate(0, {"resolve " + it->second.surface.name(), ""});
  report(found);
  it->second.surface.resolved = true;
  it->second.surface.writtenSinceResolve = false;
  hostStateChanged_ = true;
}

std::string PlatformDevice::lastPassOf(uint32_t surface) const {
  auto it = surfaces_.find(surface);
  return it == surfaces_.end() ? std::string() : it->second.lastPass;
}

TextureUse PlatformDevice::use(rhi::TextureHandle texture) const {
  TextureUse u;
  u.texture = texture;
  if (!texture) return u;
  const rhi::TextureDesc* desc = inner().describe(texture);
  if (desc) {
    u.format = desc->format;
    u.samples = desc->samples;
    u.width = desc->width;
    u.height = desc->height;
    u.label = desc->label;
  }
  auto root = viewRoots_.find(texture.id);
  u.root = root == viewRoots_.end() ? texture.id : root->second;
  u.renderedOutsidePlan = renderedOwn_.count(u.root) > 0;
  auto p = platformTextures_.find(texture.id);
  if (p != platformTextures_.end()) {
    const Surface& s = surfaces_.at(p->second.surface).surface;
    u.surface = &s;
    u.view = p->second.view;
    u.label = s.name();
  }
  return u;
}

// --- objects ----------------------------------------------------------------------------------

rhi::TextureHandle PlatformDevice::createTexture(const rhi::TextureDesc& d) {
  rhi::TextureHandle h = inner().createTexture(d);
  if (h) ownTextures_[h.id] = d.label;
  return h;
}

rhi::TextureHandle PlatformDevice::createTextureView(const rhi::TextureViewDesc& d) {
  rhi::TextureHandle h = inner().createTextureView(d);
  if (h) {
    ownTextures_[h.id] = d.label;
    auto root = viewRoots_.find(d.parent.id);
    viewRoots_[h.id] = root == viewRoots_.end() ? d.parent.id : root->second;
    // A view of a platform target reaches the same surface.
    auto p = platformTextures_.find(d.parent.id);
    if (p != platformTextures_.end()) platformTextures_[h.id] = p->second;
  }
  return h;
}

void PlatformDevice::destroy(rhi::TextureHandle h) {
  renderedOwn_.erase(h.id);
  ownTextures_.erase(h.id);
  viewRoots_.erase(h.id);
  platformTextures_.erase(h.id);  // a view made here of a platform target (GpuTargets destroys its own on the host)
  inner().destroy(h);
}

rhi::SamplerHandle PlatformDevice::createSampler(const rhi::SamplerDesc& d) {
  rhi::SamplerHandle h = inner().createSampler(d);
  if (h) samplers_[h.id] = d;
  return h;
}

void PlatformDevice::destroy(rhi::SamplerHandle h) {
  samplers_.erase(h.id);
  inner().destroy(h);
}

rhi::ShaderHandle PlatformDevice::createShader(const rhi::ShaderDesc& d) {
  rhi::ShaderHandle h = inner().createShader(d);
  if (!h) return h;
  shaders_[h.id] = shaderUse(d.spirv, d.stage);
  return h;
}

void PlatformDevice::destroy(rhi::ShaderHandle h) {
  shaders_.erase(h.id);
  inner().destroy(h);
}

rhi::PipelineHandle PlatformDevice::createPipeline(const rhi::PipelineDesc& d) {
  rhi::PipelineHandle h = inner().createPipeline(d);
  if (!h) return h;
  auto p = std::make_shared<PipelineInfo>();
  PipelineState& s = p->state;
  s.label = d.label;
  s.colorCount = d.colorTargetCount;
  for (uint32_t i = 0; i < rhi::kMaxColorTargets; ++i) s.colors[i] = i < d.colorTargetCount ? d.colorTargets[i] : rhi::ColorTargetState{};
  s.depthWrite = d.depthStencil.depthWrite;
  s.depthTest = d.depthStencilFormat != rhi::Format::Undefined && d.depthStencil.depthCompare != rhi::CompareOp::Always;
  s.stencilWrite = writesStencil(d.depthStencil);
  s.screenSpace = d.attributeCount == 0;
  s.geometryStage = bool(d.geometryShader);
  s.tessellationStages = d.tessControlShader || d.tessEvaluationShader;
  for (rhi::ShaderHandle sh : {d.vertexShader, d.geometryShader, d.tessControlShader, d.tessEvaluationShader, d.fragmentShader}) {
    auto it = shaders_.find(sh.id);
    if (!sh || it == shaders_.end()) continue;
    const ShaderUse& use = it->second;
    const bool fragment = use.stage == rhi::ShaderStage::Fragment;
    for (const rhi::ShaderResource& r : use.resources) {
      p->resources.emplace(r.binding, r);
      if (!fragment) p->preRasterBindings.insert(r.binding);
      if (isTexture(r.kind)) (fragment ? s.fragmentTextures : s.vertexTextures) += r.arraySize;
    }
    for (const rhi::SeparatePair& pair : use.pairs)
      if (std::find(p->pairs.begin(), p->pairs.end(), pair) == p->pairs.end()) p->pairs.push_back(pair);
    if (fragment) {
      s.samplesInterpolatedCoordinates = use.filteredSampling && use.userInputs;
      s.interpolators = use.inputLocations;
    }
    addNeeds(use, s);
    s.graphicsStorageWrites = s.graphicsStorageWrites || !use.writtenBindings.empty();
  }
  pipelines_[h.id] = std::move(p);
  return h;
}

void PlatformDevice::destroy(rhi::PipelineHandle h) {
  pipelines_.erase(h.id);
  inner().destroy(h);
}

rhi::ComputePipelineHandle PlatformDevice::createComputePipeline(const rhi::ComputePipelineDesc& d) {
  rhi::ComputePipelineHandle h = inner().createComputePipeline(d);
  if (!h) return h;
  auto p = std::make_shared<PipelineInfo>();
  p->state.label = d.label;
  p->state.compute = true;
  auto it = shaders_.find(d.computeShader.id);
  if (it != shaders_.end()) {
    for (const rhi::ShaderResource& r : it->second.resources) p->resources.emplace(r.binding, r);
    p->pairs = it->second.pairs;
    p->state.workgroupSize = it->second.localSize;
    p->state.sharedBytes = it->second.sharedBytes;
    addNeeds(it->second, p->state);
  }
  computePipelines_[h.id] = std::move(p);
  return h;
}

void PlatformDevice::destroy(rhi::ComputePipelineHandle h) {
  computePipelines_.erase(h.id);
  inner().destroy(h);
}

// --- commands ---------------------------------------------------------------------------------

void PlatformDevice::copyTexture(rhi::TextureHandle src, rhi::TextureHandle dst, const rhi::ReadbackRegion& s,
                                 const rhi::ReadbackRegion& d) {
  const TextureUse from = use(src), to = use(dst);
  run("", [&](DiagnosticList& out) { rules_->copy(from, to, out); });
  if (to.surface) {
    SurfaceRecord& r = surfaces_.at(to.surface->id);
    r.surface.written = r.surface.writtenSinceResolve = true;
  }
  inner().copyTexture(src, dst, s, d);
}

void PlatformDevice::beginPass(const rhi::PassDesc& d) {
  pass_ = PassState{};
  pass_.label = d.label;
  auto noteUnplanned = [&](rhi::TextureHandle t) {
    auto own = ownTextures_.find(t.id);
    if (!t || own == ownTextures_.end() || platformTextures_.count(t.id)) return;
    unplanned_.insert(d.label + ": " + own->second);
    auto root = viewRoots_.find(t.id);
    renderedOwn_.insert(root == viewRoots_.end() ? t.id : root->second);
  };
  for (uint32_t i = 0; i < rhi::kMaxColorTargets; ++i) {
    pass_.colors[i] = {use(d.colors[i].texture), d.colors[i].load, bool(d.colors[i].resolveTarget)};
    noteUnplanned(d.colors[i].texture);
    noteUnplanned(d.colors[i].resolveTarget);
  }
  pass_.depth = {use(d.depthStencil.texture), d.depthStencil.load, false};
  noteUnplanned(d.depthStencil.texture);
  afterPass_.clear();
  inPass_ = true;
  run("", [&](DiagnosticList& out) {
    rules_->beginPass(pass_, out);
    capabilityRules_->beginPass(pass_, out);
  });
  // A cleared attachment is written.
  auto cleared = [&](const PassAttachment& a) {
    if (!a.use.surface || a.load != rhi::LoadOp::Clear) return;
    Surface& s = surfaces_.at(a.use.surface->id).surface;
    s.written = s.writtenSinceResolve = true;
  };
  for (const PassAttachment& a : pass_.colors) cleared(a);
  cleared(pass_.depth);
  inner().beginPass(d);
}

void PlatformDevice::endPass() {
  inner().endPass();
  run("", [&](DiagnosticList& out) { rules_->endPass(pass_, out); });
  inPass_ = false;
  std::map<uint32_t, std::function<void()>> after;
  after.swap(afterPass_);
  for (const auto& [id, f] : after) f();  // outside the technique's pass
  hostStateChanged_ = hostStateChanged_ || !after.empty();
}

void PlatformDevice::setPipeline(rhi::PipelineHandle h) {
  pipeline_ = h.id;
  inner().setPipeline(h);  // resets the viewport to the whole pass...
  viewportX_ = viewportY_ = 0;
  if (offset_ != 0) setViewport({});  // ...which moves with the pixel centres too
}

void PlatformDevice::setViewport(const rhi::Viewport& vp) {
  viewportX_ = vp.x;
  viewportY_ = vp.y;
  rhi::Viewport moved = vp;  // width and height 0 keep meaning "the whole attachment"
  moved.x += offset_;
  moved.y += offset_;
  inner().setViewport(moved);
}

void PlatformDevice::setComputePipeline(rhi::ComputePipelineHandle h) {
  computePipeline_ = h.id;
  inner().setComputePipeline(h);
}

void PlatformDevice::setBindings(std::span<const rhi::ResourceBinding> bindings) {
  for (const rhi::ResourceBinding& b : bindings) bindings_[{b.binding, b.arrayElement}] = b;
  inner().setBindings(bindings);
}

void PlatformDevice::pushConstants(const void* data, uint32_t size) {
  pushed_.assign(static_cast<const uint8_t*>(data), static_cast<const uint8_t*>(data) + size);
  inner().pushConstants(data, size);
}

void PlatformDevice::restoreHostState() {
  if (!hostStateChanged_) return;
  hostStateChanged_ = false;
  std::vector<rhi::ResourceBinding> live;  // what is still alive of the technique's bindings
  for (const auto& [key, b] : bindings_) {
    const bool alive = b.buffer ? inner().describe(b.buffer) != nullptr
                                : b.texture ? inner().describe(b.texture) != nullptr : samplers_.count(b.sampler.id) > 0;
    const bool samplerAlive = !b.sampler || samplers_.count(b.sampler.id) > 0;
    if (alive && samplerAlive) live.push_back(b);
  }
  if (!live.empty()) inner().setBindings(live);
  if (!pushed_.empty()) inner().pushConstants(pushed_.data(), uint32_t(pushed_.size()));
}

bool PlatformDevice::drawState(bool compute, DrawState* out) const {
  const auto& table = compute ? computePipelines_ : pipelines_;
  auto p = table.find(compute ? computePipeline_ : pipeline_);
  if (p == table.end()) return false;
  const PipelineInfo& info = *p->second;
  out->pass = compute ? nullptr : &pass_;
  out->pipeline = &info.state;
  out->viewportX = viewportX_ + offset_;
  out->viewportY = viewportY_ + offset_;
  out->pixelCenterOffset = offset_;
  auto bound = [&](uint32_t binding, uint32_t element) -> const rhi::ResourceBinding* {
    auto b = bindings_.find({binding, element});
    return b == bindings_.end() ? nullptr : &b->second;
  };
  auto filteredBy = [&](rhi::SamplerHandle s) {
    auto it = samplers_.find(s.id);
    return s && it != samplers_.end() && filters(it->second);  // null: nearest
  };
  for (const auto& [binding, r] : info.resources) {
    const bool texture = r.kind == rhi::BindingKind::SampledTexture || r.kind == rhi::BindingKind::SeparateTexture ||
                         r.kind == rhi::BindingKind::StorageTexture;
    if (!texture) continue;
    for (uint32_t e = 0; e < r.arraySize; ++e) {
      const rhi::ResourceBinding* b = bound(binding, e);
      if (!b || !b->texture) continue;
      SampledTexture s;
      s.binding = binding;
      s.use = use(b->texture);
      s.storage = r.kind == rhi::BindingKind::StorageTexture;
      s.vertexStage = info.preRasterBindings.count(binding) > 0;
      s.integer = r.integer;
      if (r.kind == rhi::BindingKind::SampledTexture) s.filtered = filteredBy(b->sampler);
      if (r.kind == rhi::BindingKind::SeparateTexture)
        for (const rhi::SeparatePair& pair : info.pairs) {
          if (pair.textureBinding != binding || pair.samplerBinding == rhi::kNoSamplerBinding) continue;
          for (uint32_t se = 0; se < rhi::kMaxArrayElements; ++se)
            if (const rhi::ResourceBinding* sb = bound(pair.samplerBinding, se)) s.filtered |= filteredBy(sb->sampler);
        }
      out->sampled.push_back(std::move(s));
    }
  }
  return true;
}

void PlatformDevice::checkDraw(uint32_t vertices, uint32_t instances) {
  DrawState state;
  if (!drawState(false, &state)) return;
  state.vertices = vertices;
  state.instances = instances;
  run(state.pipeline->label, [&](DiagnosticList& out) {
    rules_->draw(state, out);
    capabilityRules_->draw(state, out);
  });
  // What the draw writes: the colour targets its write masks reach, the depth it writes.
  auto written = [&](const PassAttachment& a) {
    if (!a.use.surface) return;
    SurfaceRecord& r = surfaces_.at(a.use.surface->id);
    r.surface.written = r.surface.writtenSinceResolve = true;
    r.lastPass = pass_.label;
    if (r.afterPass) afterPass_[a.use.surface->id] = r.afterPass;  // once per pass
  };
  for (uint32_t i = 0; i < rhi::kMaxColorTargets; ++i)
    if (state.pipeline->colors[i].writeMask != 0) written(pass_.colors[i]);
  // Depth written (a stencil-only write leaves the depth a copy or resolve holds as it is).
  if (state.pipeline->depthWrite) written(pass_.depth);
}

void PlatformDevice::checkDispatch() {
  DrawState state;
  if (!drawState(true, &state)) return;
  run(state.pipeline->label, [&](DiagnosticList& out) {
    rules_->draw(state, out);
    capabilityRules_->draw(state, out);
  });
}

void PlatformDevice::draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) {
  restoreHostState();
  checkDraw(vertexCount, instanceCount);
  inner().draw(vertexCount, instanceCount, firstVertex, firstInstance);
}

void PlatformDevice::drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                                 uint32_t firstInstance) {
  restoreHostState();
  checkDraw(indexCount, instanceCount);
  inner().drawIndexed(indexCount, instanceCount, firstIndex, vertexOffset, firstInstance);
}

void PlatformDevice::dispatch(uint32_t x, uint32_t y, uint32_t z) {
  restoreHostState();
  checkDispatch();
  inner().dispatch(x, y, z);
}

PlatformDevice* asPlatformDevice(rhi::Device& device) { return dynamic_cast<PlatformDevice*>(&device); }

rhi::Device& hostDevice(rhi::Device& device) {
  if (PlatformDevice* p = asPlatformDevice(device)) return p->inner();
  return device;
}

}  // namespace parity::platforms
