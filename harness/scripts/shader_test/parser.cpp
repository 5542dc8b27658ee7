// shader_test files: the sections, then the [test] commands; parseShaderTest().
#include "harness/scripts/shader_test/steps.h"

#include "harness/scripts/opengl_glsl.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <regex>
#include <set>
#include <sstream>

namespace parity::harness::script::shader_test {

namespace {

// GL_CLIP_DISTANCE0..7 (GL_CLIP_PLANE<i> is its compatibility name).
bool isClipDistance(const std::string& cap) {
  for (const std::string prefix : {"GL_CLIP_DISTANCE", "GL_CLIP_PLANE"})
    if (cap.size() == prefix.size() + 1 && cap.compare(0, prefix.size(), prefix) == 0 && cap.back() >= '0' && cap.back() <= '7')
      return true;
  return false;
}

}  // namespace

Script ShaderTestParser::run() {
  splitSections();
  // piglit files state the GLSL or GL version or the OpenGL extensions they need, or hold ARB
  // assembly programs; VkRunner's do none of that.
  piglit_ = false;
  for (const Section& s : sections_) {
    if (s.name == "vertex program" || s.name == "fragment program") piglit_ = true;
    if (s.name == "require")
      for (const auto& [line, text] : s.lines) {
        std::vector<std::string> w = words(uncommented(text));
        if (!w.empty() && (w[0] == "GLSL" || w[0] == "GL" || w[0] == "GL_ES" || w[0] == "GLSL_ES" || w[0].rfind("GL_", 0) == 0))
          piglit_ = true;
      }
  }
  if (!piglit_) joinContinuedLines();
  tolerance_ = piglit_ ? 3.0 / 256.0 : 0.01;  // piglit: 3 steps of an 8-bit channel; VkRunner: 0.01
  for (const Section& s : sections_)
    if (s.name == "require") require(s);
  // piglit skips a file whose requirements the driver lacks before it reads the rest: an error
  // in the rest of such a file is its skip, too.
  if (script_.unsupported.empty()) return parseAfterRequirements();
  try {
    return parseAfterRequirements();
  } catch (const ShaderTestError&) {
    return std::move(script_);
  }
}

Script ShaderTestParser::parseAfterRequirements() {
  for (const Section& s : sections_) {
    if (s.name == "require") continue;
    else if (s.name == "shader include") namedString(s);
    else if (s.name == "shader include paths") {
      for (const auto& [line, text] : s.lines)
        if (!trim(text).empty()) script_.namedStringSearchPaths.push_back(trim(text));
    } else if (s.name.find("shader") != std::string::npos) shader(s);
    else if (s.name == "vertex program" || s.name == "fragment program") arbProgram(s);
    else if (s.name == "vertex data") vertexData(s);
    else if (s.name == "indices") indices(s);
    else if (s.name == "comment") continue;
    else if (s.name != "test" && s.name != "test init") unsupported(s.header, "[" + s.name + "] section");
  }
  // A piglit program without a vertex shader runs OpenGL's fixed-function vertex stage, which
  // passes the vertex on through matrices that are the identity unless a command sets them:
  // the pass-through vertex shader does the same.
  const auto hasStage = [&](Stage stage) {
    return std::any_of(script_.shaders.begin(), script_.shaders.end(), [&](const Shader& s) { return s.stage == stage; });
  };
  if (script_.hasArbPrograms()) {
    arbFixedFunction();
  } else if (piglit_ && hasStage(Stage::Fragment) && !hasStage(Stage::Vertex)) {
    Shader vertex;
    vertex.stage = Stage::Vertex;
    vertex.name = "vertex";
    vertex.passthrough = true;
    script_.shaders.insert(script_.shaders.begin(), vertex);
  }
  // One without a fragment shader runs the fixed-function fragment stage: the primary colour,
  // untextured.
  if (piglit_ && hasStage(Stage::Vertex) && !hasStage(Stage::Fragment) && !hasStage(Stage::Compute)) {
    Shader fragment;
    fragment.stage = Stage::Fragment;
    fragment.name = "fragment";
    fragment.format = "GLSL";
    fragment.openGl = true;
    fragment.glslVersion = glslVersion_;
    // GLSL 1.40 and later have no gl_Color; what their vertex shaders leave to the fixed-function
    // fragment stage is undefined, white here.
    fragment.source = glslVersion_ < 140 ? "void main() { gl_FragColor = gl_Color; }\n"
                                         : "#version 140\nout vec4 parity_FragColor;\nvoid main() { parity_FragColor = vec4(1.0); }\n";
    script_.shaders.push_back(fragment);
  }
  declareFramebuffer();
  for (Pipeline& p : script_.pipelines)
    for (const auto& [shader, values] : specializations_)
      if (std::find(p.shaders.begin(), p.shaders.end(), shader) != p.shaders.end()) p.specializations[shader] = values;
  if (piglit_) {  // OpenGL's initial GL_PATCH_VERTICES
    patchVertices_ = 3;
    for (Pipeline& p : script_.pipelines) p.patchControlPoints = patchVertices_;
  }
  // VkRunner's animation examples: [test init] runs once before the frames, [test] each frame.
  // A run here is one frame, the first (frame_num below).
  for (const Section& s : sections_)
    if (s.name == "test init" || s.name == "test") {
      loadCompatibilityMatrices(s.header, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
      break;
    }
  for (const std::string section : {"test init", "test"})
    for (const Section& s : sections_)
      if (s.name == section) test(s);
  return std::move(script_);
}

// [shader include]: the named string's path on the first line, its text after it.
void ShaderTestParser::namedString(const Section& s) {
  std::string path, text;
  for (const auto& [line, content] : s.lines) {
    if (path.empty()) {
      path = trim(content);
      if (!path.empty() && path[0] != '/') error(line, "a named string's path starts with '/', got '" + path + "'");
      continue;
    }
    text += content + "\n";
  }
  if (path.empty()) error(s.header, "[shader include] needs the named string's path on its first line");
  script_.namedStrings.push_back({path, text});
}

// An ARB assembly program runs with OpenGL's fixed-function processing in the stage the file
// leaves without one; an assembly program of what that stage does with piglit's state stands in:
// the vertex transformed by the matrices, its colours and texture coordinates passed on (no
// lighting, fog or texture generation, which no command here turns on), and the fragment's
// primary colour (no texturing is enabled). A GLSL shader beside one is not run.
void ShaderTestParser::arbFixedFunction() {
  for (const Shader& s : script_.shaders)
    if (s.format != "ARB") unsupported(s.loc.line, "an ARB assembly program beside a GLSL shader");
  auto standIn = [&](Stage stage, const char* name, const char* source) {
    if (script_.findShader(name)) return;
    Shader s;
    s.stage = stage;
    s.name = name;
    s.format = "ARB";
    s.source = source;
    script_.shaders.insert(stage == Stage::Vertex ? script_.shaders.begin() : script_.shaders.end(), s);
  };
  standIn(Stage::Vertex, "vertex",
          "!!ARBvp1.0\nOPTION ARB_position_invariant;\nMOV result.color, vertex.color;\n"
          "MOV result.color.secondary, vertex.color.secondary;\nMOV result.texcoord[0], vertex.texcoord[0];\n"
          "MOV result.texcoord[1], vertex.texcoord[1];\nMOV result.texcoord[2], vertex.texcoord[2];\n"
          "MOV result.texcoord[3], vertex.texcoord[3];\nMOV result.texcoord[4], vertex.texcoord[4];\n"
          "MOV result.texcoord[5], vertex.texcoord[5];\nMOV result.texcoord[6], vertex.texcoord[6];\n"
          "MOV result.texcoord[7], vertex.texcoord[7];\nEND\n");
  standIn(Stage::Fragment, "fragment", "!!ARBfp1.0\nMOV result.color, fragment.color;\nEND\n");
}

void ShaderTestParser::loadCompatibilityMatrices(int line, const std::array<double, 16>& projection) {
  if (script_.hasArbPrograms()) {  // OpenGL's own matrices (rhi::Device::setTransformMatrices)
    Command c;
    c.kind = Command::Kind::LoadProjection;
    c.loc = {line, 1};
    for (double e : projection) c.values.push_back(Value{.d = e});
    script_.commands.push_back(c);
  }
  static constexpr std::array<double, 16> kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  for (const CompatibilityMatrix& m : kCompatibilityMatrices) {
    const std::regex read(std::string("\\b") + m.builtIn + "\\b" + (m.builtIn == std::string("gl_ModelViewProjectionMatrix") ? "|\\bftransform\\s*\\(" : ""));
    if (std::none_of(script_.shaders.begin(), script_.shaders.end(), [&](const Shader& shader) { return std::regex_search(shader.source, read); }))
      continue;
    const std::string name = m.uniform;
    // The model-view is the identity, so the model-view-projection is the projection.
    const std::array<double, 16>& value = name == "parity_ModelViewMatrix" || name == "parity_NormalMatrix" ? kIdentity : projection;
    std::vector<std::string> w = {"uniform", m.type, m.uniform};
    for (int column = 0; column < (std::string(m.type) == "mat3" ? 3 : 4); ++column)
      for (int row = 0; row < (std::string(m.type) == "mat3" ? 3 : 4); ++row) {
        std::ostringstream number;
        number.precision(17);
        number << value[static_cast<size_t>(column * 4 + row)];
        w.push_back(number.str());
      }
    setUniform(line, w);
  }
}

void ShaderTestParser::loadClipPlane(int line, size_t plane) {
  static const std::regex kClipVertex(R"(\bgl_ClipVertex\b)");
  if (std::none_of(script_.shaders.begin(), script_.shaders.end(), [](const Shader& shader) { return std::regex_search(shader.source, kClipVertex); }))
    return;
  std::vector<std::string> w = {"uniform", "vec4", std::string(kClipPlaneUniform) + "[" + std::to_string(plane) + "]"};
  for (double c : clipPlanes_[plane]) {
    std::ostringstream number;
    number.precision(17);
    number << (clipPlaneEnabled_[plane] ? c : 0.0);
    w.push_back(number.str());
  }
  setUniform(line, w);
}

// The shaders are compiled once for a test: state they depend on is set before its first draw.
void ShaderTestParser::fixedFunctionBeforeDraw(int line, bool& state, bool value) {
  if (drawn_ && state != value) unsupported(line, "fixed-function state changed after the first draw (one pipeline state per test)");
  else state = value;
}

// glHint's targets (core and compatibility) and modes. A hint only asks: OpenGL lets an
// implementation ignore it, and Vulkan has no such state, so it reaches no device; the run
// notes it, so that a result that may depend on it says so.
void ShaderTestParser::hint(int line, const std::vector<std::string>& w) {
  static const std::set<std::string> kTargets = {
      "GL_LINE_SMOOTH_HINT", "GL_POLYGON_SMOOTH_HINT", "GL_TEXTURE_COMPRESSION_HINT", "GL_FRAGMENT_SHADER_DERIVATIVE_HINT",
      "GL_PERSPECTIVE_CORRECTION_HINT", "GL_POINT_SMOOTH_HINT", "GL_FOG_HINT", "GL_GENERATE_MIPMAP_HINT"};
  static const std::set<std::string> kModes = {"GL_FASTEST", "GL_NICEST", "GL_DONT_CARE"};
  if (w.size() != 3) error(line, "expected hint TARGET MODE");
  if (!kTargets.count(w[1])) error(line, "unknown hint target '" + w[1] + "'");
  if (!kModes.count(w[2])) error(line, "unknown hint mode '" + w[2] + "'");
  Command c;
  c.kind = Command::Kind::Hint;
  c.loc = {line, 1};
  c.other = w[1] + " " + w[2];
  script_.commands.push_back(c);
}

void ShaderTestParser::test(const Section& s) {
  for (const auto& [line, text] : s.lines) {
    std::string command = uncommented(text);
    // piglit reads numbers with strtod and strtol, which stop at a trailing ';' ("uniform float i 1.0;").
    if (piglit_)
      while (!command.empty() && (command.back() == ';' || std::isspace(static_cast<unsigned char>(command.back())))) command.pop_back();
    std::vector<std::string> w = words(command);
    if (w.empty()) continue;
    const std::string& k = w[0];
    if (k == "clear" && w.size() == 1) {
      script_.commands.push_back(clearCommand(line, Command::Kind::Clear));
    } else if (k == "clear" && w[1] == "color") {
      std::vector<Value> v = numbers(line, w, 2);
      if (v.size() != 4) error(line, "clear color needs r g b a");
      clearValue(line, Command::Kind::ClearColor, v);
    } else if (k == "clear" && (w[1] == "depth" || w[1] == "stencil")) {
      std::vector<Value> v = numbers(line, w, 2);
      if (v.size() != 1) error(line, "clear " + w[1] + " needs one value");
      clearValue(line, w[1] == "depth" ? Command::Kind::ClearDepth : Command::Kind::ClearStencil, v);
    } else if (k == "draw" && w.size() >= 2 && (w[1] == "rect" || w[1] == "arrays" || (w[1] == "instanced" && w.size() > 2 && w[2] == "rect"))) {
      draw(line, w);
    } else if (k == "compute") {
      std::vector<Value> v = numbers(line, w, 1);
      if (v.size() != 3) error(line, "compute needs x y z");
      if (!pipeline("compute")) error(line, "compute without a [compute shader]");
      Command c;
      c.kind = Command::Kind::Compute;
      c.loc = {line, 1};
      c.pipeline = propertiesPipeline(line, "compute", "", false);
      if (piglit_) c.samplerStates = script_.samplers;  // texture parameters as at this dispatch
      for (int i = 0; i < 3; ++i) c.groups[i] = static_cast<uint32_t>(v[size_t(i)].i);
      script_.commands.push_back(c);
    } else if (k == "atomic" && w.size() >= 2 && (w[1] == "counters" || w[1] == "counter") && piglit_) {
      atomicCounters(line, w);
    } else if (k == "probe" && w.size() >= 3 && w[1] == "atomic" && w[2] == "counter") {
      probeAtomicCounter(line, w);
    } else if (k == "probe" && w.size() >= 2 && w[1] == "ssbo") {
      probeBuffer(line, w);
    } else if (k == "probe") {
      probe(line, w, 1, false);
    } else if (k == "relative" && w.size() >= 2 && w[1] == "probe") {
      probe(line, w, 2, true);
    } else if (k == "tolerance") {
      tolerances_.clear();
      for (size_t i = 1; i < w.size(); ++i) {
        std::string x = w[i];
        bool percent = !x.empty() && x.back() == '%';
        if (percent) x.pop_back();
        Value v;
        if (!parseNumber(x, &v)) error(line, "expected a tolerance, got '" + w[i] + "'");
        tolerances_.push_back({percent ? v.d : v.d * 255.0, percent});
      }
      if (tolerances_.size() != 1 && tolerances_.size() != 4) error(line, "tolerance takes 1 or 4 values");
    } else if ((k == "ubo" || k == "ssbo" || k == "push") && w.size() >= 2 && w[1] == "layout" && !piglit_) {
      blockLayout(line, w);
    } else if (k == "uniform" && w.size() >= 2 && w[1] == "ubo") {
      if (w.size() < 3) error(line, "uniform ubo needs a binding");
      writeBuffer(line, "ubo", w[2], w, 3);
    } else if (k == "ubo" && w.size() == 4 && w[1] == "array" && w[2] == "index") {
      Value index;  // piglit: the element of an array of blocks the next `uniform` lines set
      if (!parseNumber(w[3], &index) || !index.isInteger || index.i < 0) error(line, "expected an index, got '" + w[3] + "'");
      uboArrayIndex_ = static_cast<uint32_t>(index.i);
    } else if ((k == "ubo" || k == "ssbo") && w.size() >= 3 && w[2] == "subdata") {
      writeBuffer(line, k, w[1], w, 3);
    } else if ((k == "ubo" || k == "ssbo") && w.size() == 3) {
      Value size;
      if (!parseNumber(w[2], &size) || !size.isInteger || size.i < 0) error(line, "expected a size in bytes, got '" + w[2] + "'");
      bufferFor(line, k, w[1], static_cast<uint64_t>(size.i));
    } else if (k == "push") {
      writeBuffer(line, "push", "", w, 1);
    } else if (k == "uniform" && w.size() == 3 && w[1] == "frame_num" && !piglit_) {
      // VkRunner's animation examples: the frame number as a uint push constant at byte OFFSET.
      writeBuffer(line, "push", "", {"uniform", "uint", w[2], "0"}, 1);
    } else if (k == "block" && piglit_) {
      blockPosition(line, w);
    } else if (k == "uniform" && w.size() >= 3 && spirvProgram()) {
      setBlockUniform(line, w);
    } else if (k == "verify" && w.size() >= 2 && (w[1] == "program_interface_query" || w[1] == "program_query") && spirvProgram()) {
      verifyProgramQuery(line, w);
    } else if (k == "uniform" && w.size() >= 3) {
      Value offset;
      if (parseNumber(w[2], &offset) && !piglit_) writeBuffer(line, "push", "", w, 1);  // VkRunner: push constants
      else setUniform(line, w);
    } else if (!piglit_ && (isPipelineProperty(k) || (w.size() >= 3 && (w[1] == "entrypoint" || w[2] == "entrypoint")))) {
      pipelineState(line, w);

    } else if (k == "texture" && w.size() >= 3 && (w[1] == "rgbw" || w[1] == "junk") && w[2] == "2DArray" && piglit_) {
      arrayTexture(line, w);
    } else if (k == "texture" && w.size() >= 2 && (w[1] == "rgbw" || w[1] == "checkerboard" || w[1] == "quads" || w[1] == "miptree" ||
                                                 w[1] == "shadow1D" || w[1] == "shadow1DArray" || w[1] == "shadow2D" || w[1] == "shadowRect" ||
                                                 w[1] == "shadow2DArray") && piglit_) {
      texture(line, w);
    } else if (k == "active" && w.size() == 5 && w[1] == "uniform" && piglit_) {
      activeUniform(line, w);
    } else if (k == "fb" && w.size() >= 2 && w[1] == "tex" && piglit_) {
      framebufferTexture(line, w);
    } else if (k == "texparameter" && w.size() >= 4 && piglit_) {
      texparameter(line, w);
    } else if (k == "patch" && w.size() == 4 && w[1] == "parameter" && w[2] == "vertices") {
      Value n;
      if (!parseNumber(w[3], &n) || !n.isInteger || n.i < 1) error(line, "expected a vertex count, got '" + w[3] + "'");
      // The patch size is a draw's, not the pipeline's: each draw takes the current one.
      patchVertices_ = static_cast<uint32_t>(n.i);
      if (!drawn_)
        for (Pipeline& p : script_.pipelines) p.patchControlPoints = patchVertices_;
    } else if (k == "patch" && w.size() >= 5 && w[1] == "parameter" && w[2] == "default" && w[3] == "level" &&
               (w[4] == "outer" || w[4] == "inner")) {
      const bool outer = w[4] == "outer";
      std::vector<Value> v = numbers(line, w, 5);
      if (v.size() != (outer ? 4u : 2u)) error(line, std::string("patch parameter default level ") + w[4] + " takes " + (outer ? "4" : "2") + " levels");
      if (drawn_) {
        unsupported(line, "patch parameter default level after the first draw (one pipeline state per test)");
      } else {
        for (Pipeline& p : script_.pipelines)
          for (size_t i = 0; i < v.size(); ++i) p.defaultTessLevels[(outer ? 0 : 4) + i] = static_cast<float>(v[i].d);
      }
    } else if ((k == "enable" || k == "disable") && w.size() == 2 && piglit_ && isClipDistance(w[1])) {
      // The RHI clips by every clip distance the shaders write, as Vulkan does: enabling one is
      // what OpenGL needs to do the same, and a written distance left disabled clips here. A
      // user clip plane clips a shader writing gl_ClipVertex while it is enabled.
      const size_t plane = static_cast<size_t>(w[1].back() - '0');
      clipPlaneEnabled_[plane] = k == "enable";
      loadClipPlane(line, plane);
    } else if (k == "clip" && w.size() == 7 && w[1] == "plane" && piglit_) {
      std::vector<Value> v = numbers(line, w, 3);
      const int plane = std::atoi(w[2].c_str());
      if (w[2].find_first_not_of("0123456789") != std::string::npos || plane > 7) error(line, "clip plane takes a plane 0..7, got '" + w[2] + "'");
      for (size_t i = 0; i < 4; ++i) clipPlanes_[static_cast<size_t>(plane)][i] = v[i].d;
      loadClipPlane(line, static_cast<size_t>(plane));
    } else if (k == "hint" && piglit_) {
      hint(line, w);
    } else if ((k == "enable" || k == "disable") && w.size() == 2 && w[1] == "GL_VERTEX_PROGRAM_TWO_SIDE" && piglit_) {
      fixedFunctionBeforeDraw(line, script_.fixedFunction.twoSidedColor, k == "enable");
    } else if (k == "shade" && w.size() == 3 && w[1] == "model" && (w[2] == "flat" || w[2] == "smooth") && piglit_) {
      fixedFunctionBeforeDraw(line, script_.fixedFunction.flatShading, w[2] == "flat");
    } else if (k == "frustum" && piglit_) {
      // piglit's glFrustum(left, right, bottom, top, near, far) into the projection.
      std::vector<Value> v = numbers(line, w, 1);
      if (v.size() != 6) error(line, "frustum takes left right bottom top near far");
      const double l = v[0].d, r = v[1].d, b = v[2].d, t = v[3].d, n = v[4].d, f = v[5].d;
      if (l == r || b == t || n == f || n <= 0 || f <= 0) error(line, "frustum with an empty range or a plane not in front of the eye");
      loadCompatibilityMatrices(line, {2 * n / (r - l), 0, 0, 0, 0, 2 * n / (t - b), 0, 0, (r + l) / (r - l), (t + b) / (t - b),
                                       -(f + n) / (f - n), -1, 0, 0, -2 * f * n / (f - n), 0});
    } else if (k == "image" && w.size() >= 3 && w[1] == "texture" && piglit_) {
      imageTexture(line, w);
    } else if (k == "ortho" && piglit_) {
      // piglit's glOrtho(left, right, bottom, top, -1, 1) into the projection: the window's
      // pixels unless the four are given.
      std::vector<Value> v = numbers(line, w, 1);
      if (!v.empty() && v.size() != 4) error(line, "ortho takes left right bottom top, or nothing");
      const double l = v.empty() ? 0 : v[0].d, r = v.empty() ? width_ : v[1].d, b = v.empty() ? 0 : v[2].d, t = v.empty() ? height_ : v[3].d;
      if (l == r || b == t) error(line, "ortho with an empty range");
      loadCompatibilityMatrices(line, {2 / (r - l), 0, 0, 0, 0, 2 / (t - b), 0, 0, 0, 0, -1, 0, -(r + l) / (r - l), -(t + b) / (t - b), 0, 1});
    } else if (k == "parameter" && piglit_) {
      // parameter env_vp|local_vp|env_fp|local_fp INDEX (x, y, z, w): an ARB assembly program's.
      static const std::set<std::string> kKinds = {"env_vp", "local_vp", "env_fp", "local_fp"};
      if (w.size() < 2 || !kKinds.count(w[1])) error(line, "parameter takes env_vp, local_vp, env_fp or local_fp");
      std::vector<Value> v = numbers(line, w, 2);
      if (v.size() != 5 || !v[0].isInteger || v[0].i < 0) error(line, "parameter " + w[1] + " takes an index and (x, y, z, w)");
      Command c;
      c.kind = Command::Kind::ProgramParameter;
      c.loc = {line, 1};
      c.other = w[1];
      c.px = static_cast<uint32_t>(v[0].i);
      c.values.assign(v.begin() + 1, v.end());
      script_.commands.push_back(c);
    } else if ((k == "color" || k == "texcoord") && script_.hasArbPrograms()) {
      // color r g b a | texcoord N (x, y, z, w): glColor4f, glMultiTexCoord4f.
      std::vector<Value> v = numbers(line, w, 1);
      const bool texcoord = k == "texcoord";
      if (v.size() != (texcoord ? 5u : 4u) || (texcoord && (!v[0].isInteger || v[0].i < 0 || v[0].i > 7)))
        error(line, texcoord ? "texcoord takes a unit 0..7 and (x, y, z, w)" : "color takes r g b a");
      Command c;
      c.kind = Command::Kind::CurrentAttribute;
      c.loc = {line, 1};
      c.other = k;
      c.px = texcoord ? static_cast<uint32_t>(v[0].i) : 0;
      c.values.assign(v.begin() + (texcoord ? 1 : 0), v.end());
      script_.commands.push_back(c);
    } else if (k == "link" && w.size() == 2 && (w[1] == "success" || w[1] == "error")) {
      // One program in piglit: here the graphics pipeline of the current framebuffer and the
      // compute pipeline, whichever the shaders make.
      for (const std::string base : {"rect", "compute"}) {
        const Pipeline* p = pipeline(base);
        if (!p || p->shaders.empty()) continue;
        Command c;
        c.kind = Command::Kind::ExpectLink;
        c.linkError = w[1] == "error";
        c.loc = {line, 1};
        c.pipeline = base == "rect" ? framebufferPipeline(base) : base;
        script_.commands.push_back(c);
      }
    } else if (k == "memory" && w.size() >= 2 && w[1] == "barrier") {
      // Every RHI command sees the writes of the commands before it.
    } else {
      std::string what = k;
      if (w.size() >= 2 && std::islower(static_cast<unsigned char>(w[1][0])) && !std::isdigit(static_cast<unsigned char>(w[1][0])))
        what += " " + w[1];
      unsupported(line, what);
    }
  }
}

}  // namespace parity::harness::script::shader_test

namespace parity::harness::script {

bool isShaderTestPath(const std::string& path) {
  const std::string suffix = ".shader_test";
  return path.size() >= suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
}

ParseResult parseShaderTest(const std::string& text, const std::string& name) {
  ParseResult r;
  try {
    shader_test::ShaderTestParser p(text, name);
    r.script = p.run();
    r.ok = true;
  } catch (const shader_test::ShaderTestError& e) {
    r.error = name + ":" + std::to_string(e.line) + ": error: " + e.message;
  }
  return r;
}

}  // namespace parity::harness::script
