// RUN and CLEAR: attachments, graphics and compute pipelines, bindings, draws and dispatches.
#include "harness/scripts/runner/steps.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <regex>
#include <set>
#include <sstream>

#include "harness/io/text.h"
#include "harness/scripts/spirv_interface.h"
#include "rhi/shader_compiler.h"
#include "platforms/x360/pixel_center.h"
#include "rhi/shader_reflection.h"

namespace parity::harness::script::runner {

// Fills the vertex input of `desc` from the pipeline's VERTEX_DATA (or the generated
// position-only buffer of DRAW_RECT/DRAW_GRID when `rectBuffer`).
void PassSteps::vertexInput(const Pipeline& p, rhi::BufferHandle rectBuffer, rhi::PipelineDesc& desc,
                            std::vector<std::pair<rhi::BufferHandle, size_t>>& slots) {
  const Shader* vs = nullptr;
  for (const std::string& n : p.shaders)
    if (script_.findShader(n)->stage == Stage::Vertex) vs = script_.findShader(n);
  if (rectBuffer) {
    // piglit's `draw rect` feeds piglit_vertex and piglit_texcoord (0..1 over the rectangle),
    // wherever the compiler placed them; every other vertex shader reads location 0.
    uint32_t position = 0;
    std::optional<uint32_t> texcoord;
    if (vs && vs->openGl && !vs->passthrough) {
      const std::vector<uint32_t>& spirv = compiled_.at(vs->name);
      position = inputLocation(spirv, "piglit_vertex").value_or(inputLocation(spirv, "parity_Vertex").value_or(0));
      texcoord = inputLocation(spirv, "piglit_texcoord");
      if (!texcoord) texcoord = inputLocation(spirv, "parity_MultiTexCoord0");
    }
    desc.attributeCount = texcoord ? 2 : 1;
    desc.attributes[0] = {position, rhi::VertexFormat::Float2, 0, 0};
    if (texcoord) desc.attributes[1] = {*texcoord, rhi::VertexFormat::Float2, 8, 0};
    desc.vertexBuffers[0] = {16, false};
    slots.push_back({rectBuffer, 0});
    return;
  }
  if (vs && vs->format == "ARB" && !p.vertexData.empty())
    throw Unsupported{"[vertex data] for an ARB assembly program (OpenGL's fixed-function vertex arrays)"};
  std::vector<VertexData> inputs;
  for (VertexData v : p.vertexData) {
    // Attributes by name (shader_test): the compiler's location; one the shader does not read is left out.
    if (!v.attribute.empty()) {
      std::optional<uint32_t> location = vs ? inputLocation(compiled_.at(vs->name), v.attribute) : std::nullopt;
      if (!location) continue;
      v.location = *location + v.locationOffset;
    }
    inputs.push_back(v);
  }
  // Attributes read straight from one buffer with one stride share its slot (piglit's columns
  // are one interleaved buffer); a converted attribute gets a buffer and slot of its own.
  // The slot is bound at its first attribute's offset (offsets within a vertex stay small).
  struct Shared {
    std::string buffer;
    uint32_t stride;
    bool perInstance;
    uint32_t slot, offset;
  };
  std::vector<Shared> shared;
  auto sharedSlot = [&](const VertexData& v, uint32_t stride) -> const Shared* {
    for (const Shared& s : shared)
      if (s.buffer == v.buffer && s.stride == stride && s.perInstance == v.perInstance && v.offset >= s.offset &&
          v.offset - s.offset < stride)
        return &s;
    return nullptr;
  };
  auto newSlot = [&]() {
    const uint32_t slot = static_cast<uint32_t>(slots.size());
    if (slot >= rhi::kMaxVertexBuffers) throw Unsupported{"more than 4 vertex buffers"};
    return slot;
  };
  for (size_t i = 0; i < inputs.size(); ++i) {
    const VertexData& v = inputs[i];
    const Buffer* b = script_.findBuffer(v.buffer);
    ElementType t = b->type;
    if (!v.format.empty()) {
      std::string why;
      if (!parseFormat(v.format, &t, &why)) throw Unsupported{"VERTEX_DATA FORMAT " + v.format};
    }
    rhi::VertexFormat vf;
    size_t n = t.layout.fields.size();
    Scalar s = t.layout.fields[0].scalar;
    Mode m = t.layout.fields[0].mode;
    if (s == Scalar::Float32 && n >= 1 && n <= 4) vf = static_cast<rhi::VertexFormat>(static_cast<int>(rhi::VertexFormat::Float) + n - 1);
    else if (s == Scalar::Uint8 && m == Mode::Unorm && n == 4 && t.layout.fields[0].channel == 'R') vf = rhi::VertexFormat::UByte4Norm;
    else if ((s == Scalar::Uint32 || s == Scalar::Int32) && n >= 1 && n <= 4 && integerComponents(t)) vf = integerVertexFormat(s, n);
    else if (n <= 4 && scalarSize(s) < 4 && integerComponents(t)) {
      // 8- and 16-bit integers (R8G8_UINT, int16 vertex data): widened to 32 bits on the CPU,
      // sign-extended where signed, as the fetch would; the shader reads the same values.
      const bool isSigned = s == Scalar::Int8 || s == Scalar::Int16;
      uint32_t stride = v.stride ? v.stride : t.layout.stride;
      std::vector<uint8_t> raw = contents(v.buffer);
      std::vector<int32_t> out;
      for (size_t at = v.offset; stride && at + t.layout.stride <= raw.size(); at += stride)
        for (const Field& f : t.layout.fields) out.push_back(static_cast<int32_t>(readScalar(raw.data() + at + f.offset, f.scalar)));
      if (out.empty()) throw Failure{lineOf(v.loc) + ": VERTEX_DATA '" + v.buffer + "' holds no vertex"};
      desc.attributes[i] = {v.location, integerVertexFormat(isSigned ? Scalar::Int32 : Scalar::Uint32, n), 0,
                            newSlot()};
      desc.vertexBuffers[desc.attributes[i].bufferSlot] = {static_cast<uint32_t>(n * 4), v.perInstance};
      slots.push_back({tempBuffer(out.data(), out.size() * sizeof(int32_t), "widened vertices"), 0});
      continue;
    } else if (s == Scalar::Float64 && n >= 1 && n <= 4) {
      if (!dev_.info().caps.doubleVertexFormats)
        throw Unsupported{"vertex attribute of 64-bit components (" + t.name + "; the device reads no 64-bit vertex input)"};
      vf = static_cast<rhi::VertexFormat>(static_cast<int>(rhi::VertexFormat::Double) + n - 1);
    } else if (n <= 4 && (m == Mode::Unorm || m == Mode::Snorm || m == Mode::Float)) {
      // A format the RHI cannot fetch (R8G8_SNORM, R8_UNORM, half floats, ...): converted to
      // float components on the CPU, as the fetch would (snorm: max(v / 127, -1)).
      uint32_t stride = v.stride ? v.stride : t.layout.stride;
      std::vector<uint8_t> raw = contents(v.buffer);
      std::vector<float> out;
      for (size_t at = v.offset; stride && at + t.layout.stride <= raw.size(); at += stride)
        for (const Field& f : t.layout.fields) {
          double x = readScalar(raw.data() + at + f.offset, f.scalar);
          double bits = scalarSize(f.scalar) * 8.0;
          if (f.mode == Mode::Unorm) x /= std::pow(2.0, bits) - 1;
          if (f.mode == Mode::Snorm) x = std::max(-1.0, x / (std::pow(2.0, bits - 1) - 1));
          out.push_back(static_cast<float>(x));
        }
      if (out.empty()) throw Failure{lineOf(v.loc) + ": VERTEX_DATA '" + v.buffer + "' holds no vertex"};
      desc.attributes[i] = {v.location, static_cast<rhi::VertexFormat>(static_cast<int>(rhi::VertexFormat::Float) + n - 1), 0,
                            newSlot()};
      desc.vertexBuffers[desc.attributes[i].bufferSlot] = {static_cast<uint32_t>(n * 4), v.perInstance};
      slots.push_back({tempBuffer(out.data(), out.size() * sizeof(float), "converted vertices"), 0});
      continue;
    } else throw Unsupported{"vertex format " + t.name};
    const uint32_t stride = v.stride ? v.stride : t.layout.stride;
    if (const Shared* s = sharedSlot(v, stride)) {
      desc.attributes[i] = {v.location, vf, v.offset - s->offset, s->slot};
      continue;
    }
    const uint32_t slot = newSlot();
    desc.attributes[i] = {v.location, vf, 0, slot};
    desc.vertexBuffers[slot] = {stride, v.perInstance};
    slots.push_back({gpuBuffer(v.buffer, v.loc), v.offset});
    shared.push_back({v.buffer, stride, v.perInstance, slot, v.offset});
  }
  desc.attributeCount = static_cast<uint32_t>(inputs.size());
  if (vs && vs->openGl) genericAttributes(compiled_.at(vs->name), desc, slots);
}

// OpenGL: an input no vertex array supplies reads the current generic attribute, (0, 0, 0, 1)
// unless set (piglit draws so: a passthrough vertex shader and no [vertex data]). Here it is a
// constant attribute, one element read with stride 0, in the next free buffer slot.
void PassSteps::genericAttributes(const std::vector<uint32_t>& vertexShader, rhi::PipelineDesc& desc,
                                  std::vector<std::pair<rhi::BufferHandle, size_t>>& slots) {
  rhi::ShaderReflection reflection;
  std::string why;
  if (!rhi::reflectSpirv(vertexShader, rhi::ShaderStage::Vertex, &reflection, &why)) return;  // the pipeline reports it
  const uint32_t slot = static_cast<uint32_t>(slots.size());
  for (uint32_t location : reflection.inputLocations) {
    bool supplied = false;
    for (uint32_t a = 0; a < desc.attributeCount; ++a) {
      const rhi::VertexAttribute& attribute = desc.attributes[a];
      const bool twoLocations = attribute.format == rhi::VertexFormat::Double3 || attribute.format == rhi::VertexFormat::Double4;
      supplied |= location == attribute.location || (twoLocations && location == attribute.location + 1);
    }
    if (supplied) continue;
    if (slot >= rhi::kMaxVertexBuffers || desc.attributeCount >= rhi::kMaxVertexAttributes)
      throw Unsupported{"vertex input at location " + std::to_string(location) + " without an array, past the RHI's vertex buffers"};
    desc.attributes[desc.attributeCount++] = {location, rhi::VertexFormat::Float4, 0, slot};
  }
  if (desc.attributeCount == 0 || desc.attributes[desc.attributeCount - 1].bufferSlot != slot) return;
  static const float kGeneric[4] = {0.0f, 0.0f, 0.0f, 1.0f};
  desc.vertexBuffers[slot] = {0, false};
  slots.push_back({tempBuffer(kGeneric, sizeof kGeneric, "generic vertex attribute"), 0});
}

PassSteps::Attachments PassSteps::attachments(const Pipeline& p, rhi::LoadOp load, const ClearState& cs) {
  Attachments a;
  uint32_t count = 0;
  for (const Bind& b : p.binds)
    if (b.kind == BindKind::Color) count = std::max(count, b.location + 1);
  if (count > rhi::kMaxColorTargets) throw Unsupported{"more than 4 colour attachments"};
  a.colorFormats.assign(count, rhi::Format::Undefined);
  for (const Bind& b : p.binds) {
    if (b.kind == BindKind::Color) {
      Resource& r = res_.at(b.buffer);
      if (rhi::isDepthFormat(r.format.format)) throw Failure{lineOf(b.loc) + ": '" + b.buffer + "' has a depth format"};
      const uint32_t mipWidth = std::max(r.width >> b.baseMipLevel, 1u), mipHeight = std::max(r.height >> b.baseMipLevel, 1u);
      if (mipWidth != p.fbWidth || mipHeight != p.fbHeight)
        throw Unsupported{"attachment '" + b.buffer + "' of " + std::to_string(mipWidth) + "x" + std::to_string(mipHeight) +
                          (b.baseMipLevel ? " at mip " + std::to_string(b.baseMipLevel) : std::string()) + " in a " +
                          std::to_string(p.fbWidth) + "x" + std::to_string(p.fbHeight) + " framebuffer"};
      auto& c = a.pass.colors[b.location];
      c.texture = r.texture;
      c.mip = b.baseMipLevel;
      c.load = load;
      c.clearColor = cs.color;
      a.colorFormats[b.location] = r.format.format;
      a.samples = r.samples;
    } else if (b.kind == BindKind::DepthStencil) {
      Resource& r = res_.at(b.buffer);
      if (!rhi::isDepthFormat(r.format.format)) throw Failure{lineOf(b.loc) + ": '" + b.buffer + "' is not a depth format"};
      a.pass.depthStencil.texture = r.texture;
      a.pass.depthStencil.load = load;
      a.pass.depthStencil.clearDepth = cs.depth;
      a.pass.depthStencil.clearStencil = cs.stencil;
      a.depthFormat = r.format.format;
    }
  }
  for (const Bind& b : p.binds)
    if (b.kind == BindKind::Resolve) {
      if (count == 0) throw Failure{lineOf(b.loc) + ": resolve target without a colour attachment"};
      a.pass.colors[0].resolveTarget = res_.at(b.buffer).texture;
    }
  for (uint32_t i = 0; i < count; ++i)
    if (a.colorFormats[i] == rhi::Format::Undefined) throw Unsupported{"gaps between colour LOCATIONs"};
  return a;
}

// Pipeline state the device cannot give is a SKIP naming the construct.
void PassSteps::requireFeature(bool needed, const std::string& feature, const std::string& construct) const {
  const std::vector<std::string>& offered = dev_.info().features;
  if (needed && std::find(offered.begin(), offered.end(), feature) == offered.end())
    throw Unsupported{construct + " (the device lacks " + feature + ")"};
}

rhi::ShaderHandle PassSteps::passThroughControlShader(const Pipeline& p, const Shader& evaluation, uint32_t patchPoints) {
  if (patchPoints == 0) throw Failure{"pipeline '" + p.name + "' draws patches without a patch size"};
  std::string declarations, copies;
  int k = 0;
  for (const InterfaceVariable& v : interfaceVariables(compiled_.at(evaluation.name))) {
    if (v.output) continue;
    if (v.patch)
      throw Unsupported{"patch input '" + v.name + "' of a tessellation evaluation shader without a control shader"};
    // The declared type, from the source: `in TYPE name[];` (blocks and other forms are not passed).
    std::smatch m;
    if (!std::regex_search(evaluation.source, m, std::regex(R"(\bin\s+(\w+)\s+)" + v.name + R"(\s*\[\s*\]\s*;)")))
      throw Unsupported{"input '" + v.name + "' of a tessellation evaluation shader without a control shader (only `in TYPE name[];` is passed through)"};
    std::string layout = "layout(location = " + std::to_string(v.location) +
                         (v.componentWord ? ", component = " + std::to_string(v.component) : std::string()) + ") ";
    const std::string n = std::to_string(k++);
    declarations += layout + "in " + m[1].str() + " parity_in" + n + "[];\n" + layout + "out " + m[1].str() + " parity_out" + n + "[];\n";
    copies += "  parity_out" + n + "[gl_InvocationID] = parity_in" + n + "[gl_InvocationID];\n";
  }
  std::ostringstream levels;
  levels.precision(9);
  for (int i = 0; i < 4; ++i) levels << "  gl_TessLevelOuter[" << i << "] = " << std::showpoint << p.defaultTessLevels[size_t(i)] << ";\n";
  for (int i = 0; i < 2; ++i) levels << "  gl_TessLevelInner[" << i << "] = " << std::showpoint << p.defaultTessLevels[size_t(4 + i)] << ";\n";
  // gl_in and gl_out redeclared with the members the vertex shader writes and the evaluation
  // shader reads: Vulkan requires a built-in block to match its neighbour's (validation checks).
  const Shader* vertex = nullptr;
  for (const std::string& n : p.shaders)
    if (const Shader* s = script_.findShader(n); s->stage == Stage::Vertex) vertex = s;
  const std::vector<std::string> in = vertex ? perVertexMembers(compiled_.at(vertex->name), true) : std::vector<std::string>{};
  const std::vector<std::string> out = perVertexMembers(compiled_.at(evaluation.name), false);
  auto block = [](const std::vector<std::string>& members) {
    std::string b;
    for (const std::string& m : members) b += " " + m;
    return b;
  };
  std::string body;
  const std::pair<const char*, const char*> kPassed[] = {{"vec4 gl_Position;", "gl_Position"}, {"float gl_PointSize;", "gl_PointSize"}};
  for (const auto& [member, name] : kPassed)
    if (std::count(in.begin(), in.end(), member) && std::count(out.begin(), out.end(), member))
      body += std::string("  gl_out[gl_InvocationID].") + name + " = gl_in[gl_InvocationID]." + name + ";\n";
  std::string source = "#version 450\nlayout(vertices = " + std::to_string(patchPoints) + ") out;\n";
  if (!in.empty()) source += "in gl_PerVertex {" + block(in) + " } gl_in[gl_MaxPatchVertices];\n";
  if (!out.empty()) source += "out gl_PerVertex {" + block(out) + " } gl_out[];\n";
  source += declarations + "void main() {\n" + body + copies + levels.str() + "}\n";
  const std::string label = "pass-through tessellation control (default levels) of '" + p.name + "'";
  rhi::CompiledShader c = rhi::compileGlslSource(source, label, rhi::ShaderStage::TessControl, {});
  if (!c.ok()) throw Failure{"the " + label + " does not compile: " + oneLine(c.error)};
  rhi::ShaderDesc sd;
  sd.stage = rhi::ShaderStage::TessControl;
  sd.spirv = c.spirv;
  sd.label = label;
  rhi::ShaderHandle h = dev_.createShader(sd);
  if (!h) throw Failure{"cannot create the " + label};
  shaders_.push_back(h);
  return h;
}

rhi::PipelineHandle PassSteps::graphicsPipeline(const Pipeline& p, rhi::PrimitiveTopology topology, bool rect,
                                                const Attachments& att, std::vector<std::pair<rhi::BufferHandle, size_t>>& slots,
                                                rhi::BufferHandle rectBuffer, uint32_t patchPoints) {
  rhi::PipelineDesc d;
  d.separablePrograms = script_.separableProgram;
  vertexInput(p, rectBuffer, d, slots);
  if (!patchPoints) patchPoints = p.patchControlPoints;
  std::string key = p.name + "/" + std::to_string(int(topology)) + (rect ? "/rect" : "") + "/" + std::to_string(patchPoints);
  auto it = pipelines_.find(key);
  if (it != pipelines_.end()) return it->second.handle;
  std::vector<rhi::ShaderHandle> sh = makeShaders(p);
  for (size_t i = 0; i < p.shaders.size(); ++i) {
    Stage st = script_.findShader(p.shaders[i])->stage;
    if (st == Stage::Vertex) d.vertexShader = sh[i];
    if (st == Stage::Fragment) d.fragmentShader = sh[i];
    if (st == Stage::Geometry) d.geometryShader = sh[i];
    if (st == Stage::TessControl) d.tessControlShader = sh[i];
    if (st == Stage::TessEvaluation) d.tessEvaluationShader = sh[i];
  }
  if (d.tessEvaluationShader && !d.tessControlShader) {
    for (const std::string& n : p.shaders)
      if (const Shader* s = script_.findShader(n); s->stage == Stage::TessEvaluation)
        d.tessControlShader = passThroughControlShader(p, *s, patchPoints);
  }
  d.patchControlPoints = patchPoints;
  if (!d.vertexShader || !d.fragmentShader) throw Failure{"pipeline '" + p.name + "' needs a vertex and a fragment shader"};
  d.topology = topology;
  d.raster.cull = p.cullMode == "front" ? rhi::CullMode::Front : p.cullMode == "back" ? rhi::CullMode::Back : rhi::CullMode::None;
  d.raster.frontFace = p.frontFace == "clockwise" ? rhi::FrontFace::Clockwise : rhi::FrontFace::CounterClockwise;
  d.raster.polygonMode = p.polygonMode == "line"    ? rhi::PolygonMode::Line
                         : p.polygonMode == "point" ? rhi::PolygonMode::Point
                                                    : rhi::PolygonMode::Fill;
  d.raster.depthClampEnabled = p.depthClamp;
  // The provoking vertex only shows in flat inputs: without them a device lacking OpenGL's
  // convention draws the pipeline the same.
  static const std::regex kFlat(R"(\bflat\b)");
  const bool flatInputs = script_.fixedFunction.flatShading ||
                          std::any_of(p.shaders.begin(), p.shaders.end(), [&](const std::string& n) {
                            const Shader* s = script_.findShader(n);
                            return s->stage == Stage::Fragment && std::regex_search(s->source, kFlat);
                          });
  const bool provokingLast = p.provokingVertexLast && flatInputs;
  d.raster.provokingVertex = provokingLast ? rhi::ProvokingVertex::Last : rhi::ProvokingVertex::First;
  requireFeature(provokingLast, "provokingVertexLast", "OpenGL's provoking vertex (the last) with flat inputs");
  d.raster.depthBias = {p.depthBiasConstant, p.depthBiasSlope, p.depthBiasClamp};
  requireFeature(d.raster.polygonMode != rhi::PolygonMode::Fill, "fillModeNonSolid", "POLYGON_MODE " + p.polygonMode);
  requireFeature(p.depthClamp, "depthClamp", "DEPTH CLAMP on");
  requireFeature(p.depthBiasClamp != 0, "depthBiasClamp", "DEPTH BIAS clamp");
  requireFeature(topology >= rhi::PrimitiveTopology::LinesWithAdjacency, "geometryShader", "adjacency topologies");
  if (p.depthTest) {
    d.depthStencil.depthCompare = compareOp(p.depthCompare);
    d.depthStencil.depthWrite = p.depthWrite;
  }
  if (p.front.test || p.back.test) {
    // The RHI has one reference and one pair of masks: faces may differ in values they do not use.
    const StencilValues values = stencilValues(p);
    if (!values.agree) throw Unsupported{"different stencil reference or masks per face"};
    d.depthStencil.stencilEnabled = true;
    auto face = [](const StencilFace& f) {
      rhi::StencilFaceState s;
      if (!f.test) return s;
      s.compare = compareOp(f.compareOp);
      s.fail = stencilOp(f.failOp);
      s.pass = stencilOp(f.passOp);
      s.depthFail = stencilOp(f.depthFailOp);
      return s;
    };
    d.depthStencil.front = face(p.front);
    d.depthStencil.back = face(p.back);
    d.depthStencil.stencilReadMask = static_cast<uint8_t>(values.compareMask);
    d.depthStencil.stencilWriteMask = static_cast<uint8_t>(values.writeMask);
  }
  d.colorTargetCount = static_cast<uint32_t>(att.colorFormats.size());
  for (size_t i = 0; i < att.colorFormats.size(); ++i) {
    d.colorTargets[i].format = att.colorFormats[i];
    d.colorTargets[i].writeMask = p.colorWriteMask;
    if (p.blend.enabled) {
      auto& b = d.colorTargets[i].blend;
      b.enabled = true;
      b.srcColor = blendFactor(p.blend.srcColor);
      b.dstColor = blendFactor(p.blend.dstColor);
      b.colorOp = blendOp(p.blend.colorOp);
      b.srcAlpha = blendFactor(p.blend.srcAlpha);
      b.dstAlpha = blendFactor(p.blend.dstAlpha);
      b.alphaOp = blendOp(p.blend.alphaOp);
    }
  }
  d.depthStencilFormat = att.depthFormat;
  d.samples = att.samples;
  d.label = p.name;
  rhi::PipelineHandle h = dev_.createPipeline(d);
  if (!h) throw Failure{"cannot create pipeline '" + p.name + "'" + deviceLog()};
  pipelines_[key] = {h};
  return h;
}

// Contents of the pipeline's push_constant buffer, read before a pass begins (reads are
// transfers, which the RHI does not allow inside passes).
std::vector<uint8_t> PassSteps::pushConstantBytes(const Pipeline& p) {
  for (const Bind& b : p.binds)
    if (b.kind == BindKind::PushConstant) return contents(b.buffer);
  return {};
}

void PassSteps::useSamplerStates(const std::vector<Sampler>& states) {
  for (const Sampler& s : states) {
    std::ostringstream key;
    key << s.name << '/' << s.linearMag << s.linearMin << '/' << s.mipmapMode << '/' << s.addressMode[0] << ','
        << s.addressMode[1] << ',' << s.addressMode[2] << '/' << s.borderColor << '/' << s.minLod << ',' << s.maxLod << ',' << s.lodBias << '/' << s.compare << '/'
        << s.compareOp;
    rhi::SamplerHandle& h = samplerStates_[key.str()];
    if (!h) samplers_.push_back(h = makeSampler(s));
    samplerByName_[s.name] = h;
    samplerStateByName_[s.name] = s;
  }
}

void PassSteps::convertSnormTexelBuffers(const Pipeline& p) {
  snormTexels_.clear();
  for (const Bind& b : bindsOf(p)) {
    if (b.kind != BindKind::UniformTexelBuffer) continue;
    const Buffer* def = res_.at(b.buffer).def;
    if (!def || !def->type.isFormat) continue;
    const TexFormat tf = textureFormat(def->type);
    if (tf.bgra || tf.format == rhi::Format::Undefined || rhi::isTexelBufferFormat(tf.format) ||
        rhi::formatInfo(tf.format).kind != rhi::FormatKind::Snorm)
      continue;
    const rhi::FormatInfo& info = rhi::formatInfo(tf.format);
    const uint32_t channels = info.channels, bits = info.bytesPerTexel * 8 / channels;
    const rhi::Format floats[] = {rhi::Format::R32F, rhi::Format::RG32F, rhi::Format::Undefined, rhi::Format::RGBA32F};
    if (channels < 1 || channels > 4 || floats[channels - 1] == rhi::Format::Undefined || (bits != 8 && bits != 16))
      continue;  // bindResources names the format
    // What the texels hold when the pass runs (an earlier pass may have written them).
    const rhi::BufferHandle source = gpuBuffer(b.buffer, b.loc);
    const size_t offset = static_cast<size_t>(b.offset);
    const size_t size = b.range != 0 ? static_cast<size_t>(b.range) : dev_.describe(source)->size - offset;
    const std::vector<uint8_t> texels = dev_.readBuffer(source, offset, size);
    const double largest = bits == 8 ? 127.0 : 32767.0;
    std::vector<float> values(texels.size() * 8 / bits / channels * channels);
    for (size_t i = 0; i < values.size(); ++i) {
      const double c = bits == 8 ? static_cast<int8_t>(texels[i]) : static_cast<int16_t>(texels[2 * i] | texels[2 * i + 1] << 8);
      values[i] = static_cast<float>(std::max(c / largest, -1.0));  // the snorm rule of Vulkan and GL
    }
    rhi::ResourceBinding& r = snormTexels_[{b.set, b.binding, b.arrayElement}];
    r.buffer = tempBuffer(values.data(), std::max<size_t>(values.size(), 1) * sizeof(float), "snorm texels as floats");
    r.offset = 0;
    r.size = values.size() * sizeof(float);
    r.texelFormat = floats[channels - 1];
  }
}

void PassSteps::bindResources(const Pipeline& p, const std::vector<uint8_t>& pushBytes) {
  const auto& map = bindingMaps_.at(p.name);
  std::vector<rhi::ResourceBinding> rb = defaults_[p.name];
  for (const Bind& b : bindsOf(p)) {
    rhi::ResourceBinding r;
    auto it = map.find({b.set, b.binding});
    if (it != map.end()) r.binding = it->second;
    r.arrayElement = b.arrayElement;
    switch (b.kind) {
      case BindKind::Storage:
      case BindKind::Uniform:
        r.kind = b.kind == BindKind::Storage ? rhi::BindingKind::StorageBuffer : rhi::BindingKind::UniformBuffer;
        r.buffer = gpuBuffer(b.buffer, b.loc);
        r.offset = static_cast<size_t>(b.offset);
        r.size = static_cast<size_t>(b.range);
        break;
      case BindKind::CombinedImageSampler: {
        r.kind = rhi::BindingKind::SampledTexture;
        auto state = samplerStateByName_.find(b.sampler);
        r.texture = sampledTexture(b, state == samplerStateByName_.end() ? nullptr : &state->second);
        if (!b.sampler.empty()) r.sampler = samplerByName_.at(b.sampler);
        break;
      }
      case BindKind::StorageImage:
        r.kind = rhi::BindingKind::StorageTexture;
        r.texture = res_.at(b.buffer).texture;
        r.mip = b.baseMipLevel;
        break;
      case BindKind::SampledImage:
        r.kind = rhi::BindingKind::SeparateTexture;
        r.texture = sampledTexture(b);
        break;
      case BindKind::UniformTexelBuffer:
      case BindKind::StorageTexelBuffer: {
        r.kind = b.kind == BindKind::UniformTexelBuffer ? rhi::BindingKind::UniformTexelBuffer
                                                        : rhi::BindingKind::StorageTexelBuffer;
        r.buffer = gpuBuffer(b.buffer, b.loc);
        r.offset = static_cast<size_t>(b.offset);
        r.size = static_cast<size_t>(b.range);
        // The buffer's FORMAT (or format-named DATA_TYPE) is the texels' format.
        const Buffer* def = res_.at(b.buffer).def;
        if (!def || !def->type.isFormat) throw Unsupported{"texel buffer '" + b.buffer + "' without a FORMAT"};
        TexFormat tf = textureFormat(def->type);
        if (auto converted = snormTexels_.find({b.set, b.binding, b.arrayElement}); converted != snormTexels_.end()) {
          r.buffer = converted->second.buffer;
          r.offset = 0;
          r.size = converted->second.size;
          r.texelFormat = converted->second.texelFormat;
          break;
        }
        if (tf.bgra || !rhi::isTexelBufferFormat(tf.format))
          throw Unsupported{"texel buffer '" + b.buffer + "' of FORMAT " + def->type.name + " (not a texel buffer format of the RHI)"};
        r.texelFormat = tf.format;
        break;
      }
      case BindKind::Sampler:
        r.kind = rhi::BindingKind::SeparateSampler;
        r.sampler = samplerByName_.at(b.buffer);
        break;
      case BindKind::PushConstant: {
        if (pushBytes.size() > rhi::kMaxPushConstantBytes) throw Unsupported{"push constants over 128 bytes"};
        // The RHI pushes whole words; a shorter buffer (one int8, one int16) is padded with zeros,
        // and so are the bytes the shaders declare past the last value the script set.
        std::vector<uint8_t> words(pushBytes);
        words.resize(std::max<size_t>((words.size() + 3) / 4 * 4, pushConstantSizes_[p.name]), 0);
        dev_.pushConstants(words.data(), static_cast<uint32_t>(words.size()));
        continue;
      }
      default: continue;
    }
    rb.push_back(r);
  }
  if (!rb.empty()) dev_.setBindings(rb);
}

void PassSteps::draw(const Command& c, const Pipeline& p) {
  if (!p.subgroups.empty()) throw Unsupported{"SUBGROUP on a graphics pipeline (the RHI controls compute subgroups only)"};
  ClearState& cs = clear_[p.name];
  Attachments att = attachments(p, rhi::LoadOp::Load, cs);
  std::vector<std::pair<rhi::BufferHandle, size_t>> slots;
  rhi::PipelineHandle ph;
  uint32_t vertexCount = 0, instanceCount = 1, firstVertex = 0, firstInstance = 0;
  bool indexed = false;
  rhi::BufferHandle indexBuffer;
  rhi::IndexType indexType = rhi::IndexType::UInt32;
  uint32_t indexOffsetBytes = 0;
  if (c.kind == Command::Kind::DrawRect || c.kind == Command::Kind::DrawGrid) {
    // As in Amber, the rectangle's vertices replace the pipeline's one VERTEX_DATA for this draw;
    // Amber refuses the draw on a pipeline with more than one.
    if (p.vertexData.size() > 1)
      throw Failure{lineOf(c.loc) + ": " + (c.kind == Command::Kind::DrawRect ? "DRAW_RECT" : "DRAW_GRID") +
                    " on pipeline '" + p.name + "' with more than one VERTEX_DATA"};
    // Amber: pixels to NDC, (0, 0) the top-left = NDC (-1, -1) = framebuffer row 0.
    // x360 screen-space draws: D3D9 pixel centres (PIX_CENTER = 0, HALFPIXELOFFSET FALSE) are
    // emulated as the host does, by moving window positions +0.5 px (X5).
    float centre = platform_ == platforms::PlatformId::X360
                       ? platforms::x360::hostWindowOffset(platforms::x360::pixelCenterFor(params_.halfPixelOffset, params_))
                       : 0.0f;
    float fw = static_cast<float>(p.fbWidth), fh = static_cast<float>(p.fbHeight);
    float x = (c.x + centre) / fw * 2.0f - 1.0f, y = (c.y + centre) / fh * 2.0f - 1.0f, w = c.w / fw * 2.0f, h = c.h / fh * 2.0f;
    if (c.ndc) x = c.x, y = c.y, w = c.w, h = c.h;
    std::vector<float> v;
    rhi::PrimitiveTopology topo;
    if (c.kind == Command::Kind::DrawRect && (c.patch || c.piglitCorners)) {
      // piglit_draw_rect's order: a strip, or one patch (`draw rect patch`).
      v = {x, y, x + w, y, x, y + h, x + w, y + h};
      topo = c.patch ? rhi::PrimitiveTopology::Patches : rhi::PrimitiveTopology::TriangleStrip;
    } else if (c.kind == Command::Kind::DrawRect) {
      v = {x, y + h, x, y, x + w, y + h, x + w, y};
      topo = rhi::PrimitiveTopology::TriangleStrip;
    } else {
      topo = rhi::PrimitiveTopology::Triangles;
      float cw = w / static_cast<float>(c.cellsX), ch = h / static_cast<float>(c.cellsY);
      for (uint32_t j = 0; j < c.cellsY; ++j)
        for (uint32_t i = 0; i < c.cellsX; ++i) {
          float x0 = x + cw * static_cast<float>(i), y0 = y + ch * static_cast<float>(j), x1 = x0 + cw, y1 = y0 + ch;
          // Two triangles split along the top-left/bottom-right diagonal, both starting at the
          // cell's top-left corner (the provoking vertex of flat inputs).
          float q[12] = {x0, y0, x1, y0, x1, y1, x0, y0, x1, y1, x0, y1};
          v.insert(v.end(), q, q + 12);
        }
    }
    // Each vertex: its position and its texture coordinate (0..1 across the rectangle, or the
    // range `draw rect tex` gives).
    std::vector<float> interleaved;
    const auto& [s0, t0, sw, th] = c.texcoords;
    for (size_t i = 0; i + 1 < v.size(); i += 2)
      interleaved.insert(interleaved.end(), {v[i], v[i + 1], s0 + (w != 0 ? (v[i] - x) / w : 0.0f) * sw, t0 + (h != 0 ? (v[i + 1] - y) / h : 0.0f) * th});
    rhi::BufferHandle vb = tempBuffer(interleaved.data(), interleaved.size() * sizeof(float), "rect vertices");
    ph = graphicsPipeline(p, topo, true, att, slots, vb, c.patch ? 4 : 0);
    vertexCount = static_cast<uint32_t>(v.size() / 2);
    instanceCount = c.instanceCount;  // piglit's `draw instanced rect`
  } else {
    static const std::map<std::string, rhi::PrimitiveTopology> kTopo = {
        {"TRIANGLE_LIST", rhi::PrimitiveTopology::Triangles}, {"TRIANGLE_STRIP", rhi::PrimitiveTopology::TriangleStrip},
        {"TRIANGLE_FAN", rhi::PrimitiveTopology::Triangles}, {"LINE_LIST", rhi::PrimitiveTopology::Lines},
        {"POINT_LIST", rhi::PrimitiveTopology::Points}, {"LINE_STRIP", rhi::PrimitiveTopology::LineStrip},
        {"PATCH_LIST", rhi::PrimitiveTopology::Patches},
        {"LINE_LIST_WITH_ADJACENCY", rhi::PrimitiveTopology::LinesWithAdjacency},
        {"LINE_STRIP_WITH_ADJACENCY", rhi::PrimitiveTopology::LineStripWithAdjacency},
        {"TRIANGLE_LIST_WITH_ADJACENCY", rhi::PrimitiveTopology::TrianglesWithAdjacency},
        {"TRIANGLE_STRIP_WITH_ADJACENCY", rhi::PrimitiveTopology::TriangleStripWithAdjacency}};
    auto t = kTopo.find(c.topology);
    if (t == kTopo.end()) throw Unsupported{"DRAW_ARRAY AS " + c.topology};
    bool fan = c.topology == "TRIANGLE_FAN";
    ph = graphicsPipeline(p, t->second, false, att, slots, {}, c.patchControlPoints);
    instanceCount = c.instanceCount;
    firstInstance = c.instanceStart;
    // Vertex count: COUNT, or every element of the first vertex buffer (or index buffer).
    std::vector<uint32_t> indices;  // when converted on the CPU (uint8 indices, fans)
    if (c.indexed) {
      if (p.indexData.empty()) throw Failure{lineOf(c.loc) + ": DRAW_ARRAY INDEXED on a pipeline without INDEX_DATA"};
      const Buffer* ib = script_.findBuffer(p.indexData);
      Scalar s = ib->type.layout.fields[0].scalar;
      size_t n = ib->bytes.size() / scalarSize(s);
      uint32_t count = c.countGiven ? c.count : static_cast<uint32_t>(n - std::min<size_t>(n, c.start));
      if (s == Scalar::Uint8 || fan) {
        std::vector<uint8_t> raw = contents(p.indexData);
        std::vector<uint32_t> all;
        for (size_t i = 0; i < n; ++i) all.push_back(static_cast<uint32_t>(readScalar(raw.data() + i * scalarSize(s), s)));
        std::vector<uint32_t> sel(all.begin() + std::min<size_t>(c.start, n), all.begin() + std::min<size_t>(c.start + count, n));
        indices = sel;
      } else {
        indexBuffer = gpuBuffer(p.indexData, c.loc);
        indexType = s == Scalar::Uint16 ? rhi::IndexType::UInt16 : rhi::IndexType::UInt32;
        if (s != Scalar::Uint16 && s != Scalar::Uint32) throw Unsupported{"INDEX_DATA of " + ib->type.name};
        indexOffsetBytes = c.start * scalarSize(s);
        vertexCount = count;
      }
      indexed = true;
    } else {
      uint32_t n = 0;
      if (!p.vertexData.empty()) {
        const Buffer* vb = script_.findBuffer(p.vertexData[0].buffer);
        uint32_t stride = p.vertexData[0].stride ? p.vertexData[0].stride : vb->type.layout.stride;
        n = static_cast<uint32_t>(vb->bytes.size() / std::max(1u, stride));
      }
      uint32_t count = c.countGiven ? c.count : n - std::min(n, c.start);
      if (fan) {
        for (uint32_t i = 0; i < count; ++i) indices.push_back(c.start + i);
      } else {
        vertexCount = count;
        firstVertex = c.start;
      }
    }
    if (fan || !indices.empty() || (indexed && !indexBuffer)) {
      std::vector<uint32_t> list;
      if (fan) {
        for (size_t i = 1; i + 1 < indices.size(); ++i) list.insert(list.end(), {indices[0], indices[i], indices[i + 1]});
      } else {
        list = indices;
      }
      if (list.empty()) list.push_back(0), vertexCount = 0;
      else vertexCount = static_cast<uint32_t>(list.size());
      indexBuffer = tempBuffer(list.data(), list.size() * 4, "converted indices");
      indexType = rhi::IndexType::UInt32;
      indexOffsetBytes = 0;
      indexed = true;
    }
  }
  std::vector<uint8_t> pushBytes = pushConstantBytes(p);
  useSamplerStates(c.samplerStates);
  convertSnormTexelBuffers(p);
  dev_.beginPass(att.pass);
  dev_.setPipeline(ph);
  applyArbProgramState(p);
  if (p.viewport) dev_.setViewport({(*p.viewport)[0], (*p.viewport)[1], (*p.viewport)[2], (*p.viewport)[3], p.viewportDepth[0], p.viewportDepth[1]});
  if (p.front.test || p.back.test) dev_.setStencilReference(static_cast<uint8_t>(stencilValues(p).reference));
  if (p.blend.enabled) dev_.setBlendConstant(p.blend.constant);
  bindResources(p, pushBytes);
  for (size_t i = 0; i < slots.size(); ++i) dev_.setVertexBuffer(static_cast<uint32_t>(i), slots[i].first, slots[i].second);
  if (indexed) {
    dev_.setIndexBuffer(indexBuffer, indexType, indexOffsetBytes);
    if (vertexCount) dev_.drawIndexed(vertexCount, instanceCount, 0, c.baseVertex, firstInstance);
  } else if (vertexCount) {
    dev_.draw(vertexCount, instanceCount, firstVertex, firstInstance);
  }
  dev_.endPass();
  // What the console's render backend stores of the logical images drawn into: x360 clamps fixed
  // point and rounds 7e3 after every write (the shaders write them unclamped; nothing elsewhere).
  for (const Bind& b : p.binds)
    if (b.kind == BindKind::Color && res_.at(b.buffer).logical && targets_) {
      targets_->clampFixedPoint(b.buffer);
      targets_->quantiseFloat7e3(b.buffer);
    }
}

// SUBGROUP: the compute shader's subgroup size control; the device's sizes bound REQUIRED_SIZE.
void PassSteps::subgroupControl(const Pipeline& p, rhi::ComputePipelineDesc& d) const {
  for (const auto& [shader, control] : p.subgroups) {
    const rhi::DeviceInfo& info = dev_.info();
    const rhi::Capabilities& caps = info.caps;
    if (!caps.subgroupSizeControl)
      throw Unsupported{"SUBGROUP (subgroup size control, which " + info.renderer + " on " + info.backend + " lacks)"};
    d.fullSubgroups = control.fullyPopulated;
    d.varyingSubgroupSize = control.varyingSize;
    const std::string& size = control.requiredSize;
    d.requiredSubgroupSize = size == "MIN" ? caps.minSubgroupSize : size == "MAX" ? caps.maxSubgroupSize
                           : size.empty() ? 0 : static_cast<uint32_t>(std::stoul(size));
    const uint32_t n = d.requiredSubgroupSize;
    if (n && ((n & (n - 1)) || n < caps.minSubgroupSize || n > caps.maxSubgroupSize))
      throw Unsupported{"SUBGROUP REQUIRED_SIZE " + size + " (" + info.renderer + " has subgroups of " + std::to_string(caps.minSubgroupSize) +
                        " to " + std::to_string(caps.maxSubgroupSize) + ")"};
  }
}

rhi::ComputePipelineHandle PassSteps::computePipeline(const Pipeline& p) {
  auto it = computePipelines_.find(p.name);
  if (it != computePipelines_.end()) return it->second;
  std::vector<rhi::ShaderHandle> sh = makeShaders(p);
  if (sh.size() != 1) throw Failure{"compute pipeline '" + p.name + "' needs one compute shader"};
  rhi::ComputePipelineDesc d;
  d.computeShader = sh[0];
  d.label = p.name;
  subgroupControl(p, d);
  rhi::ComputePipelineHandle h = dev_.createComputePipeline(d);
  if (!h) throw Failure{"cannot create compute pipeline '" + p.name + "'" + deviceLog()};
  return computePipelines_[p.name] = h;
}

void PassSteps::link(const Pipeline& p) {
  if (p.compute) {
    computePipeline(p);
    return;
  }
  const Attachments att = attachments(p, rhi::LoadOp::Load, clear_[p.name]);
  std::vector<std::pair<rhi::BufferHandle, size_t>> slots;
  const float corners[16] = {-1, -1, 0, 0, 1, -1, 1, 0, -1, 1, 0, 1, 1, 1, 1, 1};
  const bool tessellated = std::any_of(p.shaders.begin(), p.shaders.end(), [&](const std::string& n) {
    const Stage s = script_.findShader(n)->stage;
    return s == Stage::TessControl || s == Stage::TessEvaluation;
  });
  // `draw rect patch`'s pipeline where the shaders tessellate, `draw rect`'s otherwise.
  graphicsPipeline(p, tessellated ? rhi::PrimitiveTopology::Patches : rhi::PrimitiveTopology::TriangleStrip, true, att, slots,
                   tempBuffer(corners, sizeof corners, "rect vertices"), tessellated ? 4 : 0);
}

namespace {
struct CheckingLink {
  bool& flag;
  explicit CheckingLink(bool& f) : flag(f) { flag = true; }
  ~CheckingLink() { flag = false; }
};
}  // namespace

ExpectResult PassSteps::linkError(const Command& c, const Pipeline& p) {
  if (!runsOpenGlGlsl(p)) {
    const std::vector<std::string>& features = dev_.info().features;
    if (std::find(features.begin(), features.end(), "openGlGlsl") == features.end()) return portLinkError(c, p);
    throw Unsupported{lineOf(c.loc) + ": link error (OpenGL's linker decides it; " + dev_.info().backend + " here runs the program's port)"};
  }
  CheckingLink checking(checkingLink_);
  makeShaders(p);  // a shader that does not compile throws: piglit fails there too
  try {
    link(p);
  } catch (const Failure& f) {
    return {c.loc.line, true, lineOf(c.loc) + ": link error: " + f.what};
  }
  return {c.loc.line, false, lineOf(c.loc) + ": link error expected, but the program links"};
}

ExpectResult PassSteps::portLinkError(const Command& c, const Pipeline& p) {
  const std::string expected = lineOf(c.loc) + ": link error";
  const std::optional<rhi::ProgramLink> linked = linkPort(p);
  if (!linked) throw Unsupported{expected + " (OpenGL's linker decides it; the program is not GLSL that glslang links)"};
  if (!linked->linkError.empty()) return {c.loc.line, true, expected + ": glslang's linker: " + oneLine(linked->linkError)};
  // A unit glslang does not compile (code it cannot port, an extension it does not know) says
  // nothing of OpenGL's link rules.
  if (!linked->compileError.empty())
    throw Unsupported{expected + " (OpenGL's linker decides it; glslang cannot port the program: " + oneLine(linked->compileError) + ")"};
  for (const std::string& n : p.shaders)
    if (linkOnlyPorts_.count(n)) throw Unsupported{expected + " (OpenGL's linker decides it; " + declarationPorts_.at(n) + ")"};
  CheckingLink checking(checkingLink_);
  try {
    makeShaders(p);
    link(p);
  } catch (const Failure& f) {
    // Once glslang has linked the stages (a block of one name matches across them), what the RHI's
    // validation refuses (E_PIPELINE_ARRAY_SIZE, E_PIPELINE_BINDING_CONFLICT) is about bindings the
    // port placed, where OpenGL lets different blocks and samplers share a binding point.
    throw Unsupported{expected + " (OpenGL's linker decides it; glslang links the port, and the RHI refuses its pipeline: " + f.what + ")"};
  }
  throw Unsupported{expected + " (the port links and its pipeline is created: OpenGL's rule has no check on " + dev_.info().backend + ")"};
}

void PassSteps::compute(const Command& c, const Pipeline& p) {
  const rhi::ComputePipelineHandle h = computePipeline(p);
  useSamplerStates(c.samplerStates);
  convertSnormTexelBuffers(p);
  dev_.setComputePipeline(h);
  bindResources(p, pushConstantBytes(p));
  dev_.dispatch(c.groups[0], c.groups[1], c.groups[2]);
}

void PassSteps::clearPass(const Pipeline& p) {
  Attachments att = attachments(p, rhi::LoadOp::Clear, clear_[p.name]);
  dev_.beginPass(att.pass);
  dev_.endPass();
}

}  // namespace parity::harness::script::runner
