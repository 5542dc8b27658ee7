// Shaders of a script on a device whose driver compiles OpenGL GLSL itself (rhi::ShaderDesc::
// openGlGlsl): which pipelines run there, the sources the driver gets, and the driver as the
// judge of a shader glslang cannot port.
#include "harness/scripts/runner/steps.h"

#include <algorithm>
#include <regex>

#include "harness/io/text.h"
#include "harness/scripts/opengl_glsl.h"
#include "rhi/shader_compiler.h"

namespace parity::harness::script::runner {

namespace {

// What OpenGL runs for a piglit program without a vertex shader, written for the driver: the
// position from piglit's attribute (the port's kPassthroughVs input) and, before GLSL 1.40,
// fixed-function vertex processing's colour (the current colour, white unless set).
std::string nativePassthroughVs(int version) {
  std::string src = "#version " + std::to_string(version) + "\n";
  src += std::string(version < 130 ? "attribute" : "in") + " vec4 piglit_vertex;\nvoid main() {\n  gl_Position = piglit_vertex;\n";
  if (version < 140) src += "  gl_FrontColor = gl_Color;\n";
  return src + "}\n";
}

}  // namespace

std::string ShaderSteps::deviceLog() {
  std::string log;
  for (const std::string& note : dev_.takeNotes()) log += (log.empty() ? ": " : "; ") + oneLine(note);
  return log.empty() ? " (see the validation message above)" : log;
}

bool ShaderSteps::runsOpenGlGlsl(const Pipeline& p) const {
  const std::vector<std::string>& features = dev_.info().features;
  if (std::find(features.begin(), features.end(), "openGlGlsl") == features.end()) return false;
  if (script_.fixedFunction.flatShading || script_.fixedFunction.twoSidedColor) return false;
  if (!script_.namedStrings.empty()) return false;  // the runner gives them to glslang only
  if (script_.separateShaderObjects) return false;   // one linked program matches stages by name
  bool control = false, evaluation = false;
  for (const std::string& n : p.shaders) {
    const Shader* s = script_.findShader(n);
    if (!s || !(s->openGl || s->passthrough)) return false;
    // A rectangle texture is a 2D one whose coordinates the port normalises.
    static const std::regex kPortOnly(R"(\b(gl_ClipVertex|sampler2DRect\w*)\b)");
    if (s->openGl && std::regex_search(s->source, kPortOnly)) return false;
    for (const Shader::LinkedUnit& unit : s->linkedUnits)
      if (std::regex_search(unit.source, kPortOnly)) return false;
    control |= s->stage == Stage::TessControl;
    evaluation |= s->stage == Stage::TessEvaluation;
  }
  if (evaluation && !control) return false;  // the runner's pass-through control shader is Vulkan GLSL
  return std::none_of(script_.commands.begin(), script_.commands.end(), [](const Command& c) {
    return c.kind == Command::Kind::SetUniform && c.uniform.rfind(depthModeUniform(""), 0) == 0;
  });
}

bool ShaderSteps::runsOnlyOpenGlGlsl(const std::string& shader) const {
  bool used = false;
  for (const Pipeline& p : script_.pipelines) {
    if (std::find(p.shaders.begin(), p.shaders.end(), shader) == p.shaders.end()) continue;
    if (!runsOpenGlGlsl(p)) return false;
    used = true;
  }
  return used;
}

rhi::Device* ShaderSteps::openGlJudge() {
  auto compilesOpenGlGlsl = [](const rhi::Device& d) {
    const std::vector<std::string>& features = d.info().features;
    return std::find(features.begin(), features.end(), "openGlGlsl") != features.end();
  };
  rhi::Device* judge = compilesOpenGlGlsl(dev_) ? &dev_ : opts_.openGlCompiler ? opts_.openGlCompiler() : nullptr;
  return judge && compilesOpenGlGlsl(*judge) ? judge : nullptr;
}

std::optional<std::string> ShaderSteps::judgeLacksRequirement() {
  rhi::Device* judge = openGlJudge();
  if (!judge) return std::nullopt;
  const std::vector<std::string>& offered = judge->info().openGlExtensions;
  for (const Requirement& r : script_.requirements)
    if (r.what == "opengl_extension" && std::find(offered.begin(), offered.end(), r.value) == offered.end())
      return "[require] " + r.value + " (line " + std::to_string(r.loc.line) + "), which the GL driver that judges the OpenGL GLSL (" +
             judge->info().renderer + ") does not offer";
  return std::nullopt;
}

std::optional<std::string> ShaderSteps::driverCompiles(const Shader& s) {
  rhi::Device* judge = openGlJudge();
  if (!judge) return std::nullopt;
  // The driver compiles the units without linking them, so a port of nothing stands in.
  const std::vector<uint32_t> empty = emptyPort(s.stage);
  if (empty.empty()) return std::nullopt;
  rhi::ShaderDesc sd;
  sd.stage = rhiStage(s.stage);
  sd.spirv = empty;
  sd.openGlGlsl = openGlUnits(s);
  sd.label = s.name;
  rhi::ShaderHandle h = judge->createShader(sd);
  std::string log;
  for (const std::string& note : judge->takeNotes()) log += (log.empty() ? "" : "; ") + oneLine(note);
  if (!h) return log.empty() ? "the driver refuses it" : log;
  judge->destroy(h);
  return std::string();
}

std::vector<uint32_t> ShaderSteps::emptyPort(Stage stage) {
  static const std::map<Stage, const char*> kEmptyPorts = {
      {Stage::Vertex, "#version 450\nvoid main() {}\n"},
      {Stage::Fragment, "#version 450\nvoid main() {}\n"},
      {Stage::Compute, "#version 450\nlayout(local_size_x = 1) in;\nvoid main() {}\n"},
      {Stage::Geometry, "#version 450\nlayout(points) in;\nlayout(points, max_vertices = 1) out;\nvoid main() {}\n"},
      {Stage::TessControl, "#version 450\nlayout(vertices = 1) out;\nvoid main() {}\n"},
      {Stage::TessEvaluation, "#version 450\nlayout(triangles) in;\nvoid main() {}\n"}};
  rhi::CompiledShader c = rhi::compileGlslSource(kEmptyPorts.at(stage), "empty port", rhiStage(stage), {});
  return c.ok() ? c.spirv : std::vector<uint32_t>{};
}

std::vector<std::string> ShaderSteps::openGlSources(const Shader& s, const Pipeline& p) const {
  if (s.passthrough) {
    int version = 110;
    for (const std::string& n : p.shaders)
      if (const Shader* f = script_.findShader(n); f && f->openGl && f->stage == Stage::Fragment) version = openGlGlslVersion(f->source, 110);
    return {nativePassthroughVs(version)};
  }
  return openGlUnits(s);
}

std::vector<std::string> ShaderSteps::openGlUnits(const Shader& s) const {
  std::vector<std::string> units;
  auto add = [&](const std::string& source, int sourceLine) {
    // piglit gives a shader without #version the GLSL version the file requires.
    OpenGlGlsl gl = nativeOpenGlGlsl(source, s.stage, s.glslVersion);
    const std::string version = s.glslVersion > 110 ? "#version " + std::to_string(s.glslVersion) : "";
    units.push_back(withDeclarations(gl.source, gl.declarations, sourceLine, version));
  };
  add(s.source, s.sourceLine);
  for (const Shader::LinkedUnit& unit : s.linkedUnits) add(unit.source, unit.sourceLine);
  return units;
}

}  // namespace parity::harness::script::runner
