// GL backend: shaders. SPIR-V is cross-compiled to GLSL 450 core with the SPIRV-Cross C API and
// compiled by the driver. Binding numbers are kept (set 0 binding N -> GL binding point, texture
// unit or image unit N; a program with descriptor arrays moves them when it links, gl_pipeline.cpp);
// the push-constant block becomes a UBO at kGlPushConstantBinding.
// Separate textures and samplers become combined sampler uniforms with no binding of their own
// (texture units kMaxBindings and up, assigned per program: see gl_device.h).
#include <spirv_cross/spirv_cross_c.h>

#include <algorithm>
#include <memory>
#include <type_traits>

#include "rhi/combined_samplers.h"
#include "rhi/gl/gl_device.h"

namespace parity::rhi::gl {

namespace {

struct SpvcContextDeleter {
  void operator()(spvc_context c) const { spvc_context_destroy(c); }
};
using SpvcContext = std::unique_ptr<std::remove_pointer_t<spvc_context>, SpvcContextDeleter>;

void onSpvcError(void* userData, const char* message) {
  auto* error = static_cast<std::string*>(userData);
  if (error->empty()) *error = message;
}

SpvExecutionModel executionModel(ShaderStage stage) {
  switch (stage) {
    case ShaderStage::Vertex: return SpvExecutionModelVertex;
    case ShaderStage::Fragment: return SpvExecutionModelFragment;
    case ShaderStage::Compute: return SpvExecutionModelGLCompute;
    case ShaderStage::Geometry: return SpvExecutionModelGeometry;
    case ShaderStage::TessControl: return SpvExecutionModelTessellationControl;
    case ShaderStage::TessEvaluation: return SpvExecutionModelTessellationEvaluation;
  }
  return SpvExecutionModelVertex;
}

// Push constants are std430 in Vulkan GLSL, but a GL 4.5 uniform block can only be std140 (with
// explicit offsets at best): a block holding, say, `float f[3]` has no UBO equivalent. Such
// blocks become a read-only storage block instead (std430 exists there): the SPIR-V's
// PushConstant storage class is rewritten to StorageBuffer before cross-compiling.
std::vector<uint32_t> pushConstantsAsStorageBuffer(const std::vector<uint32_t>& spirv) {
  std::vector<uint32_t> out = spirv;
  if (out.size() < 5) return out;
  if (out[1] < 0x00010300) out[1] = 0x00010300;  // StorageBuffer storage class: SPIR-V 1.3
  for (size_t i = 5; i < out.size();) {
    const uint32_t words = out[i] >> 16, op = out[i] & 0xFFFF;
    if (words == 0 || i + words > out.size()) break;
    if ((op == SpvOpTypePointer || op == SpvOpTypeForwardPointer) && words > 2 &&
        out[i + 2] == SpvStorageClassPushConstant)
      out[i + 2] = SpvStorageClassStorageBuffer;
    if (op == SpvOpVariable && words > 3 && out[i + 3] == SpvStorageClassPushConstant)
      out[i + 3] = SpvStorageClassStorageBuffer;
    i += words;
  }
  return out;
}

// Returns the GLSL source, or an empty string with *error set. `storageBlock`: the SPIR-V had its
// push-constant block turned into a storage block (see above), which gets the same binding.
// `pairs`: the separate texture/sampler pairs reflection found (GLSL 450 without Vulkan semantics
// has no separate textures and samplers, so each pair becomes one combined sampler uniform named
// by combinedSamplerName(); linkProgram gives it its texture unit).
std::string crossCompile(const std::vector<uint32_t>& spirv, const ShaderDesc& desc, bool storageBlock,
                         const std::vector<SeparatePair>& pairs, std::string* error) {
  std::string spvcError;
  spvc_context raw = nullptr;
  if (spvc_context_create(&raw) != SPVC_SUCCESS) {
    *error = "SPIRV-Cross: cannot create a context";
    return {};
  }
  SpvcContext context(raw);
  spvc_context_set_error_callback(raw, onSpvcError, &spvcError);
  auto failed = [&](const char* what) {
    *error = std::string("SPIRV-Cross: ") + what + (spvcError.empty() ? "" : ": " + spvcError);
    return std::string();
  };

  spvc_parsed_ir ir = nullptr;
  spvc_compiler compiler = nullptr;
  if (spvc_context_parse_spirv(raw, spirv.data(), spirv.size(), &ir) != SPVC_SUCCESS)
    return failed("cannot parse the SPIR-V");
  if (spvc_context_create_compiler(raw, SPVC_BACKEND_GLSL, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP, &compiler) !=
      SPVC_SUCCESS)
    return failed("cannot create a GLSL compiler");
  if (spvc_compiler_set_entry_point(compiler, desc.entryPoint.c_str(), executionModel(desc.stage)) != SPVC_SUCCESS)
    return failed("entry point not found");

  spvc_compiler_options options = nullptr;
  spvc_compiler_create_compiler_options(compiler, &options);
  spvc_compiler_options_set_uint(options, SPVC_COMPILER_OPTION_GLSL_VERSION, 450);
  spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_GLSL_ES, SPVC_FALSE);
  spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_GLSL_VULKAN_SEMANTICS, SPVC_FALSE);
  spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_GLSL_EMIT_PUSH_CONSTANT_AS_UNIFORM_BUFFER, SPVC_TRUE);
  // Clip-space conventions are normalised by glClipControl (gl_device.cpp), not in the shader.
  spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_FIXUP_DEPTH_CONVENTION, SPVC_FALSE);
  spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_FLIP_VERTEX_Y, SPVC_FALSE);
  if (spvc_compiler_install_compiler_options(compiler, options) != SPVC_SUCCESS)
    return failed("cannot set the GLSL options");

  spvc_resources resources = nullptr;
  spvc_compiler_create_shader_resources(compiler, &resources);
  const spvc_reflected_resource* list = nullptr;
  size_t count = 0;
  if (!storageBlock) {
    spvc_resources_get_resource_list_for_type(resources, SPVC_RESOURCE_TYPE_PUSH_CONSTANT, &list, &count);
    for (size_t i = 0; i < count; ++i)
      spvc_compiler_set_decoration(compiler, list[i].id, SpvDecorationBinding, kGlPushConstantBinding);
  } else {
    // The rewritten block is the only storage block without a DescriptorSet decoration.
    spvc_resources_get_resource_list_for_type(resources, SPVC_RESOURCE_TYPE_STORAGE_BUFFER, &list, &count);
    for (size_t i = 0; i < count; ++i)
      if (!spvc_compiler_has_decoration(compiler, list[i].id, SpvDecorationDescriptorSet)) {
        spvc_compiler_set_decoration(compiler, list[i].id, SpvDecorationBinding, kGlPushConstantBinding);
        spvc_compiler_set_decoration(compiler, list[i].id, SpvDecorationNonWritable, 1);
      }
  }

  // Samplers, images and texel buffers under names linkProgram can look up (glResourceName).
  for (spvc_resource_type type : {SPVC_RESOURCE_TYPE_SAMPLED_IMAGE, SPVC_RESOURCE_TYPE_STORAGE_IMAGE}) {
    spvc_resources_get_resource_list_for_type(resources, type, &list, &count);
    for (size_t i = 0; i < count; ++i)
      spvc_compiler_set_name(compiler, list[i].id,
                             glResourceName(spvc_compiler_get_decoration(compiler, list[i].id, SpvDecorationBinding)).c_str());
  }

  if (!pairs.empty()) {
    // The same analysis as reflectSpirv(), so the combined variables are the reflected pairs.
    std::vector<CombinedPair> combined;
    if (!combineSeparatePairs(compiler, spirv, &combined)) return failed("cannot combine the separate textures and samplers");
    for (const CombinedPair& c : combined) {
      // Stable across stages (linkProgram looks the uniform up by name) and without a binding:
      // the unit is the program's to assign.
      spvc_compiler_set_name(compiler, c.combinedVariable, combinedSamplerName(c.pair).c_str());
      spvc_compiler_unset_decoration(compiler, c.combinedVariable, SpvDecorationBinding);
    }
  }

  const char* source = nullptr;
  if (spvc_compiler_compile(compiler, &source) != SPVC_SUCCESS || !source) return failed("GLSL generation failed");
  return source;
}

GLenum glStage(ShaderStage stage) {
  switch (stage) {
    case ShaderStage::Vertex: return GL_VERTEX_SHADER;
    case ShaderStage::Fragment: return GL_FRAGMENT_SHADER;
    case ShaderStage::Compute: return GL_COMPUTE_SHADER;
    case ShaderStage::Geometry: return GL_GEOMETRY_SHADER;
    case ShaderStage::TessControl: return GL_TESS_CONTROL_SHADER;
    case ShaderStage::TessEvaluation: return GL_TESS_EVALUATION_SHADER;
  }
  return GL_VERTEX_SHADER;
}

}  // namespace

std::string glResourceName(uint32_t binding) { return "parity_binding_" + std::to_string(binding); }

std::string combinedSamplerName(const SeparatePair& pair) {
  std::string name = "parity_combined_" + std::to_string(pair.textureBinding) + "_";
  name += pair.samplerBinding == kNoSamplerBinding ? std::string("none") : std::to_string(pair.samplerBinding);
  return pair.depthCompare ? name + "_shadow" : name;
}

ShaderHandle GlDevice::createShader(const ShaderDesc& desc) {
  const std::string name = desc.label.empty() ? std::string("shader") : desc.label;
  GlShader shader;
  shader.stage = desc.stage;
  shader.label = desc.label;
  std::string error;
  if (!reflectSpirv(desc.spirv, desc.stage, &shader.reflection, &error)) {
    log(name + ": " + error);
    return {};
  }
  const std::vector<SeparatePair>& pairs = shader.reflection.separatePairs;
  std::string glsl = crossCompile(desc.spirv, desc, false, pairs, &error);
  if (glsl.empty() && shader.reflection.pushConstantSize > 0) {
    std::string storageError;
    glsl = crossCompile(pushConstantsAsStorageBuffer(desc.spirv), desc, true, pairs, &storageError);
    shader.pushConstantsInStorageBlock = !glsl.empty();
    if (glsl.empty()) error += " (as a storage block: " + storageError + ")";
  }
  if (glsl.empty()) {
    log(name + ": " + error);
    return {};
  }

  shader.name = gl.CreateShader(glStage(desc.stage));
  const GLchar* text = glsl.c_str();
  gl.ShaderSource(shader.name, 1, &text, nullptr);
  gl.CompileShader(shader.name);
  GLint ok = GL_FALSE;
  gl.GetShaderiv(shader.name, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    // The GLSL is generated, so this is a SPIRV-Cross or driver limitation, not a user error:
    // report it with the generated source.
    GLint length = 0;
    gl.GetShaderiv(shader.name, GL_INFO_LOG_LENGTH, &length);
    std::string infoLog(static_cast<size_t>(std::max(length, 1)), '\0');
    gl.GetShaderInfoLog(shader.name, length, nullptr, infoLog.data());
    log(name + ": the GLSL generated from SPIR-V does not compile:\n" + infoLog.c_str() + "\n--- generated GLSL ---\n" +
        glsl);
    gl.DeleteShader(shader.name);
    return {};
  }
  label(GL_SHADER, shader.name, desc.label);
  return shaders_.add(std::move(shader));
}

void GlDevice::destroy(ShaderHandle h) {
  // Programs already linked keep working: GL deletes a shader object only once detached, and
  // linkProgram() detaches right after linking.
  std::optional<GlShader> shader = shaders_.remove(h);
  if (shader) gl.DeleteShader(shader->name);
}

}  // namespace parity::rhi::gl
