// GL backend: pipelines. A graphics pipeline is a linked program plus a vertex array object
// holding its vertex layout; its fixed-function state is applied at draw time
// (applyRenderState in gl_commands.cpp). A compute pipeline is a linked program.
#include <algorithm>
#include <string_view>

#include "rhi/gl/gl_device.h"

namespace parity::rhi::gl {

namespace {

struct GlVertexFormat {
  GLint components;
  GLenum type;
  bool normalised;
  bool integer;  // read as ivec/uvec (glVertexArrayAttribIFormat)
  bool doubles = false;  // read as double/dvec (glVertexArrayAttribLFormat)
};

GlVertexFormat glVertexFormat(VertexFormat f) {
  switch (f) {
    case VertexFormat::Float: return {1, GL_FLOAT, false, false};
    case VertexFormat::Float2: return {2, GL_FLOAT, false, false};
    case VertexFormat::Float3: return {3, GL_FLOAT, false, false};
    case VertexFormat::Float4: return {4, GL_FLOAT, false, false};
    case VertexFormat::UByte4Norm: return {4, GL_UNSIGNED_BYTE, true, false};
    case VertexFormat::UInt: return {1, GL_UNSIGNED_INT, false, true};
    case VertexFormat::UInt2: return {2, GL_UNSIGNED_INT, false, true};
    case VertexFormat::UInt4: return {4, GL_UNSIGNED_INT, false, true};
    case VertexFormat::UInt3: return {3, GL_UNSIGNED_INT, false, true};
    case VertexFormat::Int: return {1, GL_INT, false, true};
    case VertexFormat::Int2: return {2, GL_INT, false, true};
    case VertexFormat::Int3: return {3, GL_INT, false, true};
    case VertexFormat::Int4: return {4, GL_INT, false, true};
    case VertexFormat::Double: return {1, GL_DOUBLE, false, false, true};
    case VertexFormat::Double2: return {2, GL_DOUBLE, false, false, true};
    case VertexFormat::Double3: return {3, GL_DOUBLE, false, false, true};
    case VertexFormat::Double4: return {4, GL_DOUBLE, false, false, true};
  }
  return {4, GL_FLOAT, false, false};
}

}  // namespace

// SPIRV-Cross's GLSL keeps each input's first location.
uint32_t openGlAttributeLocation(const ShaderReflection& vs, uint32_t location) {
  for (const auto& [first, vectors] : vs.doubleWideInputs)
    if (location >= first && location < first + 2 * vectors) return first + (location - first) / 2;
  return location;
}

std::string GlDevice::programInfoLog(GLuint program) {
  GLint length = 0;
  gl.GetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::string infoLog(static_cast<size_t>(std::max(length, 1)), '\0');
  gl.GetProgramInfoLog(program, length, nullptr, infoLog.data());
  return infoLog.c_str();
}

GLuint GlDevice::linkShaders(const std::vector<GLuint>& names, std::string* error) {
  const GLuint program = gl.CreateProgram();
  for (GLuint s : names) gl.AttachShader(program, s);
  gl.LinkProgram(program);
  for (GLuint s : names) gl.DetachShader(program, s);
  GLint ok = GL_FALSE;
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok) return program;
  *error = "program does not link:\n" + programInfoLog(program);
  gl.DeleteProgram(program);
  return 0;
}

// The shaders' GLSL objects link; where one has none or they do not link, the program is linked
// from the modules themselves through GL_ARB_gl_spirv (the two kinds do not link together).
bool GlDevice::linkProgram(const std::vector<const GlShader*>& shaders, const std::string& label_,
                           GlProgram* out, bool separable) {
  const std::string what = label_.empty() ? std::string("pipeline") : label_;
  if (std::any_of(shaders.begin(), shaders.end(), [](const GlShader* s) { return s->arbProgram != 0; }))
    return placeArbPrograms(shaders, label_, out);
  const auto openGl = std::count_if(shaders.begin(), shaders.end(), [](const GlShader* s) { return !s->openGlUnits.empty(); });
  if (openGl != 0 && static_cast<size_t>(openGl) != shaders.size()) {
    log(what + ": stages from OpenGL GLSL (ShaderDesc::openGlGlsl) cannot link with stages from SPIR-V only");
    return false;
  }
  bool fromSpirv = std::any_of(shaders.begin(), shaders.end(), [](const GlShader* s) { return s->name == 0; });
  std::string glslError;
  GLuint program = 0;
  if (openGl != 0) {
    program = linkOpenGlGlsl(shaders, &glslError, separable);
    if (program == 0) {
      notes_.push_back(what + ": " + glslError);  // the program's own error (Device::takeNotes)
      return false;
    }
  } else if (!fromSpirv) {
    std::vector<GLuint> names;
    for (const GlShader* s : shaders) names.push_back(s->name);
    program = linkShaders(names, &glslError);
  }
  if (program == 0) {
    if (!std::all_of(shaders.begin(), shaders.end(), [&](const GlShader* s) { return takesSpirv(*s); })) {
      log(what + ": " + (fromSpirv ? "a stage that only GL_ARB_gl_spirv takes cannot link with stages it cannot take"
                                   : glslError));
      return false;
    }
    std::vector<GLuint> names, compiledHere;
    std::string spirvError;
    for (const GlShader* s : shaders) {
      GLuint name = s->spirvName;
      if (name == 0 && (name = compileSpirv(*s, &spirvError)) == 0) break;
      if (s->spirvName == 0) compiledHere.push_back(name);
      names.push_back(name);
    }
    if (names.size() == shaders.size()) program = linkShaders(names, &spirvError);
    for (GLuint name : compiledHere) gl.DeleteShader(name);
    if (program == 0) {
      log(what + ": " + (glslError.empty() ? std::string() : glslError + "\n--- and through GL_ARB_gl_spirv: ") + spirvError);
      return false;
    }
    if (!glslError.empty()) notes_.push_back(what + ": ran through GL_ARB_gl_spirv instead of SPIRV-Cross's GLSL: " + glslError);
    fromSpirv = true;
  }
  label(GL_PROGRAM, program, label_);

  out->name = program;
  out->resources.clear();
  out->pushConstantSize = 0;
  out->pushConstantsInUniformBlock = out->pushConstantsInStorageBlock = false;
  for (const GlShader* s : shaders) {
    for (const ShaderResource& r : s->reflection.resources) {
      const bool known = std::any_of(out->resources.begin(), out->resources.end(),
                                     [&](const ShaderResource& e) { return e.binding == r.binding; });
      if (!known) out->resources.push_back(r);
    }
    out->pushConstantSize = std::max(out->pushConstantSize, s->reflection.pushConstantSize);
    if (s->reflection.pushConstantSize > 0) {  // the SPIR-V path has it as a uniform block (gl_shader.cpp)
      out->pushConstantsInStorageBlock |= !fromSpirv && s->pushConstantsInStorageBlock;
      out->pushConstantsInUniformBlock |= fromSpirv || !s->pushConstantsInStorageBlock;
    }
  }
  for (const GlShader* s : shaders) out->readsBaseVertex |= s->reflection.readsBaseVertex;
  // Each stage's clip distances feed the next; the last stage before rasterisation's are used.
  for (ShaderStage last : {ShaderStage::Geometry, ShaderStage::TessEvaluation, ShaderStage::Vertex}) {
    auto s = std::find_if(shaders.begin(), shaders.end(), [&](const GlShader* x) { return x->stage == last; });
    if (s == shaders.end()) continue;
    out->clipDistances = (*s)->reflection.clipDistances;
    break;
  }
  out->points = glBindingPoints(out->resources);
  out->openGlClipSpace = false;
  out->looseUniforms.clear();
  out->baseInstanceLocation = -1;
  if (openGl != 0) {
    out->readsBaseVertex = false;  // OpenGL's gl_BaseVertex is the program's own
    placeOpenGlInterface(shaders, *out);
    return true;
  }
  if (out->points[kMaxBindings] != kMaxBindings) moveToBindingPoints(*out);  // else the GLSL's bindings are the points

  // Separate texture/sampler pairs from unit P(kMaxBindings) on, one unit per texture element (gl_device.h).
  std::vector<const ShaderReflection*> reflections;
  for (const GlShader* s : shaders) reflections.push_back(&s->reflection);
  out->separatePairs = mergeSeparatePairs(reflections);
  out->pairUnits.clear();
  uint32_t unit = out->points[kMaxBindings];
  for (const SeparatePair& pair : out->separatePairs) {
    out->pairUnits.push_back(unit);
    auto texture = std::find_if(out->resources.begin(), out->resources.end(),
                                [&](const ShaderResource& r) { return r.binding == pair.textureBinding; });
    unit += texture == out->resources.end() ? 1 : texture->arraySize;
  }
  if (!out->separatePairs.empty() && unit > static_cast<uint32_t>(maxTextureUnits_)) {
    log((label_.empty() ? std::string("pipeline") : label_) + ": " + std::to_string(out->separatePairs.size()) +
        " separate texture/sampler pairs need texture units up to " + std::to_string(unit - 1) + "; the driver has " +
        std::to_string(maxTextureUnits_));
    gl.DeleteProgram(program);
    return false;
  }
  for (size_t k = 0; k < out->separatePairs.size(); ++k) {
    const uint32_t elements = (k + 1 < out->pairUnits.size() ? out->pairUnits[k + 1] : unit) - out->pairUnits[k];
    const std::string name = combinedSamplerName(out->separatePairs[k]);
    for (uint32_t e = 0; e < elements; ++e) {
      const std::string element = elements > 1 ? name + "[" + std::to_string(e) + "]" : name;
      const GLint location = gl.GetUniformLocation(program, element.c_str());
      if (location >= 0) gl.ProgramUniform1i(program, location, static_cast<GLint>(out->pairUnits[k] + e));
    }
  }
  // gl_InstanceIndex includes the first instance in Vulkan; gl_InstanceID does not, so
  // SPIRV-Cross adds this uniform, which draws set to firstInstance.
  out->baseInstanceLocation = gl.GetUniformLocation(program, "SPIRV_Cross_BaseInstance");
  return true;
}

std::array<uint32_t, kMaxBindings + 1> glBindingPoints(const std::vector<ShaderResource>& resources) {
  std::array<uint32_t, kMaxBindings + 1> points{};
  uint32_t shift = 0;
  for (uint32_t b = 0; b <= kMaxBindings; ++b) {
    points[b] = b + shift;
    for (const ShaderResource& r : resources)
      if (r.binding == b) shift += r.arraySize - 1;
  }
  return points;
}

// The GLSL declares binding b's array at points b .. b + N - 1 (SPIRV-Cross keeps the SPIR-V
// binding) and the push-constant block at kGlPushConstantBinding; once an array lies below other
// bindings those overlap, so every block, sampler and image moves to its point P(b) + e here.
// Blocks are found by the point their GLSL declares (element e of an array of blocks is named
// "Block[e]" and declares b + e), samplers and images by name (glResourceName).
void GlDevice::moveToBindingPoints(const GlProgram& p) {
  for (GLenum interface : {GL_UNIFORM_BLOCK, GL_SHADER_STORAGE_BLOCK}) {
    GLint count = 0;
    gl.GetProgramInterfaceiv(p.name, interface, GL_ACTIVE_RESOURCES, &count);
    for (GLint i = 0; i < count; ++i) {
      char name[256] = {};
      gl.GetProgramResourceName(p.name, interface, static_cast<GLuint>(i), sizeof name, nullptr, name);
      const GLenum property = GL_BUFFER_BINDING;
      GLint declared = 0;
      gl.GetProgramResourceiv(p.name, interface, static_cast<GLuint>(i), 1, &property, 1, nullptr, &declared);
      const std::string_view n = name;
      uint32_t element = 0;
      if (!n.empty() && n.back() == ']' && n.rfind('[') != std::string_view::npos)
        element = static_cast<uint32_t>(std::stoul(std::string(n.substr(n.rfind('[') + 1))));
      const uint32_t binding = static_cast<uint32_t>(declared) - element;
      if (declared < 0 || binding > kMaxBindings) continue;
      const GLuint point = p.points[binding] + element;
      if (interface == GL_UNIFORM_BLOCK)
        gl.UniformBlockBinding(p.name, static_cast<GLuint>(i), point);
      else
        gl.ShaderStorageBlockBinding(p.name, static_cast<GLuint>(i), point);
    }
  }
  for (const ShaderResource& r : p.resources) {
    if (r.kind != BindingKind::SampledTexture && r.kind != BindingKind::StorageTexture &&
        r.kind != BindingKind::UniformTexelBuffer && r.kind != BindingKind::StorageTexelBuffer)
      continue;
    for (uint32_t e = 0; e < r.arraySize; ++e) {
      const std::string name = glResourceName(r.binding) + (r.arraySize > 1 ? "[" + std::to_string(e) + "]" : "");
      const GLint location = gl.GetUniformLocation(p.name, name.c_str());
      if (location >= 0) gl.ProgramUniform1i(p.name, location, static_cast<GLint>(p.points[r.binding] + e));
    }
  }
}

PipelineHandle GlDevice::createPipeline(const PipelineDesc& desc) {
  const GlShader* vs = shaders_.get(desc.vertexShader);
  const GlShader* fs = shaders_.get(desc.fragmentShader);
  if (!vs || !fs) return {};
  GlPipeline pipeline;
  pipeline.desc = desc;
  std::vector<const GlShader*> stages{vs};
  for (ShaderHandle optional : {desc.tessControlShader, desc.tessEvaluationShader, desc.geometryShader})
    if (const GlShader* s = shaders_.get(optional)) stages.push_back(s);
  stages.push_back(fs);
  if (!linkProgram(stages, desc.label, &pipeline.program, desc.separablePrograms)) return {};

  gl.CreateVertexArrays(1, &pipeline.vao);
  for (uint32_t i = 0; i < desc.attributeCount && i < kMaxVertexAttributes; ++i) {
    const VertexAttribute& a = desc.attributes[i];
    const GlVertexFormat f = glVertexFormat(a.format);
    const auto placed = pipeline.program.attributeLocations.find(a.location);  // a program from OpenGL GLSL
    const GLuint location = placed != pipeline.program.attributeLocations.end() ? placed->second
                                                                             : openGlAttributeLocation(vs->reflection, a.location);
    gl.EnableVertexArrayAttrib(pipeline.vao, location);
    if (f.doubles)
      gl.VertexArrayAttribLFormat(pipeline.vao, location, f.components, f.type, a.offset);
    else if (f.integer)
      gl.VertexArrayAttribIFormat(pipeline.vao, location, f.components, f.type, a.offset);
    else
      gl.VertexArrayAttribFormat(pipeline.vao, location, f.components, f.type, f.normalised ? GL_TRUE : GL_FALSE, a.offset);
    gl.VertexArrayAttribBinding(pipeline.vao, location, a.bufferSlot);
  }
  for (uint32_t slot = 0; slot < kMaxVertexBuffers; ++slot)
    gl.VertexArrayBindingDivisor(pipeline.vao, slot, desc.vertexBuffers[slot].perInstance ? 1 : 0);
  label(GL_VERTEX_ARRAY, pipeline.vao, desc.label);
  return pipelines_.add(std::move(pipeline));
}

ComputePipelineHandle GlDevice::createComputePipeline(const ComputePipelineDesc& desc) {
  const GlShader* cs = shaders_.get(desc.computeShader);
  if (!cs) return {};
  GlComputePipeline pipeline;
  pipeline.desc = desc;
  if (!linkProgram({cs}, desc.label, &pipeline.program)) return {};
  return computePipelines_.add(std::move(pipeline));
}

void GlDevice::destroy(PipelineHandle h) {
  std::optional<GlPipeline> pipeline = pipelines_.remove(h);
  if (!pipeline) return;
  gl.DeleteProgram(pipeline->program.name);
  for (const GlProgram::RepackedBlock& b : pipeline->program.repackedBlocks) gl.DeleteBuffers(1, &b.shadow);
  gl.DeleteVertexArrays(1, &pipeline->vao);
  if (pipeline_ == h) pipeline_ = {};
}

void GlDevice::destroy(ComputePipelineHandle h) {
  std::optional<GlComputePipeline> pipeline = computePipelines_.remove(h);
  if (!pipeline) return;
  gl.DeleteProgram(pipeline->program.name);
  for (const GlProgram::RepackedBlock& b : pipeline->program.repackedBlocks) gl.DeleteBuffers(1, &b.shadow);
  if (computePipeline_ == h) computePipeline_ = {};
}

}  // namespace parity::rhi::gl
