// GL backend: shaders. SPIR-V is cross-compiled to GLSL 450 core with the SPIRV-Cross C API and
// compiled by the driver. Binding numbers are kept (set 0 binding N -> GL binding point, texture
// unit or image unit N; a program with descriptor arrays moves them when it links, gl_pipeline.cpp);
// the push-constant block becomes a UBO at kGlPushConstantBinding.
// Separate textures and samplers become combined sampler uniforms with no binding of their own
// (texture units kMaxBindings and up, assigned per program: see gl_device.h).
// Where the generated GLSL fails (SPIRV-Cross cannot express the module, or the driver rejects
// what it wrote) and the context has GL_ARB_gl_spirv, the driver takes the module itself: the
// translation failure becomes a note (Device::takeNotes) instead of the shader's end.
#include <spirv_cross/spirv_cross_c.h>

#include <algorithm>
#include <map>
#include <memory>
#include <type_traits>
#include <utility>

#include "rhi/combined_samplers.h"
#include "rhi/gl/gl_device.h"
#include "rhi/shader_cache.h"
#include "rhi/shader_reflection.h"
#include "rhi/spirv_lowering.h"

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

// Moves the push-constant block (its pointer types and variables) to storage class `to`; returns
// the moved variables.
std::vector<uint32_t> movePushConstants(std::vector<uint32_t>& spirv, SpvStorageClass to) {
  std::vector<uint32_t> variables;
  forEachInstruction(spirv, [&](uint32_t op, size_t i, uint32_t words) {
    if ((op == SpvOpTypePointer || op == SpvOpTypeForwardPointer) && words > 2 && spirv[i + 2] == SpvStorageClassPushConstant)
      spirv[i + 2] = to;
    if (op == SpvOpVariable && words > 3 && spirv[i + 3] == SpvStorageClassPushConstant) {
      spirv[i + 3] = to;
      variables.push_back(spirv[i + 2]);
    }
  });
  return variables;
}

// Push constants are std430 in Vulkan GLSL, but a GL 4.5 uniform block can only be std140 (with
// explicit offsets at best): a block holding, say, `float f[3]` has no UBO equivalent. Such
// blocks become a read-only storage block instead (std430 exists there): the SPIR-V's
// PushConstant storage class is rewritten to StorageBuffer before cross-compiling.
std::vector<uint32_t> pushConstantsAsStorageBuffer(const std::vector<uint32_t>& spirv) {
  std::vector<uint32_t> out = spirv;
  if (out.size() < 5) return out;
  if (out[1] < 0x00010300) out[1] = 0x00010300;  // StorageBuffer storage class: SPIR-V 1.3
  movePushConstants(out, SpvStorageClassStorageBuffer);
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

// crossCompile through the on-disk cache (rhi/shader_cache.h): a matrix child translates the same
// modules its siblings did, about half a millisecond each. The result is a function of the module,
// the entry point, the stage and the push-constant form (`pairs` come from the module); the key adds
// SPIRV-Cross's version and a hash of the code that translates (PARITY_SHADER_CACHE_STAMP, from
// CMakeLists.txt), so an edit to it is never served an entry translated before. Failures are not
// cached.
std::string translateToGlsl(const std::vector<uint32_t>& spirv, const ShaderDesc& desc, bool storageBlock,
                            const std::vector<SeparatePair>& pairs, std::string* error) {
  std::string key;
  if (!shaderCacheDirectory().empty()) {
    unsigned major = 0, minor = 0, patch = 0;
    spvc_get_version(&major, &minor, &patch);
    key = "spirv-cross " + std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(patch) +
          " glsl450 code " PARITY_SHADER_CACHE_STAMP + '\0' + std::to_string(static_cast<int>(desc.stage)) + '\0' +
          desc.entryPoint + '\0' + (storageBlock ? "storage-block" : "uniform-block") + '\0' +
          std::string(reinterpret_cast<const char*>(spirv.data()), spirv.size() * sizeof(uint32_t));
    if (std::optional<std::string> glsl = loadCachedBytes(key)) return *glsl;
  }
  std::string glsl = crossCompile(spirv, desc, storageBlock, pairs, error);
  if (!key.empty() && !glsl.empty()) storeCachedBytes(key, glsl);
  return glsl;
}

constexpr bool isAnnotation(uint32_t op) {
  return (op >= SpvOpDecorate && op <= SpvOpGroupMemberDecorate) || op == SpvOpDecorateId ||
         op == SpvOpDecorateString || op == SpvOpMemberDecorateString;
}

// The module in GL_ARB_gl_spirv's environment: the GL SPIR-V rules have no descriptor sets (set 0
// is the only one here, shader_reflection.cpp) and no push constants, so DescriptorSet
// decorations go and the push-constant block becomes a uniform block at kGlPushConstantBinding,
// the UBO the device keeps there; its members keep their explicit SPIR-V offsets.
std::vector<uint32_t> glSpirvForm(const std::vector<uint32_t>& spirv) {
  if (spirv.size() < 5) return spirv;
  std::vector<uint32_t> out(spirv.begin(), spirv.begin() + 5);
  size_t firstAnnotation = 0;
  forEachInstruction(spirv, [&](uint32_t op, size_t i, uint32_t words) {
    if (op == SpvOpDecorate && words >= 3 && spirv[i + 2] == SpvDecorationDescriptorSet) return;
    if (isAnnotation(op) && firstAnnotation == 0) firstAnnotation = out.size();
    out.insert(out.end(), spirv.begin() + static_cast<std::ptrdiff_t>(i), spirv.begin() + static_cast<std::ptrdiff_t>(i + words));
  });
  std::vector<uint32_t> bindings;
  for (uint32_t variable : movePushConstants(out, SpvStorageClassUniform))
    bindings.insert(bindings.end(), {(4u << 16) | SpvOpDecorate, variable, SpvDecorationBinding, kGlPushConstantBinding});
  if (!bindings.empty() && firstAnnotation != 0)
    out.insert(out.begin() + static_cast<std::ptrdiff_t>(firstAnnotation), bindings.begin(), bindings.end());
  return out;
}

// What SPIRV-Cross is known to translate wrongly while its GLSL still compiles, or "". GLSL picks
// atomicMin/atomicMax's comparison by the operand's type, and SPIRV-Cross writes them without a
// cast: OpAtomicUMax on an int compares signed (VK-GL-CTS signed_op/int_atomicumax). SPIRV-Cross
// writes OpFOrdNotEqual as GLSL's !=, which is true for a NaN operand where the ordered comparison
// is false (VkRunner unordered-comparison; glslang itself emits != as OpFUnordNotEqual, which
// round-trips).
std::string glslMistranslation(const std::vector<uint32_t>& spirv) {
  std::map<uint32_t, bool> signedInts;  // OpTypeInt result id -> signedness
  std::string wrong;
  forEachInstruction(spirv, [&](uint32_t op, size_t i, uint32_t words) {
    if (op == SpvOpTypeInt && words >= 4) signedInts[spirv[i + 1]] = spirv[i + 3] != 0;
    if (wrong.empty() && op == SpvOpFOrdNotEqual)
      wrong = "SPIRV-Cross writes OpFOrdNotEqual as GLSL's !=, which is true where an operand is NaN";
    const bool signedOp = op == SpvOpAtomicSMin || op == SpvOpAtomicSMax;
    if (!wrong.empty() || !(signedOp || op == SpvOpAtomicUMin || op == SpvOpAtomicUMax) || words < 2) return;
    auto type = signedInts.find(spirv[i + 1]);
    if (type != signedInts.end() && type->second != signedOp)
      wrong = std::string("SPIRV-Cross writes ") + (signedOp ? "a signed" : "an unsigned") + " atomic min/max on " +
              (signedOp ? "a uint" : "an int") + " as GLSL's atomicMin/atomicMax of that type, which compares " +
              (signedOp ? "unsigned" : "signed");
  });
  return wrong;
}


}  // namespace

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
  shader.spirv = desc.spirv;
  shader.entryPoint = desc.entryPoint;
  if (std::string lowered = lowerForDrivers(shader.spirv); !lowered.empty()) notes_.push_back(name + ": " + lowered);
  const std::vector<uint32_t>& spirv = shader.spirv;
  std::string error;
  if (!reflectSpirv(spirv, desc.stage, &shader.reflection, &error)) {
    log(name + ": " + error);
    return {};
  }
  if (!desc.arbProgram.empty()) {  // the driver's assembler: gl_arb_program.cpp
    shader.arbProgram = loadArbProgram(desc, &error);
    if (shader.arbProgram == 0) {
      notes_.push_back(name + ": " + error);
      return {};
    }
    return shaders_.add(std::move(shader));
  }
  if (!desc.openGlGlsl.empty()) {  // the driver's own compiler: gl_opengl_glsl.cpp
    shader.openGlUnits = compileOpenGlGlsl(desc, &error);
    shader.looseUniformBlock = desc.looseUniformBlock;
    if (shader.openGlUnits.empty()) {
      notes_.push_back(name + ": " + error);
      return {};
    }
    return shaders_.add(std::move(shader));
  }
  const std::vector<SeparatePair>& pairs = shader.reflection.separatePairs;
  shader.translationError = takesSpirv(shader) ? glslMistranslation(spirv) : std::string();
  if (shader.translationError.empty()) {
    std::string glsl = translateToGlsl(spirv, desc, false, pairs, &error);
    if (glsl.empty() && shader.reflection.pushConstantSize > 0) {
      std::string storageError;
      glsl = translateToGlsl(pushConstantsAsStorageBuffer(spirv), desc, true, pairs, &storageError);
      shader.pushConstantsInStorageBlock = !glsl.empty();
      if (glsl.empty()) error += " (as a storage block: " + storageError + ")";
    }
    if (glsl.empty()) shader.translationError = error;
    else shader.name = compileGlsl(desc.stage, glsl, &shader.translationError);
  }
  if (shader.name == 0) {
    if (!takesSpirv(shader)) {
      log(name + ": " + shader.translationError);
      return {};
    }
    std::string spirvError;
    shader.spirvName = compileSpirv(shader, &spirvError);
    if (shader.spirvName == 0) {
      log(name + ": " + shader.translationError + "\n--- and through GL_ARB_gl_spirv: " + spirvError);
      return {};
    }
    notes_.push_back(name + ": ran through GL_ARB_gl_spirv instead of SPIRV-Cross's GLSL: " + shader.translationError);
  }
  label(GL_SHADER, shader.name != 0 ? shader.name : shader.spirvName, desc.label);
  return shaders_.add(std::move(shader));
}

// The SPIR-V path keeps the module's own bindings, so it is open to modules without what the GLSL
// path renames or moves: separate texture/sampler pairs and descriptor arrays.
bool GlDevice::takesSpirv(const GlShader& shader) const {
  if (!specializeShader_ || !shader.reflection.separatePairs.empty()) return false;
  return std::all_of(shader.reflection.resources.begin(), shader.reflection.resources.end(),
                     [](const ShaderResource& r) { return r.arraySize == 1; });
}

GLuint GlDevice::compileSpirv(const GlShader& shader, std::string* error) {
  const std::vector<uint32_t> module = glSpirvForm(shader.spirv);
  GLuint name = gl.CreateShader(glStage(shader.stage));
  while (gl.GetError() != GL_NO_ERROR) {
  }
  gl.ShaderBinary(1, &name, GL_SHADER_BINARY_FORMAT_SPIR_V_ARB, module.data(),
                  static_cast<GLsizei>(module.size() * sizeof(uint32_t)));
  if (gl.GetError() != GL_NO_ERROR) {
    *error = "the driver refuses the module (glShaderBinary)";
    gl.DeleteShader(name);
    return 0;
  }
  specializeShader_(name, shader.entryPoint.c_str(), 0, nullptr, nullptr);
  GLint ok = GL_FALSE;
  gl.GetShaderiv(name, GL_COMPILE_STATUS, &ok);
  if (ok) return name;
  const std::string infoLog = shaderInfoLog(name);
  *error = "glSpecializeShader: " + (infoLog.empty() ? std::string("failed") : infoLog);
  gl.DeleteShader(name);
  return 0;
}

GLuint GlDevice::compileGlsl(ShaderStage stage, const std::string& glsl, std::string* error) {
  GLuint name = gl.CreateShader(glStage(stage));
  const GLchar* text = glsl.c_str();
  gl.ShaderSource(name, 1, &text, nullptr);
  // The compiler's own debug messages are muted here: a failure is this backend's to report,
  // with the generated source, or to recover from through GL_ARB_gl_spirv with a note.
  gl.DebugMessageControl(GL_DEBUG_SOURCE_SHADER_COMPILER, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_FALSE);
  gl.CompileShader(name);
  for (GLenum severity : {GL_DEBUG_SEVERITY_HIGH, GL_DEBUG_SEVERITY_MEDIUM, GL_DEBUG_SEVERITY_LOW})
    gl.DebugMessageControl(GL_DEBUG_SOURCE_SHADER_COMPILER, GL_DONT_CARE, severity, 0, nullptr, GL_TRUE);
  GLint ok = GL_FALSE;
  gl.GetShaderiv(name, GL_COMPILE_STATUS, &ok);
  if (ok) return name;
  // The GLSL is generated, so this is a SPIRV-Cross or driver limitation, not a user error:
  // report it with the generated source.
  *error = "the GLSL generated from SPIR-V does not compile:\n" + shaderInfoLog(name) + "\n--- generated GLSL ---\n" + glsl;
  gl.DeleteShader(name);
  return 0;
}

std::string GlDevice::shaderInfoLog(GLuint shader) {
  GLint length = 0;
  gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string infoLog(static_cast<size_t>(std::max(length, 1)), '\0');
  gl.GetShaderInfoLog(shader, length, nullptr, infoLog.data());
  return infoLog.c_str();
}

std::vector<std::string> GlDevice::takeNotes() { return std::exchange(notes_, {}); }

void GlDevice::destroy(ShaderHandle h) {
  // Programs already linked keep working: GL deletes a shader object only once detached, and
  // linkProgram() detaches right after linking.
  std::optional<GlShader> shader = shaders_.remove(h);
  if (shader && shader->name != 0) gl.DeleteShader(shader->name);
  if (shader && shader->spirvName != 0) gl.DeleteShader(shader->spirvName);
  if (shader) deleteArbProgram(shader->arbProgram);
  if (shader)
    for (GLuint unit : shader->openGlUnits) gl.DeleteShader(unit);
}

}  // namespace parity::rhi::gl
