#include "mini_port.h"

#include <algorithm>
#include <mutex>

#include "rhi/shader_compiler.h"
#include "techniques/common/pass_helpers.h"

namespace parity::test {

using platforms::LogicalFormat;
using platforms::LogicalTarget;
using platforms::TargetRole;
using techniques::TechniqueError;

namespace {

const char* const kAlbedo = "albedo";
const char* const kNormal = "normal";
const char* const kLight = "light";
const char* const kThird = "third";      // MixedMrt: HDR; SharedBlend: 8-bit; MrtMsaaMismatch: 4x
const char* const kDsf4x = "dsf.4x";     // PackedMsaaResolve
const char* const kScratch = "scratch";  // ScratchOverDepth
const char* const kBig = "big";          // SurfaceTooLarge

const char* const kVs = R"(#version 450
layout(location = 0) out vec2 vUv;
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  vUv = p;
  gl_Position = vec4(p * 2.0 - 1.0, 0.5, 1.0);
})";

const char* const kQuadVs = R"(#version 450
layout(location = 0) in vec2 aPosition;
layout(location = 1) in vec2 aUv;
layout(location = 0) out vec2 vUv;
void main() {
  vUv = aUv;
  gl_Position = vec4(aPosition, 0.5, 1.0);
})";

const char* const kGBufferFs = R"(#version 450
#include "platform.glsl"
layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 oAlbedo;
#ifdef NORMAL_BLENDED
layout(location = 1) out vec4 oNormal;
#else
layout(location = 1) out PARITY_RG16_BITS_TYPE oNormal;
#endif
#if defined(THIRD_HDR) || defined(THIRD_RGBA8)
layout(location = 2) out vec4 oThird;
#endif
void main() {
  oAlbedo = vec4(fract(gl_FragCoord.xy / 16.0), 0.25, 0.75);
#ifdef NORMAL_OUT_OF_RANGE
  vec2 n = vec2(-0.5, 1.5);
#else
  vec2 n = clamp(vUv.yx, 0.0, 1.0);
#endif
#ifdef NORMAL_BLENDED
  oNormal = parityWriteRg16(n);
#else
  oNormal = parityWriteRg16Bits(n);
#endif
#if defined(THIRD_HDR)
  oThird = parityWriteRgba16Hdr(vec4(2.0));
#elif defined(THIRD_RGBA8)
  oThird = vec4(0.5);
#endif
})";

const char* const kLightFs = R"(#version 450
#include "platform.glsl"
layout(location = 0) in vec2 vUv;
layout(binding = 4) uniform sampler2D uAlbedo;
layout(binding = 5) uniform PARITY_RG16_SAMPLER uNormal;
layout(binding = 6) uniform PARITY_DEPTH_SAMPLER uDepth;
#if defined(DEPTH_SURFACE) || defined(OWN_TEXTURE)
layout(binding = 7) uniform sampler2D uDepthSurface;
#elif defined(DEPTH_MSAA)
layout(binding = 7) uniform sampler2DMS uDepthSurface;
#endif
layout(location = 0) out vec4 oLight;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float d = parityReadDepth(texelFetch(uDepth, p, 0));
#if defined(DEPTH_SURFACE) || defined(DEPTH_MSAA) || defined(OWN_TEXTURE)
  d = 0.5 * (d + texelFetch(uDepthSurface, p, 0).r);
#endif
#ifdef NO_GBUFFER_READ
  vec3 albedo = vec3(0.5);
  vec2 n = vec2(0.5);
#else
  vec3 albedo = texture(uAlbedo, vUv).rgb;
  vec2 n = parityReadRg16(texture(uNormal, vUv));
#endif
  vec4 light = vec4(albedo * (0.5 + n.x + n.y) * (1.0 - 0.5 * d), 1.0) * HDR_SCALE;
#ifdef HDR_NAN
  light.x = uintBitsToFloat(0x7FC00000u);
#endif
  oLight = parityWriteRgba16Hdr(light);
})";

const char* const kComposeFs = R"(#version 450
#include "platform.glsl"
layout(location = 0) in vec2 vUv;
layout(binding = 4) uniform sampler2D uLight;
layout(binding = 5) uniform sampler2D uAlbedo;
layout(location = 0) out vec4 oColor;
void main() {
  vec3 l = parityReadRgba16Hdr(texture(uLight, vUv)).rgb;
  oColor = vec4(l / (1.0 + l) + 0.1 * texture(uAlbedo, vUv).rgb, 1.0);
})";

const char* const kPlainFs = R"(#version 450
#include "platform.glsl"
layout(location = 0) out vec4 oColor;
void main() {
#ifdef PACKED
  oColor = parityWriteRg16(vec2(0.25, 0.75));
#else
  oColor = vec4(0.5);
#endif
})";

rhi::ResourceBinding sampledWith(uint32_t binding, rhi::TextureHandle texture, rhi::SamplerHandle sampler) {
  rhi::ResourceBinding b = techniques::sampled(binding, texture);
  b.sampler = sampler;
  return b;
}

}  // namespace

const std::vector<MistakeInfo>& allMistakes() {
  static const std::vector<MistakeInfo> list = {
      {Mistake::None, "clean", "the technique as a console port writes it"},
      {Mistake::PackedBlend, "packed-blend", "the two-16-bit target blended (DEST_COLOR x SRC)"},
      {Mistake::PackedFilter, "packed-filter", "the two-16-bit target's surface sampled through a bilinear sampler"},
      {Mistake::PackedWriteMask, "packed-writemask", "the two-16-bit target written with mask R only"},
      {Mistake::HdrAbove32, "hdr-above-32", "light values up to 64 written to the HDR target"},
      {Mistake::HdrNaN, "hdr-nan", "a NaN written to the HDR target"},
      {Mistake::HdrMultiplyBlend, "hdr-multiply-blend", "the HDR target blended by DEST_COLOR"},
      {Mistake::DepthFeedback, "depth-feedback", "depth read while the pass writes it"},
      {Mistake::DepthFiltered, "depth-filtered", "depth read through a bilinear sampler"},
      {Mistake::DepthSurfaceSampled, "depth-surface-sampled", "the depth surface sampled, not its resolve or copy"},
      {Mistake::DepthSampledWhileBound, "depth-sampled-while-bound", "the depth surface sampled by a pass it is attached to"},
      {Mistake::OwnFloatDepthSampled, "own-float-depth-sampled", "a D32F depth texture of the technique's own sampled"},
      {Mistake::MsaaDepthSampled, "msaa-depth-sampled", "a 4x depth texture of the technique's own sampled"},
      {Mistake::SampleBeforeResolve, "sample-before-resolve", "the albedo sampled, its resolve left out"},
      {Mistake::SampleEdramSurface, "sample-edram-surface", "the albedo's surface sampled, not its resolved texture"},
      {Mistake::StaleResolve, "stale-resolve", "the albedo drawn into after its resolve, then sampled"},
      {Mistake::MixedMrt, "mixed-mrt", "an HDR (64 bpp) target bound beside the 32-bpp G-buffer"},
      {Mistake::SharedBlend, "shared-blend", "two targets of a pass blended with different functions"},
      {Mistake::OwnRg16Target, "own-rg16-target", "a RG16_UNORM texture of the technique's own rendered into"},
      {Mistake::PackedMsaaResolve, "packed-msaa-resolve", "a 4x two-16-bit target resolved by averaging"},
      {Mistake::UnalignedResolve, "unaligned-resolve", "the albedo resolved as the rectangle (4, 4) 64x32"},
      {Mistake::D3D10Centres, "d3d10-centres", "the compose pass samples at D3D10 centres (no -0.5)"},
      {Mistake::QuadD3D10Centres, "quad-d3d10-centres", "the same, its quad from a vertex buffer"},
      {Mistake::MixedCentres, "mixed-centres", "the compose pass draws once with the -0.5 and once without"},
      {Mistake::LBufferBeforeResolve, "lbuffer-before-resolve", "the L-buffer, over the G-buffer tiles, drawn before their resolve"},
      {Mistake::LBufferOverDepth, "lbuffer-over-depth", "the L-buffer placed over the depth its pass tests against"},
      {Mistake::GBufferSameBase, "gbuffer-same-base", "two G-buffer targets declared live apart, bound together"},
      {Mistake::ScratchOverDepth, "scratch-over-depth", "a target declared live apart, over the depth's tiles, drawn before the depth's resolve"},
      {Mistake::SurfaceTooLarge, "surface-too-large", "a 4x 64-bpp target at 960x544"},
      {Mistake::MrtMsaaMismatch, "mrt-msaa-mismatch", "a 4x target bound beside 1x targets"},
      {Mistake::NormalOutOfRange, "normal-out-of-range", "values -0.5 and 1.5 written to the two-16-bit target"},
      {Mistake::OwnTargetSampled, "own-target-sampled", "an RGBA8 texture of the technique's own rendered into, then sampled"},
  };
  return list;
}

std::string MiniPort::name() const {
  for (const MistakeInfo& m : allMistakes())
    if (m.mistake == mistake_) return mistake_ == Mistake::None ? "mini-port" : "mini-port:" + m.name;
  return "mini-port";
}

std::vector<techniques::PassInfo> MiniPort::passes() const {
  return {{"gbuffer", "albedo, the two-16-bit target and depth", {kAlbedo, kNormal, "depth"}},
          {"light", "the lit G-buffer added into the HDR light buffer", {kLight}},
          {"compose", "the light buffer tone-mapped", {"color"}}};
}

std::vector<LogicalTarget> MiniPort::logicalTargets(const techniques::RenderSettings& settings) const {
  LogicalTarget albedo{kAlbedo, LogicalFormat::Rgba8Unorm, true, TargetRole::GBuffer, "gbuffer"};
  LogicalTarget normal{kNormal, LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "gbuffer"};
  LogicalTarget depth = techniques::sceneDepthTarget("gbuffer", true);
  depth.role = TargetRole::GBuffer;  // the G-buffer's depth (X4: no G-buffer surface may overlap it)
  LogicalTarget light{kLight, LogicalFormat::Rgba16Hdr, true, TargetRole::Plain, "light"};
  std::vector<LogicalTarget> t;
  switch (mistake_) {
    case Mistake::LBufferBeforeResolve:
      light.role = TargetRole::LBuffer;
      light.livePasses = {"light"};  // may take the G-buffer colour tiles, resolved before the light pass
      break;
    case Mistake::LBufferOverDepth:
      light.role = TargetRole::LBuffer;
      light.livePasses = {"light"};
      depth.livePasses = {"gbuffer"};  // but the light pass tests against it
      t.push_back(depth);              // placed first: the L-buffer takes its tiles
      break;
    case Mistake::GBufferSameBase:
      albedo.livePasses = {"gbuffer"};
      normal.livePasses = {"gbuffer normals"};  // but bound with the albedo
      break;
    default: break;
  }
  if (mistake_ != Mistake::LBufferOverDepth) t.push_back(depth);
  t.push_back(albedo);
  t.push_back(normal);
  t.push_back(light);
  t.push_back(techniques::outputColorTarget(settings, "compose"));
  switch (mistake_) {
    case Mistake::MixedMrt: t.push_back({kThird, LogicalFormat::Rgba16Hdr, false, TargetRole::GBuffer, "gbuffer"}); break;
    case Mistake::SharedBlend: t.push_back({kThird, LogicalFormat::Rgba8Unorm, false, TargetRole::Plain, "gbuffer"}); break;
    case Mistake::MrtMsaaMismatch:
      t.push_back({kThird, LogicalFormat::Rgba8Unorm, false, TargetRole::Plain, "gbuffer", 4});
      break;
    case Mistake::PackedMsaaResolve: t.push_back({kDsf4x, LogicalFormat::Rg16Unorm, true, TargetRole::Plain, "dsf", 4}); break;
    case Mistake::ScratchOverDepth: {
      LogicalTarget scratch{kScratch, LogicalFormat::Rgba8Unorm, false, TargetRole::Plain, "scratch"};
      scratch.livePasses = {"scratch"};  // its tiles may be any not live in "scratch": the depth's
      t.insert(t.begin() + 2, scratch);
      break;
    }
    case Mistake::SurfaceTooLarge: t.push_back({kBig, LogicalFormat::Rgba16Hdr, false, TargetRole::Plain, "big", 4}); break;
    default: break;
  }
  return t;
}

rhi::PipelineHandle MiniPort::pipeline(rhi::Device& device, const char* fragment,
                                       std::vector<std::pair<std::string, std::string>> defines, rhi::PipelineDesc state,
                                       const char* vertex) {
  rhi::ShaderCompileOptions options = targets_->shaderOptions(settings_);
  for (auto& d : defines) options.defines.push_back(std::move(d));
  auto shader = [&](const char* source, rhi::ShaderStage stage) {
    rhi::CompiledShader c = rhi::compileGlslSource(source, name() + (stage == rhi::ShaderStage::Vertex ? ".vert" : ".frag"),
                                                   stage, options);
    if (!c.ok()) throw TechniqueError(c.error);
    rhi::ShaderDesc d;
    d.stage = stage;
    d.spirv = c.spirv;
    d.label = name();
    rhi::ShaderHandle h = device.createShader(d);
    shaders_.push_back(h);
    return h;
  };
  state.vertexShader = shader(vertex ? vertex : kVs, rhi::ShaderStage::Vertex);
  state.fragmentShader = shader(fragment, rhi::ShaderStage::Fragment);
  rhi::PipelineHandle h = device.createPipeline(state);
  if (!h) throw TechniqueError(name() + ": the device rejected pipeline " + state.label);
  pipelines_.push_back(h);
  return h;
}

namespace {
rhi::PipelineDesc colorState(std::initializer_list<rhi::Format> colors, const std::string& label, uint32_t samples = 1) {
  rhi::PipelineDesc p;
  for (rhi::Format f : colors) p.colorTargets[p.colorTargetCount++].format = f;
  p.samples = samples;
  p.label = label;
  return p;
}
}  // namespace

void MiniPort::prepare(rhi::Device& device, const techniques::RenderSettings& settings) {
  settings_ = settings;
  targets_ = std::make_unique<techniques::PlannedTargets>(device, settings, logicalTargets(settings), name());
  const platforms::TargetPlan& plan = targets_->plan();
  auto fmt = [&](const char* t) { return targets_->format(t); };
  const rhi::Format depth = fmt("depth");

  // G-buffer.
  {
    std::vector<std::pair<std::string, std::string>> d;
    const bool blended = mistake_ == Mistake::PackedBlend;
    if (blended) d.push_back({"NORMAL_BLENDED", "1"});
    if (mistake_ == Mistake::NormalOutOfRange) d.push_back({"NORMAL_OUT_OF_RANGE", "1"});
    if (mistake_ == Mistake::MixedMrt) d.push_back({"THIRD_HDR", "1"});
    if (mistake_ == Mistake::SharedBlend || mistake_ == Mistake::MrtMsaaMismatch) d.push_back({"THIRD_RGBA8", "1"});
    rhi::PipelineDesc p = colorState({fmt(kAlbedo), blended ? fmt(kNormal) : plan.find(kNormal)->writeFormat},
                                     name() + " g-buffer");
    if (plan.find(kThird)) p.colorTargets[p.colorTargetCount++].format = fmt(kThird);
    p.depthStencilFormat = depth;
    p.depthStencil.depthCompare = rhi::CompareOp::Less;
    p.depthStencil.depthWrite = true;
    if (blended) {
      p.colorTargets[1].blend.enabled = true;
      p.colorTargets[1].blend.srcColor = rhi::BlendFactor::DstColor;
      p.colorTargets[1].blend.dstColor = rhi::BlendFactor::Zero;
    }
    if (mistake_ == Mistake::PackedWriteMask) p.colorTargets[1].writeMask = rhi::ColorMask_R;
    if (mistake_ == Mistake::SharedBlend) {  // alpha blending the albedo, adding the third
      p.colorTargets[0].blend.enabled = true;
      p.colorTargets[0].blend.srcColor = rhi::BlendFactor::SrcAlpha;
      p.colorTargets[0].blend.dstColor = rhi::BlendFactor::OneMinusSrcAlpha;
      techniques::enableAdditiveBlending(p.colorTargets[2]);
    }
    gbuffer_ = pipeline(device, kGBufferFs, d, p);
  }
  // Light.
  {
    std::vector<std::pair<std::string, std::string>> d = {{"HDR_SCALE", mistake_ == Mistake::HdrAbove32 ? "64.0" : "4.0"}};
    if (mistake_ == Mistake::HdrNaN) d.push_back({"HDR_NAN", "1"});
    if (mistake_ == Mistake::DepthSurfaceSampled || mistake_ == Mistake::DepthSampledWhileBound ||
        mistake_ == Mistake::OwnFloatDepthSampled)
      d.push_back({"DEPTH_SURFACE", "1"});
    if (mistake_ == Mistake::MsaaDepthSampled) d.push_back({"DEPTH_MSAA", "1"});
    if (mistake_ == Mistake::OwnTargetSampled) d.push_back({"OWN_TEXTURE", "1"});
    if (mistake_ == Mistake::LBufferBeforeResolve) d.push_back({"NO_GBUFFER_READ", "1"});
    rhi::PipelineDesc p = colorState({fmt(kLight)}, name() + " light");
    techniques::enableAdditiveBlending(p.colorTargets[0]);
    if (mistake_ == Mistake::HdrMultiplyBlend) {
      p.colorTargets[0].blend.srcColor = rhi::BlendFactor::DstColor;
      p.colorTargets[0].blend.dstColor = rhi::BlendFactor::Zero;
    }
    if (depthBoundInLight()) {
      p.depthStencilFormat = depth;
      p.depthStencil.depthCompare = rhi::CompareOp::Always;
      p.depthStencil.depthWrite = mistake_ == Mistake::DepthFeedback;
    }
    light_ = pipeline(device, kLightFs, d, p);
  }
  rhi::PipelineDesc compose = colorState({fmt("color")}, name() + " compose");
  if (mistake_ == Mistake::QuadD3D10Centres) {  // a quad from a vertex buffer: (x, y, u, v) per corner
    compose.topology = rhi::PrimitiveTopology::TriangleStrip;
    compose.attributes[0] = {0, rhi::VertexFormat::Float2, 0, 0};
    compose.attributes[1] = {1, rhi::VertexFormat::Float2, 8, 0};
    compose.attributeCount = 2;
    compose.vertexBuffers[0].stride = 16;
    const float corners[] = {-1, -1, 0, 0, 1, -1, 1, 0, -1, 1, 0, 1, 1, 1, 1, 1};
    rhi::BufferDesc b;
    b.size = sizeof(corners);
    b.usage = rhi::BufferUsage_Vertex;
    b.initialData = corners;
    b.label = "quad";
    quad_ = device.createBuffer(b);
  }
  compose_ = pipeline(device, kComposeFs, {}, compose, mistake_ == Mistake::QuadD3D10Centres ? kQuadVs : kVs);
  const rhi::Format plain = mistake_ == Mistake::OwnRg16Target      ? rhi::Format::RG16_UNORM
                           : mistake_ == Mistake::OwnTargetSampled ? rhi::Format::RGBA8
                                                                   : fmt(kAlbedo);
  plain_ = pipeline(device, kPlainFs, {}, colorState({plain}, name() + " plain"));
  if (plan.find(kBig)) plainMsaa_ = pipeline(device, kPlainFs, {}, colorState({fmt(kBig)}, name() + " big", 4));
  if (plan.find(kDsf4x))
    packedMsaa_ = pipeline(device, kPlainFs, {{"PACKED", "1"}}, colorState({fmt(kDsf4x)}, name() + " dsf", 4));

  rhi::SamplerDesc s;
  nearest_ = device.createSampler(s);
  s.minFilter = s.magFilter = rhi::Filter::Linear;
  linear_ = device.createSampler(s);
  rhi::TextureDesc own;
  own.width = settings.width;
  own.height = settings.height;
  own.label = "own";
  if (mistake_ == Mistake::OwnFloatDepthSampled) own.format = rhi::Format::D32F;
  if (mistake_ == Mistake::MsaaDepthSampled) {
    own.format = rhi::Format::D24S8;
    own.samples = 4;
  }
  if (mistake_ == Mistake::OwnRg16Target) own.format = rhi::Format::RG16_UNORM;
  if (mistake_ == Mistake::OwnTargetSampled) own.format = rhi::Format::RGBA8;
  if (mistake_ == Mistake::OwnFloatDepthSampled || mistake_ == Mistake::MsaaDepthSampled ||
      mistake_ == Mistake::OwnRg16Target || mistake_ == Mistake::OwnTargetSampled)
    own_ = device.createTexture(own);
}

bool MiniPort::depthBoundInLight() const {
  return mistake_ == Mistake::DepthFeedback || mistake_ == Mistake::DepthSampledWhileBound ||
         mistake_ == Mistake::LBufferOverDepth;
}

void MiniPort::fullScreen(rhi::Device& device, bool compensated) {
  rhi::Viewport vp;  // D3D9 centres: the -0.5 of a D3D9 port (0 elsewhere)
  vp.x = vp.y = compensated ? -targets_->plan().pixelCenterOffset : 0.0f;
  device.setViewport(vp);
  device.draw(3);
}

rhi::TextureHandle MiniPort::render(rhi::Device& device, scene::SceneGpu&, const scene::Camera&) {
  auto simplePass = [&](const char* label, rhi::TextureHandle target, rhi::PipelineHandle p) {
    rhi::PassDesc pass;
    pass.colors[0].texture = target;
    pass.label = label;
    device.beginPass(pass);
    device.setPipeline(p);
    device.draw(3);
    device.endPass();
  };
  // G-buffer.
  rhi::PassDesc g;
  g.colors[0].texture = targets_->attachment(kAlbedo);
  g.colors[1].texture = mistake_ == Mistake::PackedBlend ? targets_->attachment(kNormal) : targets_->gpu().writeTarget(kNormal);
  g.colors[2].texture = targets_->attachment(kThird);
  g.depthStencil.texture = targets_->attachment("depth");
  g.label = "gbuffer";
  device.beginPass(g);
  device.setPipeline(gbuffer_);
  fullScreen(device);
  device.endPass();
  if (mistake_ == Mistake::ScratchOverDepth) simplePass("scratch", targets_->attachment(kScratch), plain_);
  if (mistake_ == Mistake::OwnRg16Target) simplePass("own rg16", own_, plain_);
  if (mistake_ == Mistake::OwnTargetSampled) simplePass("own", own_, plain_);
  if (mistake_ == Mistake::PackedMsaaResolve) {
    simplePass("dsf", targets_->attachment(kDsf4x), packedMsaa_);
    targets_->resolve(kDsf4x);
  }
  if (mistake_ == Mistake::OwnFloatDepthSampled || mistake_ == Mistake::MsaaDepthSampled) {
    rhi::PassDesc z;
    z.depthStencil.texture = own_;
    z.depthStencil.clearDepth = 0.25f;
    z.label = "own depth";
    device.beginPass(z);
    device.endPass();
  }
  targets_->resolve("depth");
  const bool gbufferResolvedLate = mistake_ == Mistake::LBufferBeforeResolve;
  if (mistake_ == Mistake::UnalignedResolve) targets_->resolve(kAlbedo, 1, rhi::Rect{4, 4, 64, 32});
  else if (mistake_ != Mistake::SampleBeforeResolve && !gbufferResolvedLate) targets_->resolve(kAlbedo);
  if (!gbufferResolvedLate) targets_->resolve(kNormal);
  if (mistake_ == Mistake::SurfaceTooLarge) simplePass("big", targets_->attachment(kBig), plainMsaa_);
  if (mistake_ == Mistake::StaleResolve) {
    rhi::PassDesc again;
    again.colors[0].texture = targets_->attachment(kAlbedo);
    again.colors[0].load = rhi::LoadOp::Load;
    again.label = "albedo touch-up";
    device.beginPass(again);
    device.setPipeline(plain_);
    device.draw(3);
    device.endPass();
  }

  // Light.
  rhi::PassDesc l;
  l.colors[0].texture = targets_->attachment(kLight);
  l.colors[0].clearColor = targets_->gpu().clearColor(kLight, {0.0f, 0.0f, 0.0f, 0.0f});
  if (depthBoundInLight()) {
    l.depthStencil.texture = targets_->attachment("depth");
    l.depthStencil.load = rhi::LoadOp::Load;
  }
  l.label = "light";
  device.beginPass(l);
  device.setPipeline(light_);
  const rhi::TextureHandle albedo =
      mistake_ == Mistake::SampleEdramSurface ? targets_->attachment(kAlbedo) : targets_->readTexture(kAlbedo);
  const bool packedFilter = mistake_ == Mistake::PackedFilter;
  std::vector<rhi::ResourceBinding> b = {
      sampledWith(4, albedo, nearest_),
      sampledWith(5, packedFilter ? targets_->attachment(kNormal) : targets_->readTexture(kNormal), packedFilter ? linear_ : nearest_),
      sampledWith(6, targets_->readTexture("depth"), mistake_ == Mistake::DepthFiltered ? linear_ : rhi::SamplerHandle{})};
  if (mistake_ == Mistake::DepthSurfaceSampled || mistake_ == Mistake::DepthSampledWhileBound)
    b.push_back(techniques::sampled(7, targets_->attachment("depth")));
  if (own_ && mistake_ != Mistake::OwnRg16Target) b.push_back(techniques::sampled(7, own_));
  device.setBindings(b);
  fullScreen(device);
  device.endPass();
  if (gbufferResolvedLate) {
    targets_->resolve(kAlbedo);
    targets_->resolve(kNormal);
  }
  targets_->resolve(kLight);

  // Compose.
  rhi::PassDesc c;
  c.colors[0].texture = targets_->attachment("color");
  c.label = "compose";
  device.beginPass(c);
  device.setPipeline(compose_);
  const rhi::ResourceBinding cb[] = {sampledWith(4, targets_->readTexture(kLight), linear_),
                                     sampledWith(5, targets_->readTexture(kAlbedo), nearest_)};
  device.setBindings(cb);
  if (mistake_ == Mistake::MixedCentres) fullScreen(device, true);
  if (mistake_ == Mistake::QuadD3D10Centres) {
    device.setVertexBuffer(0, quad_);
    device.draw(4);
  } else {
    fullScreen(device, mistake_ != Mistake::D3D10Centres && mistake_ != Mistake::MixedCentres);
  }
  device.endPass();
  return targets_->present();
}

std::vector<techniques::NamedTarget> MiniPort::targets() const {
  if (!targets_) return {};
  return {{"color", targets_->readTexture("color")}};
}

void MiniPort::release(rhi::Device& device) {
  for (rhi::PipelineHandle p : pipelines_) device.destroy(p);
  for (rhi::ShaderHandle s : shaders_) device.destroy(s);
  pipelines_.clear();
  shaders_.clear();
  if (nearest_) device.destroy(nearest_);
  if (linear_) device.destroy(linear_);
  if (own_) device.destroy(own_);
  if (quad_) device.destroy(quad_);
  quad_ = {};
  nearest_ = linear_ = {};
  own_ = {};
  targets_.reset();
}

void registerMiniPorts() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (const MistakeInfo& m : allMistakes()) {
      const Mistake mistake = m.mistake;
      techniques::registerTechnique({MiniPort(mistake).name(), m.what, [mistake] { return std::make_unique<MiniPort>(mistake); }});
    }
  });
}

}  // namespace parity::test
