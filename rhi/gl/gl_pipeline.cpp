// GL backend: pipelines. A graphics pipeline is a linked program plus a vertex array object
// holding its vertex layout; its fixed-function state is applied at draw time
// (applyRenderState in gl_commands.cpp). A compute pipeline is a linked program.
#include <algorithm>

#include "rhi/gl/gl_device.h"

namespace parity::rhi::gl {

namespace {

struct GlVertexFormat {
  GLint components;
  GLenum type;
  bool normalised;
  bool integer;  // read as ivec/uvec (glVertexArrayAttribIFormat)
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
  }
  return {4, GL_FLOAT, false, false};
}

}  // namespace

bool GlDevice::linkProgram(const std::vector<const GlShader*>& shaders, const std::string& label_,
                           GlProgram* out) {
  const GLuint program = gl.CreateProgram();
  for (const GlShader* s : shaders) gl.AttachShader(program, s->name);
  gl.LinkProgram(program);
  for (const GlShader* s : shaders) gl.DetachShader(program, s->name);
  GLint ok = GL_FALSE;
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    gl.GetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string infoLog(static_cast<size_t>(std::max(length, 1)), '\0');
    gl.GetProgramInfoLog(program, length, nullptr, infoLog.data());
    log((label_.empty() ? std::string("pipeline") : label_) + ": program does not link:\n" + infoLog.c_str());
    gl.DeleteProgram(program);
    return false;
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
    if (s->reflection.pushConstantSize > 0) {
      out->pushConstantsInStorageBlock |= s->pushConstantsInStorageBlock;
      out->pushConstantsInUniformBlock |= !s->pushConstantsInStorageBlock;
    }
  }
  // Separate texture/sampler pairs: pair k samples through unit kGlFirstPairUnit + k (gl_device.h).
  std::vector<const ShaderReflection*> reflections;
  for (const GlShader* s : shaders) reflections.push_back(&s->reflection);
  out->separatePairs = mergeSeparatePairs(reflections);
  if (!out->separatePairs.empty() &&
      kGlFirstPairUnit + out->separatePairs.size() > static_cast<size_t>(maxTextureUnits_)) {
    log((label_.empty() ? std::string("pipeline") : label_) + ": " + std::to_string(out->separatePairs.size()) +
        " separate texture/sampler pairs need texture units up to " +
        std::to_string(kGlFirstPairUnit + out->separatePairs.size() - 1) + "; the driver has " +
        std::to_string(maxTextureUnits_));
    gl.DeleteProgram(program);
    return false;
  }
  for (size_t k = 0; k < out->separatePairs.size(); ++k) {
    const GLint location = gl.GetUniformLocation(program, combinedSamplerName(out->separatePairs[k]).c_str());
    if (location >= 0) gl.ProgramUniform1i(program, location, static_cast<GLint>(kGlFirstPairUnit + k));
  }
  // gl_InstanceIndex includes the first instance in Vulkan; gl_InstanceID does not, so
  // SPIRV-Cross adds this uniform, which draws set to firstInstance.
  out->baseInstanceLocation = gl.GetUniformLocation(program, "SPIRV_Cross_BaseInstance");
  return true;
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
  if (!linkProgram(stages, desc.label, &pipeline.program)) return {};

  gl.CreateVertexArrays(1, &pipeline.vao);
  for (uint32_t i = 0; i < desc.attributeCount && i < kMaxVertexAttributes; ++i) {
    const VertexAttribute& a = desc.attributes[i];
    const GlVertexFormat f = glVertexFormat(a.format);
    gl.EnableVertexArrayAttrib(pipeline.vao, a.location);
    if (f.integer)
      gl.VertexArrayAttribIFormat(pipeline.vao, a.location, f.components, f.type, a.offset);
    else
      gl.VertexArrayAttribFormat(pipeline.vao, a.location, f.components, f.type, f.normalised ? GL_TRUE : GL_FALSE,
                                 a.offset);
    gl.VertexArrayAttribBinding(pipeline.vao, a.location, a.bufferSlot);
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
  gl.DeleteVertexArrays(1, &pipeline->vao);
  if (pipeline_ == h) pipeline_ = {};
}

void GlDevice::destroy(ComputePipelineHandle h) {
  std::optional<GlComputePipeline> pipeline = computePipelines_.remove(h);
  if (!pipeline) return;
  gl.DeleteProgram(pipeline->program.name);
  if (computePipeline_ == h) computePipeline_ = {};
}

}  // namespace parity::rhi::gl
