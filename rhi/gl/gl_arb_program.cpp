// GL backend: ARB assembly programs (ShaderDesc::arbProgram), OpenGL's ARB_vertex_program and
// ARB_fragment_program. The driver loads each program text (glProgramStringARB); a pipeline of
// them has no program object: its programs are bound and their targets enabled at each draw, as
// piglit's shader_runner does. They need a compatibility context, whose entry points and
// matrix stacks the core header does not declare, so they are loaded here on their own.
#include <algorithm>
#include <type_traits>

#include "rhi/gl/gl_device.h"

namespace parity::rhi::gl {

namespace {

// Enumerants of ARB_vertex_program, ARB_fragment_program and OpenGL 1.0's matrix stacks, absent
// from the core header.
constexpr GLenum kVertexProgram = 0x8620;          // GL_VERTEX_PROGRAM_ARB
constexpr GLenum kFragmentProgram = 0x8804;        // GL_FRAGMENT_PROGRAM_ARB
constexpr GLenum kProgramFormatAscii = 0x8875;     // GL_PROGRAM_FORMAT_ASCII_ARB
constexpr GLenum kProgramErrorPosition = 0x864B;   // GL_PROGRAM_ERROR_POSITION_ARB
constexpr GLenum kProgramErrorString = 0x8874;     // GL_PROGRAM_ERROR_STRING_ARB
constexpr GLenum kModelView = 0x1700;              // GL_MODELVIEW
constexpr GLenum kProjection = 0x1701;             // GL_PROJECTION

GLenum target(ShaderStage stage) { return stage == ShaderStage::Vertex ? kVertexProgram : kFragmentProgram; }

}  // namespace

bool GlDevice::loadArbProgramFunctions() {
  GLint profile = 0;
  gl.GetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  const std::vector<std::string>& offered = info_.openGlExtensions;
  for (const char* extension : {"GL_ARB_vertex_program", "GL_ARB_fragment_program"})
    if (std::find(offered.begin(), offered.end(), extension) == offered.end()) return false;
  if (!(profile & GL_CONTEXT_COMPATIBILITY_PROFILE_BIT)) return false;
  ArbProgramFunctions f;
  auto load = [&](auto& entry, const char* name) {
    entry = reinterpret_cast<std::remove_reference_t<decltype(entry)>>(context_->getProcAddress(name));
    return entry != nullptr;
  };
  if (!load(f.GenPrograms, "glGenProgramsARB") || !load(f.DeletePrograms, "glDeleteProgramsARB") ||
      !load(f.BindProgram, "glBindProgramARB") || !load(f.ProgramString, "glProgramStringARB") ||
      !load(f.ProgramEnvParameter4fv, "glProgramEnvParameter4fvARB") ||
      !load(f.ProgramLocalParameter4fv, "glProgramLocalParameter4fvARB") || !load(f.MatrixMode, "glMatrixMode") ||
      !load(f.LoadMatrixf, "glLoadMatrixf") || !load(f.Color4fv, "glColor4fv") || !load(f.MultiTexCoord4fv, "glMultiTexCoord4fv"))
    return false;
  arb_ = f;
  return true;
}

GLuint GlDevice::loadArbProgram(const ShaderDesc& desc, std::string* error) {
  if (!arb_.ProgramString) {
    *error = "ARB assembly programs need a compatibility context with GL_ARB_vertex_program and GL_ARB_fragment_program";
    return 0;
  }
  if (desc.stage != ShaderStage::Vertex && desc.stage != ShaderStage::Fragment) {
    *error = "an ARB assembly program is a vertex or a fragment program";
    return 0;
  }
  GLuint program = 0;
  arb_.GenPrograms(1, &program);
  arb_.BindProgram(target(desc.stage), program);
  while (gl.GetError() != GL_NO_ERROR) {
  }
  arb_.ProgramString(target(desc.stage), kProgramFormatAscii, static_cast<GLsizei>(desc.arbProgram.size()), desc.arbProgram.data());
  GLint position = -1;
  gl.GetIntegerv(kProgramErrorPosition, &position);
  const GLenum glError = gl.GetError();
  const bool failed = glError != GL_NO_ERROR || position != -1;
  arb_.BindProgram(target(desc.stage), 0);
  if (!failed) return program;
  const auto* message = reinterpret_cast<const char*>(gl.GetString(kProgramErrorString));
  *error = "the ARB assembly program does not load (GL error " + std::to_string(glError) +
           (position >= 0 ? ", at character " + std::to_string(position) : std::string()) + "): " +
           (message && *message ? message : "the driver gives no reason");
  arb_.DeletePrograms(1, &program);
  return 0;
}

void GlDevice::deleteArbProgram(GLuint program) {
  if (program != 0 && arb_.DeletePrograms) arb_.DeletePrograms(1, &program);
}

bool GlDevice::placeArbPrograms(const std::vector<const GlShader*>& shaders, const std::string& label, GlProgram* out) {
  const std::string what = label.empty() ? std::string("pipeline") : label;
  if (!std::all_of(shaders.begin(), shaders.end(), [](const GlShader* s) { return s->arbProgram != 0; })) {
    notes_.push_back(what + ": ARB assembly programs (ShaderDesc::arbProgram) cannot be combined with shaders");
    return false;
  }
  *out = GlProgram{};
  for (const GlShader* s : shaders) {
    (s->stage == ShaderStage::Vertex ? out->arbVertexProgram : out->arbFragmentProgram) = s->arbProgram;
    for (const ShaderResource& r : s->reflection.resources)
      if (std::none_of(out->resources.begin(), out->resources.end(), [&](const ShaderResource& e) { return e.binding == r.binding; }))
        out->resources.push_back(r);
  }
  // texture[N] reads unit N, which binding N's point is while no binding holds an array.
  out->points = glBindingPoints(out->resources);
  for (const ShaderResource& r : out->resources)
    if (r.arraySize != 1 || r.kind != BindingKind::SampledTexture) {
      notes_.push_back(what + ": the port of an ARB assembly program declares '" + r.name + "', which is not one texture unit");
      return false;
    }
  out->openGlClipSpace = true;
  return true;
}

void GlDevice::bindArbPrograms(const GlProgram& program) {
  const bool arb = program.arbVertexProgram != 0 || program.arbFragmentProgram != 0;
  if (!arb && !arbProgramsEnabled_) return;
  for (const auto& [stageTarget, name] : {std::pair{kVertexProgram, program.arbVertexProgram}, std::pair{kFragmentProgram, program.arbFragmentProgram}}) {
    if (name != 0) {
      gl.Enable(stageTarget);
      arb_.BindProgram(stageTarget, name);
    } else {
      gl.Disable(stageTarget);
    }
  }
  arbProgramsEnabled_ = arb;
}

void GlDevice::setProgramParameter(ShaderStage stage, bool local, uint32_t index, const std::array<float, 4>& value) {
  if (!arb_.ProgramString || (stage != ShaderStage::Vertex && stage != ShaderStage::Fragment)) return;
  if (!local) {
    arb_.ProgramEnvParameter4fv(target(stage), index, value.data());
    return;
  }
  const GlPipeline* p = pipelines_.get(pipeline_);
  const GLuint program = !p ? 0 : stage == ShaderStage::Vertex ? p->program.arbVertexProgram : p->program.arbFragmentProgram;
  if (program == 0) return;
  arb_.BindProgram(target(stage), program);  // local parameters belong to the bound program
  arb_.ProgramLocalParameter4fv(target(stage), index, value.data());
}

void GlDevice::setTransformMatrices(const std::array<float, 16>& modelView, const std::array<float, 16>& projection) {
  if (!arb_.MatrixMode) return;
  arb_.MatrixMode(kProjection);
  arb_.LoadMatrixf(projection.data());
  arb_.MatrixMode(kModelView);
  arb_.LoadMatrixf(modelView.data());
}

void GlDevice::setCurrentAttribute(CurrentAttribute attribute, uint32_t index, const std::array<float, 4>& value) {
  if (!arb_.Color4fv) return;
  if (attribute == CurrentAttribute::Color && index == 0) arb_.Color4fv(value.data());
  if (attribute == CurrentAttribute::TexCoord && index < 8) arb_.MultiTexCoord4fv(GL_TEXTURE0 + index, value.data());
}

}  // namespace parity::rhi::gl
