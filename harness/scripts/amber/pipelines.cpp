// AmberScript pipelines: PIPELINE and DERIVE_PIPELINE with their bodies (ATTACH, BIND, VERTEX_DATA, INDEX_DATA, DEPTH, STENCIL, BLEND, ...).
#include "harness/scripts/amber/statements.h"

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>

namespace parity::harness::script::amber {

void PipelineStatements::pipelineBody(Pipeline& p, const Token& start) {
  while (true) {
    Token w = next();
    if (!w.valid()) error(start, "missing END for PIPELINE '" + p.name + "'");
    const std::string& k = w.text;
    if (k == "END") break;
    if (k == "ATTACH") {
      Token s = nextSameLine("shader name");
      const Shader* sh = script_.findShader(s.text);
      if (!sh) error(s, "unknown shader '" + s.text + "'");
      if (p.compute != (sh->stage == Stage::Compute))
        error(s, "shader '" + s.text + "' does not fit a " + std::string(p.compute ? "compute" : "graphics") + " pipeline");
      p.shaders.push_back(s.text);
      while (true) {
        Token o = peekSameLine();
        if (!o.valid()) break;
        next();
        if (o.text == "ENTRY_POINT") p.entryPoints[s.text] = nextSameLine("entry point").text;
        else if (o.text == "TYPE") {
          nextSameLine("stage");
          if (peekSameLine().valid() && peekSameLine().text == "ENTRY_POINT") continue;
        } else if (o.text == "SPECIALIZE") {
          // SPECIALIZE id AS uint32|int32|float value: the constant's 32 bits.
          uint32_t id = uintSameLine("specialization constant id");
          Token as = nextSameLine("AS");
          if (as.text != "AS") error(as, "expected AS, got '" + as.text + "'");
          Token type = nextSameLine("type (uint32, int32, float)");
          Token value = nextSameLine("value");
          uint32_t bits = 0;
          if (type.text == "uint32") {
            bits = uintToken(value);
          } else if (type.text == "int32") {
            char* end = nullptr;
            errno = 0;
            long long v = std::strtoll(value.text.c_str(), &end, 0);
            if (value.text.empty() || *end || errno || v < INT32_MIN || v > INT32_MAX)
              error(value, "expected a 32-bit integer, got '" + value.text + "'");
            bits = static_cast<uint32_t>(static_cast<int32_t>(v));
          } else if (type.text == "float") {
            float f = static_cast<float>(numberToken(value));
            std::memcpy(&bits, &f, 4);
          } else {
            error(type, "unknown SPECIALIZE type '" + type.text + "' (uint32, int32, float)");
          }
          p.specializations[s.text][id] = bits;
        } else error(o, "unexpected '" + o.text + "' after ATTACH");
      }
    } else if (k == "FRAMEBUFFER_SIZE") {
      p.fbWidth = dimensionSameLine(w, "width");
      p.fbHeight = dimensionSameLine(w, "height");
      expectEndOfLine();
    } else if (k == "BIND") {
      bind(p, w);
    } else if (k == "VERTEX_DATA") {
      VertexData v;
      v.loc = {w.line, w.col};
      Token b = nextSameLine("buffer name");
      if (!script_.findBuffer(b.text)) error(b, "unknown buffer '" + b.text + "'");
      v.buffer = b.text;
      expectWord("LOCATION");
      v.location = uintSameLine("location");
      while (true) {
        Token o = peekSameLine();
        if (!o.valid()) break;
        next();
        if (o.text == "RATE") v.perInstance = lower(nextSameLine("vertex or instance").text) == "instance";
        else if (o.text == "OFFSET") v.offset = uintSameLine("offset");
        else if (o.text == "STRIDE") v.stride = uintSameLine("stride");
        else if (o.text == "FORMAT") v.format = nextSameLine("format").text;
        else error(o, "unexpected '" + o.text + "' in VERTEX_DATA");
      }
      p.vertexData.push_back(v);
    } else if (k == "INDEX_DATA") {
      Token b = nextSameLine("buffer name");
      if (!script_.findBuffer(b.text)) error(b, "unknown buffer '" + b.text + "'");
      p.indexData = b.text;
      expectEndOfLine();
    } else if (k == "DEPTH") {
      depthBlock(p, w);
    } else if (k == "STENCIL") {
      stencilBlock(p, w);
    } else if (k == "BLEND") {
      blendBlock(p, w);
    } else if (k == "CULL_MODE") {
      p.cullMode = lower(nextSameLine("cull mode").text);
      if (p.cullMode == "front_and_back") unsupported(w, "CULL_MODE front_and_back");
    } else if (k == "FRONT_FACE") {
      p.frontFace = lower(nextSameLine("front face").text);
    } else if (k == "VIEWPORT") {
      std::array<float, 4> vp{};
      vp[0] = static_cast<float>(numberSameLine("x"));
      vp[1] = static_cast<float>(numberSameLine("y"));
      expectWord("SIZE");
      vp[2] = static_cast<float>(numberSameLine("width"));
      vp[3] = static_cast<float>(numberSameLine("height"));
      while (peekSameLine().valid()) {
        Token o = next();
        if (o.text == "MIN_DEPTH") p.viewportDepth[0] = static_cast<float>(numberSameLine("min depth"));
        else if (o.text == "MAX_DEPTH") p.viewportDepth[1] = static_cast<float>(numberSameLine("max depth"));
        else error(o, "unexpected '" + o.text + "' in VIEWPORT");
      }
      p.viewport = vp;
    } else if (k == "SET") {  // SET KERNEL ARG_NAME|ARG_NUMBER a AS type value (OpenCL)
      Token kernel = nextSameLine("KERNEL");
      if (kernel.text != "KERNEL") error(kernel, "expected KERNEL, got '" + kernel.text + "'");
      unsupported(w, "SET KERNEL (OpenCL kernel arguments)");
      skipLine();
    } else if (k == "POLYGON_MODE") {
      Token m = nextSameLine("fill, line or point");
      if (m.text != "fill" && m.text != "line" && m.text != "point")
        error(m, "unknown POLYGON_MODE '" + m.text + "' (fill, line or point)");
      p.polygonMode = m.text;
      expectEndOfLine();
    } else if (k == "PATCH_CONTROL_POINTS") {
      p.patchControlPoints = uintSameLine("control points");
      expectEndOfLine();
    } else if (k == "SHADER_OPTIMIZATION") {
      Token s = nextSameLine("shader name");
      if (!script_.findShader(s.text)) error(s, "unknown shader '" + s.text + "'");
      expectEndOfLine();
      std::vector<std::string>& passes = p.optimizations[s.text];
      passes.clear();  // DERIVE_PIPELINE: the derived block replaces the parent's
      while (true) {
        Token o = next();
        if (!o.valid()) error(w, "missing END for SHADER_OPTIMIZATION");
        if (o.text == "END") break;
        passes.push_back(o.text);
      }
    } else if (k == "SUBGROUP") {
      subgroup(p, w);
    } else if (k == "COMPILE_OPTIONS" || k == "LINE_WIDTH") {
      unsupported(w, k);
      if (k == "COMPILE_OPTIONS") skipBlock(w);
      else skipLine();
    } else {
      error(w, "unexpected '" + k + "' in PIPELINE");
    }
  }
}

// SUBGROUP shader / FULLY_POPULATED on|off / VARYING_SIZE on|off / REQUIRED_SIZE n|MIN|MAX / END
void PipelineStatements::subgroup(Pipeline& p, const Token& w) {
  Token s = nextSameLine("shader name");
  if (!script_.findShader(s.text)) error(s, "unknown shader '" + s.text + "'");
  expectEndOfLine();
  SubgroupControl& control = p.subgroups[s.text];
  while (true) {
    Token o = next();
    if (!o.valid()) error(w, "missing END for SUBGROUP");
    if (o.text == "END") break;
    if (o.text == "FULLY_POPULATED" || o.text == "VARYING_SIZE") {
      Token v = nextSameLine("on or off");
      if (lower(v.text) != "on" && lower(v.text) != "off") error(v, o.text + " takes on or off, got '" + v.text + "'");
      (o.text == "FULLY_POPULATED" ? control.fullyPopulated : control.varyingSize) = onOff(v.text);
    } else if (o.text == "REQUIRED_SIZE") {
      Token v = nextSameLine("a subgroup size, MIN or MAX");
      if (v.text == "MIN" || v.text == "MAX") control.requiredSize = v.text;
      else control.requiredSize = std::to_string(uintToken(v));
    } else {
      error(o, "unexpected '" + o.text + "' in SUBGROUP (FULLY_POPULATED, VARYING_SIZE, REQUIRED_SIZE or END)");
    }
    expectEndOfLine();
  }
}

void PipelineStatements::bind(Pipeline& p, const Token& w) {
  Bind b;
  b.loc = {w.line, w.col};
  std::vector<std::string> elements;   // per element of BUFFER_ARRAY / SAMPLER_ARRAY (BUFFER: one)
  std::vector<uint64_t> offsets, ranges;  // per element, as many as given
  // OFFSET, DESCRIPTOR_OFFSET and DESCRIPTOR_RANGE take one value per element.
  auto perElement = [&](std::vector<uint64_t>& into, const char* what) {
    const size_t n = std::max<size_t>(elements.size(), 1);
    into.resize(std::max(into.size(), n), 0);
    for (size_t i = 0; i < n; ++i) into[i] += uintSameLine(what);
  };
  Token what = nextSameLine("BUFFER or SAMPLER");
  if (what.text == "SAMPLER") {
    Token s = nextSameLine("sampler name");
    if (!script_.findSampler(s.text)) error(s, "unknown sampler '" + s.text + "'");
    b.kind = BindKind::Sampler;
    b.buffer = s.text;
    if (peekSameLine().valid() && peekSameLine().text == "KERNEL") {
      Token kernel = next();
      unsupported(kernel, "BIND SAMPLER ... KERNEL (OpenCL kernel arguments)");
      return skipLine();
    }
  } else if (what.text == "SAMPLER_ARRAY") {  // BIND SAMPLER_ARRAY s0 s1 ... DESCRIPTOR_SET d BINDING b
    b.kind = BindKind::Sampler;
    while (peekSameLine().valid() && peekSameLine().text != "DESCRIPTOR_SET" && peekSameLine().text != "BINDING") {
      Token s = next();
      if (!script_.findSampler(s.text)) error(s, "unknown sampler '" + s.text + "'");
      elements.push_back(s.text);
    }
    if (elements.empty()) error(what, "SAMPLER_ARRAY without samplers");
  } else if (what.text == "BUFFER" || what.text == "BUFFER_ARRAY") {
    // BUFFER_ARRAY: the buffers of a descriptor array's elements, in order, up to AS.
    do {
      Token n = nextSameLine("buffer name");
      if (!script_.findBuffer(n.text)) error(n, "unknown buffer '" + n.text + "'");
      elements.push_back(n.text);
    } while (what.text == "BUFFER_ARRAY" && peekSameLine().valid() && peekSameLine().text != "AS");
    b.buffer = elements[0];
    if (peekSameLine().valid() && peekSameLine().text == "KERNEL") {  // OpenCL: KERNEL ARG_NAME a | ARG_NUMBER n
      Token kernel = next();
      Token how = nextSameLine("ARG_NAME or ARG_NUMBER");
      if (how.text != "ARG_NAME" && how.text != "ARG_NUMBER") error(how, "expected ARG_NAME or ARG_NUMBER, got '" + how.text + "'");
      nextSameLine("kernel argument");
      unsupported(kernel, "BIND BUFFER ... KERNEL " + how.text + " (OpenCL kernel arguments)");
      return skipLine();
    }
    expectWord("AS");
    Token as = nextSameLine("binding type");
    b.asWord = as.text;
    static const std::map<std::string, BindKind> kKinds = {
        {"color", BindKind::Color}, {"depth_stencil", BindKind::DepthStencil}, {"resolve", BindKind::Resolve},
        {"storage", BindKind::Storage}, {"uniform", BindKind::Uniform},
        {"combined_image_sampler", BindKind::CombinedImageSampler}, {"sampled_image", BindKind::SampledImage},
        {"storage_image", BindKind::StorageImage}, {"push_constant", BindKind::PushConstant}};
    auto it = kKinds.find(as.text);
    if (it != kKinds.end()) {
      b.kind = it->second;
    } else if (as.text == "storage_dynamic" || as.text == "uniform_dynamic") {
      b.kind = as.text == "storage_dynamic" ? BindKind::Storage : BindKind::Uniform;
    } else if (as.text == "uniform_texel_buffer" || as.text == "storage_texel_buffer") {
      b.kind = as.text == "uniform_texel_buffer" ? BindKind::UniformTexelBuffer : BindKind::StorageTexelBuffer;
    } else {
      error(as, "unknown binding type '" + as.text + "'");
    }
  } else {
    error(what, "expected BUFFER or SAMPLER after BIND, got '" + what.text + "'");
  }
  while (true) {
    Token o = peekSameLine();
    if (!o.valid()) break;
    next();
    if (o.text == "LOCATION") b.location = uintSameLine("location");
    else if (o.text == "DESCRIPTOR_SET") b.set = uintSameLine("descriptor set");
    else if (o.text == "BINDING") b.binding = uintSameLine("binding");
    else if (o.text == "SAMPLER") {
      Token s = nextSameLine("sampler name");
      if (!script_.findSampler(s.text)) error(s, "unknown sampler '" + s.text + "'");
      b.sampler = s.text;
    } else if (o.text == "BASE_MIP_LEVEL") {
      b.baseMipLevel = uintSameLine("mip level");
      // Colour attachments render to that level; sampled and storage images bind it and up.
      if (b.baseMipLevel && b.kind != BindKind::Color && b.kind != BindKind::CombinedImageSampler &&
          b.kind != BindKind::SampledImage && b.kind != BindKind::StorageImage)
        unsupported(o, "BASE_MIP_LEVEL on " + b.asWord);
    } else if (o.text == "DESCRIPTOR_OFFSET" || o.text == "OFFSET") {
      // Both add up to the start of the bound range (a dynamic offset is applied on top of
      // the descriptor's own); VK_WHOLE_SIZE and "to the end" are the default range.
      perElement(offsets, "offset");
      if (b.kind != BindKind::Storage && b.kind != BindKind::Uniform && b.kind != BindKind::UniformTexelBuffer &&
          b.kind != BindKind::StorageTexelBuffer)
        error(o, o.text + " applies to storage and uniform buffers");
    } else if (o.text == "DESCRIPTOR_RANGE") {
      ranges.clear();
      perElement(ranges, "range");
      if (b.kind != BindKind::Storage && b.kind != BindKind::Uniform && b.kind != BindKind::UniformTexelBuffer &&
          b.kind != BindKind::StorageTexelBuffer)
        error(o, o.text + " applies to storage and uniform buffers");
    } else error(o, "unexpected '" + o.text + "' in BIND");
  }
  if (elements.empty()) elements.push_back(b.buffer);  // BIND SAMPLER
  for (size_t i = 0; i < elements.size(); ++i) {
    Bind element = b;
    element.buffer = elements[i];
    element.arrayElement = static_cast<uint32_t>(i);
    if (i < offsets.size()) element.offset = offsets[i];
    if (i < ranges.size()) element.range = ranges[i];
    addBind(p, element);
  }
}

void PipelineStatements::addBind(Pipeline& p, const Bind& b) {
  for (auto& e : p.binds)
    if (e.kind == b.kind && (b.kind == BindKind::Color ? e.location == b.location
                            : b.kind == BindKind::DepthStencil || b.kind == BindKind::Resolve || b.kind == BindKind::PushConstant
                                ? true
                                : e.set == b.set && e.binding == b.binding && e.arrayElement == b.arrayElement)) {
      e = b;  // DERIVE_PIPELINE rebinding replaces
      return;
    }
  p.binds.push_back(b);
}

void PipelineStatements::depthBlock(Pipeline& p, const Token& start) {
  while (true) {
    Token w = next();
    if (!w.valid()) error(start, "missing END for DEPTH");
    if (w.text == "END") return;
    if (w.text == "TEST") p.depthTest = onOff(nextSameLine("on/off").text);
    else if (w.text == "WRITE") p.depthWrite = onOff(nextSameLine("on/off").text);
    else if (w.text == "COMPARE_OP") p.depthCompare = lower(nextSameLine("compare op").text);
    else if (w.text == "CLAMP") {
      p.depthClamp = onOff(nextSameLine("on/off").text);
    } else if (w.text == "BOUNDS") {
      expectWord("min");
      double mn = numberSameLine("min");
      expectWord("max");
      double mx = numberSameLine("max");
      if (mn != 0.0 || mx != 1.0) unsupported(w, "DEPTH BOUNDS");
    } else if (w.text == "BIAS") {  // Amber: BIAS constant c clamp k slope s, in this order
      for (auto [word, value] : {std::pair{"constant", &p.depthBiasConstant}, std::pair{"clamp", &p.depthBiasClamp},
                                 std::pair{"slope", &p.depthBiasSlope}}) {
        expectWord(word);
        *value = static_cast<float>(numberSameLine(word));
      }
    } else error(w, "unexpected '" + w.text + "' in DEPTH");
  }
}

void PipelineStatements::stencilBlock(Pipeline& p, const Token& start) {
  Token face = nextSameLine("front, back or front_and_back");
  bool front = face.text == "front" || face.text == "front_and_back";
  bool back = face.text == "back" || face.text == "front_and_back";
  if (!front && !back) error(face, "expected front, back or front_and_back");
  StencilFace s = front ? p.front : p.back;
  while (true) {
    Token w = next();
    if (!w.valid()) error(start, "missing END for STENCIL");
    if (w.text == "END") break;
    if (w.text == "TEST") s.test = onOff(nextSameLine("on/off").text);
    else if (w.text == "FAIL_OP") s.failOp = lower(nextSameLine("op").text);
    else if (w.text == "PASS_OP") s.passOp = lower(nextSameLine("op").text);
    else if (w.text == "DEPTH_FAIL_OP") s.depthFailOp = lower(nextSameLine("op").text);
    else if (w.text == "COMPARE_OP") s.compareOp = lower(nextSameLine("op").text);
    else if (w.text == "COMPARE_MASK") s.compareMask = uintSameLine("mask");
    else if (w.text == "WRITE_MASK") s.writeMask = uintSameLine("mask");
    else if (w.text == "REFERENCE") s.reference = uintSameLine("reference");
    else error(w, "unexpected '" + w.text + "' in STENCIL");
  }
  if (front) p.front = s;
  if (back) p.back = s;
}

void PipelineStatements::blendBlock(Pipeline& p, const Token& start) {
  p.blend.enabled = true;
  while (true) {
    Token w = next();
    if (!w.valid()) error(start, "missing END for BLEND");
    if (w.text == "END") return;
    if (w.text == "CONSTANT") {  // ours: the blend constant colour, four floats 0..1
      for (int i = 0; i < 4; ++i) p.blend.constant[i] = static_cast<float>(numberSameLine("blend constant component"));
      expectEndOfLine();
      continue;
    }
    std::string v = lower(nextSameLine("value").text);
    if (w.text == "SRC_COLOR_FACTOR") p.blend.srcColor = v;
    else if (w.text == "DST_COLOR_FACTOR") p.blend.dstColor = v;
    else if (w.text == "COLOR_OP") p.blend.colorOp = v;
    else if (w.text == "SRC_ALPHA_FACTOR") p.blend.srcAlpha = v;
    else if (w.text == "DST_ALPHA_FACTOR") p.blend.dstAlpha = v;
    else if (w.text == "ALPHA_OP") p.blend.alphaOp = v;
    else error(w, "unexpected '" + w.text + "' in BLEND");
  }
}

void PipelineStatements::pipeline(const Token& t) {
  Pipeline p;
  p.loc = {t.line, t.col};
  Token kind = nextSameLine("graphics or compute");
  if (kind.text == "compute") p.compute = true;
  else if (kind.text != "graphics") error(kind, "expected graphics or compute, got '" + kind.text + "'");
  Token name = nextSameLine("pipeline name");
  if (script_.findPipeline(name.text)) error(name, "duplicate pipeline name '" + name.text + "'");
  p.name = name.text;
  expectEndOfLine();
  pipelineBody(p, t);
  script_.pipelines.push_back(p);
}

void PipelineStatements::derivePipeline(const Token& t) {
  Token name = nextSameLine("pipeline name");
  expectWord("FROM");
  Token parent = nextSameLine("parent pipeline name");
  const Pipeline* base = script_.findPipeline(parent.text);
  if (!base) error(parent, "unknown pipeline '" + parent.text + "'");
  if (script_.findPipeline(name.text)) error(name, "duplicate pipeline name '" + name.text + "'");
  Pipeline p = *base;
  p.name = name.text;
  p.loc = {t.line, t.col};
  expectEndOfLine();
  pipelineBody(p, t);
  script_.pipelines.push_back(p);
}

}  // namespace parity::harness::script::amber
