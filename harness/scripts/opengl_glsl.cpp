#include "harness/scripts/opengl_glsl.h"

#include <algorithm>
#include <cctype>
#include <functional>
#include <map>
#include <regex>
#include <span>
#include <set>
#include <sstream>
#include <vector>

namespace parity::harness::script {

namespace {

// The GLSL version in which each extension became core (OpenGL 4.5 core profile, appendix of
// each version's GLSL specification).
int coreVersion(const std::string& extension) {
  static const std::map<std::string, int> kCore = {
      {"GL_ARB_texture_rectangle", 140},         {"GL_ARB_uniform_buffer_object", 140},
      {"GL_ARB_explicit_attrib_location", 330},  {"GL_ARB_shader_bit_encoding", 330},
      {"GL_ARB_gpu_shader5", 400},               {"GL_ARB_gpu_shader_fp64", 400},
      {"GL_ARB_tessellation_shader", 400},       {"GL_ARB_texture_query_lod", 400},
      {"GL_ARB_sample_shading", 400},            {"GL_ARB_texture_cube_map_array", 400},
      {"GL_ARB_texture_gather", 400},            {"GL_ARB_shader_subroutine", 400},
      {"GL_ARB_separate_shader_objects", 410},   {"GL_ARB_vertex_attrib_64bit", 410},
      {"GL_ARB_viewport_array", 410},            {"GL_ARB_shader_precision", 410},
      {"GL_ARB_shading_language_420pack", 420},
      {"GL_ARB_shader_atomic_counters", 420},    {"GL_ARB_shader_image_load_store", 420},
      {"GL_ARB_conservative_depth", 420},        {"GL_ARB_shading_language_packing", 420},
      {"GL_ARB_arrays_of_arrays", 430},          {"GL_ARB_compute_shader", 430},
      {"GL_ARB_shader_storage_buffer_object", 430}, {"GL_ARB_explicit_uniform_location", 430},
      {"GL_ARB_fragment_layer_viewport", 430},   {"GL_ARB_shader_image_size", 430},
      {"GL_ARB_texture_query_levels", 430},      {"GL_ARB_enhanced_layouts", 440},
      {"GL_ARB_cull_distance", 450},             {"GL_ARB_derivative_control", 450},
      {"GL_ARB_shader_texture_image_samples", 450},
      // mix() of ints, uints and bools selected by bools, core in 4.50.
      {"GL_EXT_shader_integer_mix", 450},
      // Its *GradARB functions are textureGrad() and textureProjGrad() from 1.30 on (spelled anew below).
      {"GL_ARB_shader_texture_lod", 130},
      // GLSL 4.00's integer functions and implicit int-to-uint conversions, brought to 1.30.
      {"GL_MESA_shader_integer_functions", 400}};
  auto it = kCore.find(extension);
  return it == kCore.end() ? 0 : it->second;
}

// OpenGL extensions the port enables under another name that glslang knows for the same
// language (glslangName), or from the version glslang declares their built-ins in.
struct GlslangSpelling {
  const char* extension;
  const char* glslangName;  // nullptr: the same name
  int minimumVersion;       // 0: any
  const char* alsoEnable;   // a second extension glslang needs for the same built-ins
};
constexpr GlslangSpelling kGlslangSpellings[] = {
    // min3, max3 and mid3, declared from 4.30 on.
    {"GL_AMD_shader_trinary_minmax", nullptr, 430, nullptr},
    // 64-bit integer types, their implicit conversions and built-in overloads (glslang's ARB
    // spelling lacks sign(), min(), max() and clamp() of them), declared from 4.50 on.
    {"GL_ARB_gpu_shader_int64", "GL_EXT_shader_explicit_arithmetic_types_int64", 450, nullptr},
    // The layout qualifiers of gl_FragDepth (depth_any, depth_greater, ...) that ARB made core in 4.20.
    {"GL_AMD_conservative_depth", "GL_ARB_conservative_depth", 0, nullptr},
    // atomicAdd and atomicExchange of floats in buffers and shared memory.
    {"GL_NV_shader_atomic_float", "GL_EXT_shader_atomic_float", 450, nullptr},
    // atomicMin and atomicMax of floats, declared with float atomics from 4.50 on.
    {"GL_INTEL_shader_atomic_float_minmax", "GL_EXT_shader_atomic_float2", 450, "GL_EXT_shader_atomic_float"},
};

// GL_ARB_shader_group_vote's and GL_ARB_shader_ballot's built-ins under their
// GL_KHR_shader_subgroup names. glslang spells the ARB ones with SPV_KHR_subgroup_vote and
// SPV_KHR_shader_ballot, which Vulkan drivers (lavapipe among them) need not offer; the KHR ones
// are Vulkan 1.1's core subgroup operations. ARB's group is the subgroup; its 64-bit masks are the
// low two words of the KHR uvec4 masks (no subgroup has more than 64 invocations where the ARB
// extension is offered).
struct SubgroupSpelling {
  const char* extension;
  const char* subgroupExtensions;  // enabled in the port
  std::vector<std::pair<const char*, const char*>> names;  // ARB name, its KHR form (a macro body)
};
const std::vector<SubgroupSpelling>& subgroupSpellings() {
  static const std::vector<SubgroupSpelling> kSpellings = {
      {"GL_ARB_shader_group_vote",
       "GL_KHR_shader_subgroup_vote",
       {{"anyInvocationARB", "subgroupAny"}, {"allInvocationsARB", "subgroupAll"}, {"allInvocationsEqualARB", "subgroupAllEqual"}}},
      {"GL_ARB_shader_ballot",
       "GL_KHR_shader_subgroup_ballot",
       {{"readFirstInvocationARB", "subgroupBroadcastFirst"},
        {"readInvocationARB", "subgroupBroadcast"},
        {"ballotARB(value)", "packUint2x32(subgroupBallot(value).xy)"},
        {"gl_SubGroupSizeARB", "gl_SubgroupSize"},
        {"gl_SubGroupInvocationARB", "gl_SubgroupInvocationID"},
        {"gl_SubGroupEqMaskARB", "packUint2x32(gl_SubgroupEqMask.xy)"},
        {"gl_SubGroupGeMaskARB", "packUint2x32(gl_SubgroupGeMask.xy)"},
        {"gl_SubGroupGtMaskARB", "packUint2x32(gl_SubgroupGtMask.xy)"},
        {"gl_SubGroupLeMaskARB", "packUint2x32(gl_SubgroupLeMask.xy)"},
        {"gl_SubGroupLtMaskARB", "packUint2x32(gl_SubgroupLtMask.xy)"}}}};
  return kSpellings;
}

int glslangMinimumVersion(const std::string& extension) {
  for (const GlslangSpelling& g : kGlslangSpellings)
    if (extension == (g.glslangName ? g.glslangName : g.extension)) return g.minimumVersion;
  return 0;
}

std::string replaceWord(const std::string& text, const std::string& word, const std::string& with) {
  return std::regex_replace(text, std::regex("\\b" + word + "\\b"), with);
}

// Joins lines ending in a backslash (a continuation GLSL only allows from 4.20, which Mesa and so
// piglit's shaders use in every version), keeping the line count: the removed line breaks
// follow the joined line.
std::string joinContinuedLines(const std::string& text) {
  std::string out;
  int pending = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\\' && i + 1 < text.size() && text[i + 1] == '\n') {
      ++pending;
      ++i;
      continue;
    }
    out += text[i];
    if (text[i] == '\n') out.append(static_cast<size_t>(pending), '\n'), pending = 0;
  }
  return out;
}

const std::regex& shadowCall() {
  static const std::regex kCall(R"(\bshadow(1D|2D|2DRect)(Array|Proj|Lod|ProjLod)?(GradARB)?\s*\()");
  return kCall;
}

// GL_ARB_shader_texture_lod's sampler functions as their GLSL 1.30 forms, and the compatibility
// profile's shadow functions with the depth texture mode (prepareOpenGlGlsl's comment).
std::string textureFunctions(const std::string& source) {
  std::string out;
  static const std::pair<const char*, const char*> kLod[] = {
      {"texture1DGradARB", "textureGrad"},         {"texture2DGradARB", "textureGrad"},
      {"texture3DGradARB", "textureGrad"},         {"textureCubeGradARB", "textureGrad"},
      {"texture1DProjGradARB", "textureProjGrad"}, {"texture2DProjGradARB", "textureProjGrad"},
      {"texture3DProjGradARB", "textureProjGrad"}};
  // GLSL 1.10's sampler functions (and GL_EXT_texture_array's), which GLSL 1.30 made overloads of
  // texture(), textureProj() and textureLod(). glslang's Vulkan rules read texture1D, texture2D,
  // texture3D, textureCube and texture2DArray as the names of Vulkan's texture types, so a call
  // of one is a constructor it refuses.
  static const std::pair<const char*, const char*> kLegacy[] = {
      {"texture1D", "texture"},          {"texture1DProj", "textureProj"},   {"texture1DLod", "textureLod"},
      {"texture1DProjLod", "textureProjLod"}, {"texture2D", "texture"},       {"texture2DProj", "textureProj"},
      {"texture2DLod", "textureLod"},    {"texture2DProjLod", "textureProjLod"}, {"texture3D", "texture"},
      {"texture3DProj", "textureProj"},  {"texture3DLod", "textureLod"},     {"texture3DProjLod", "textureProjLod"},
      {"textureCube", "texture"},        {"textureCubeLod", "textureLod"},   {"texture1DArray", "texture"},
      {"texture2DArray", "texture"},     {"texture1DArrayLod", "textureLod"}, {"texture2DArrayLod", "textureLod"}};
  using Names = std::span<const std::pair<const char*, const char*>>;
  for (Names table : {Names(kLod), Names(kLegacy)})
    for (const auto& [old, core] : table)
      if (std::regex_search(source, std::regex(std::string("\\b") + old + "\\s*\\(")))
        out += std::string("#define ") + old + " " + core + "\n";
  const std::vector<std::string> samplers = depthModeSamplers(source);
  if (samplers.empty()) return out;
  out += "vec4 parity_depth_texture_mode(float r, int mode) {\n"
         "  return mode == 1 ? vec4(r) : mode == 2 ? vec4(0.0, 0.0, 0.0, r) : mode == 3 ? vec4(r, 0.0, 0.0, 1.0) : vec4(r, r, r, 1.0);\n"
         "}\n";
  for (const std::string& sampler : samplers) out += "uniform int " + depthModeUniform(sampler) + ";\n";
  const std::string mode = "parity_depth_mode_##s";
  // GLSL 1.30's forms of GLSL 1.10's shadow functions (a 1D lookup reads p.x and compares p.z).
  out += "#define shadow1D(s, p) parity_depth_texture_mode(texture(s, (p).xyz), " + mode + ")\n";
  out += "#define shadow1DProj(s, p) parity_depth_texture_mode(textureProj(s, p), " + mode + ")\n";
  out += "#define shadow1DLod(s, p, lod) parity_depth_texture_mode(textureLod(s, (p).xyz, lod), " + mode + ")\n";
  out += "#define shadow1DProjLod(s, p, lod) parity_depth_texture_mode(textureProjLod(s, p, lod), " + mode + ")\n";
  out += "#define shadow2D(s, p) parity_depth_texture_mode(texture(s, (p).xyz), " + mode + ")\n";
  out += "#define shadow2DProj(s, p) parity_depth_texture_mode(textureProj(s, p), " + mode + ")\n";
  out += "#define shadow2DLod(s, p, lod) parity_depth_texture_mode(textureLod(s, (p).xyz, lod), " + mode + ")\n";
  out += "#define shadow2DProjLod(s, p, lod) parity_depth_texture_mode(textureProjLod(s, p, lod), " + mode + ")\n";
  out += "#define shadow2DRectProj(s, p) parity_depth_texture_mode(texture(s, vec3((p).xy / (p).w / vec2(textureSize(s, 0)), (p).z / (p).w)), " +
         mode + ")\n";
  out += "#define shadow2DGradARB(s, p, dx, dy) parity_depth_texture_mode(textureGrad(s, (p).xyz, dx, dy), " + mode + ")\n";
  out += "#define shadow2DArray(s, p) parity_depth_texture_mode(texture(s, p), " + mode + ")\n";
  out += "#define shadow1DArray(s, p) parity_depth_texture_mode(texture(s, p), " + mode + ")\n";
  out += "#define shadow2DRect(s, p) parity_depth_texture_mode(texture(s, vec3((p).xy / vec2(textureSize(s, 0)), (p).z)), " + mode + ")\n";
  out += "#define shadow2DRectGradARB(s, p, dx, dy) parity_depth_texture_mode(textureGrad(s, vec3((p).xy / vec2(textureSize(s, 0)), (p).z), "
         "(dx) / vec2(textureSize(s, 0)), (dy) / vec2(textureSize(s, 0))), " + mode + ")\n";
  return out;
}

// The compatibility profile's colour and texture-coordinate varyings, matched by name like any
// other varying. A shader may redeclare a colour with an interpolation qualifier (`flat out vec4
// gl_FrontColor;`); one it leaves unqualified is flat under glShadeModel(GL_FLAT). The fragment
// shader's gl_Color and gl_SecondaryColor are the front values, or, under two-sided colour, the
// back ones on back faces: so a vertex shader writing either of a pair declares both.
void compatibilityVaryings(OpenGlGlsl& out, Stage stage, const FixedFunctionState& fixedFunction) {
  auto uses = [&](const std::string& name) { return std::regex_search(out.source, std::regex("\\b" + name + "\\b")); };
  // Removes a redeclaration of `builtIn` and returns its qualifiers (or the shade model's).
  auto qualifiers = [&](const std::string& builtIn) {
    static const std::regex kInterpolation(R"(\b(?:flat|smooth|noperspective|centroid|sample)\b)");
    const std::regex redeclaration(R"(((?:\w+[ \t]+)*)(?:in|out|varying)[ \t]+vec4[ \t]+)" + builtIn + R"([ \t]*;)");
    std::smatch m;
    std::string found;
    if (std::regex_search(out.source, m, redeclaration)) {
      const std::string words = m[1];
      for (auto it = std::sregex_iterator(words.begin(), words.end(), kInterpolation); it != std::sregex_iterator(); ++it)
        found += it->str() + " ";
      out.source.replace(static_cast<size_t>(m.position()), static_cast<size_t>(m.length()), "");
    }
    if (found.empty() && fixedFunction.flatShading) found = "flat ";
    return found;
  };
  struct Pair {
    const char* front;  // vertex built-ins
    const char* back;
    const char* read;   // the fragment built-in
  };
  static const Pair kPairs[] = {{"gl_FrontColor", "gl_BackColor", "gl_Color"},
                                {"gl_FrontSecondaryColor", "gl_BackSecondaryColor", "gl_SecondaryColor"}};
  auto renamed = [](const std::string& builtIn) { return "parity_" + builtIn.substr(3); };
  for (const Pair& pair : kPairs) {
    if (stage == Stage::Vertex && (uses(pair.front) || uses(pair.back))) {
      for (const std::string builtIn : {pair.front, pair.back}) {
        out.declarations += qualifiers(builtIn) + "out vec4 " + renamed(builtIn) + ";\n";
        out.source = replaceWord(out.source, builtIn, renamed(builtIn));
      }
    } else if (stage == Stage::Fragment && uses(pair.read)) {
      const std::string q = qualifiers(pair.read), front = renamed(pair.front), back = renamed(pair.back);
      out.declarations += q + "in vec4 " + front + ";\n";
      if (fixedFunction.twoSidedColor) out.declarations += q + "in vec4 " + back + ";\n";
      out.source = replaceWord(out.source, pair.read, fixedFunction.twoSidedColor ? "(gl_FrontFacing ? " + front + " : " + back + ")" : front);
    }
  }
  if ((stage != Stage::Vertex && stage != Stage::Fragment) || !uses("gl_TexCoord")) return;
  const bool redeclared = std::regex_search(out.source, std::regex(R"(\bvec4\s+gl_TexCoord\b)"));
  out.source = replaceWord(out.source, "gl_TexCoord", "parity_TexCoord");
  if (!redeclared)
    out.declarations += std::string(stage == Stage::Vertex ? "out" : "in") + " vec4 parity_TexCoord[8];\n";
}

}  // namespace

std::vector<std::string> depthModeSamplers(const std::string& source) {
  std::vector<std::string> names;
  if (!std::regex_search(source, shadowCall())) return names;
  static const std::regex kSampler(R"(\buniform\s+(?:\w+\s+)*sampler(?:2DRect|[12]D(?:Array)?)Shadow\s+(\w+))");
  for (auto it = std::sregex_iterator(source.begin(), source.end(), kSampler); it != std::sregex_iterator(); ++it)
    names.push_back((*it)[1]);
  return names;
}

bool portsExtension(const std::string& extension) {
  return std::any_of(std::begin(kGlslangSpellings), std::end(kGlslangSpellings), [&](const GlslangSpelling& g) { return extension == g.extension; });
}

std::string declarationsOnly(const std::string& source) {
  // Comments become spaces (line breaks kept), so that braces and parentheses in them do not count.
  std::string text = source;
  for (size_t i = 0; i + 1 < text.size(); ++i) {
    if (text[i] == '/' && text[i + 1] == '/') {
      for (; i < text.size() && text[i] != '\n'; ++i) text[i] = ' ';
    } else if (text[i] == '/' && text[i + 1] == '*') {
      size_t end = text.find("*/", i + 2);
      end = end == std::string::npos ? text.size() : end + 2;
      for (; i < end; ++i)
        if (text[i] != '\n') text[i] = ' ';
      --i;
    }
  }
  static const std::regex kMain(R"(\bvoid\s+main\s*\(\s*(void\s*)?\)\s*\{)");
  const bool definesMain = std::regex_search(text, kMain);
  // A body is a brace at depth 0 right after a closing parenthesis: blocks and structs follow a
  // name, initialisers end in ';'. It becomes ';' (its line breaks kept).
  std::string out;
  int depth = 0;
  char lastSignificant = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (depth == 0 && ch == '{' && lastSignificant == ')') {
      int inner = 0;
      size_t j = i;
      for (; j < text.size(); ++j) {
        if (text[j] == '{') ++inner;
        if (text[j] == '}' && --inner == 0) break;
      }
      out += ';';
      out += std::string(static_cast<size_t>(std::count(text.begin() + static_cast<long>(i), text.begin() + static_cast<long>(std::min(j, text.size())), '\n')), '\n');
      i = j;
      lastSignificant = ';';
      continue;
    }
    if (ch == '{') ++depth;
    if (ch == '}') --depth;
    if (!std::isspace(static_cast<unsigned char>(ch))) lastSignificant = ch;
    out += ch;
  }
  return definesMain ? out + "void main() {}\n" : out;
}

int openGlGlslVersion(const std::string& source, int defaultVersion) {
  static const std::regex kVersion(R"(#[ \t]*version[ \t]+(\d+))");
  std::smatch m;
  return std::regex_search(source, m, kVersion) ? std::stoi(m[1]) : defaultVersion;
}

OpenGlGlsl nativeOpenGlGlsl(const std::string& source, Stage stage, int defaultVersion) {
  OpenGlGlsl out;
  out.source = source;
  auto uses = [&](const std::string& name) { return std::regex_search(source, std::regex("\\b" + name + "\\b")); };
  const bool ftransform = std::regex_search(source, std::regex(R"(\bftransform\s*\()"));
  for (const CompatibilityMatrix& m : kCompatibilityMatrices) {
    const bool mvp = std::string(m.builtIn) == "gl_ModelViewProjectionMatrix";
    if (!uses(m.builtIn) && !(mvp && ftransform)) continue;
    out.declarations += std::string("uniform ") + m.type + " " + m.uniform + ";\n";
    if (uses(m.builtIn)) out.declarations += std::string("#define ") + m.builtIn + " " + m.uniform + "\n";
  }
  if (stage != Stage::Vertex) return out;
  const std::string input = openGlGlslVersion(source, defaultVersion) < 130 ? "attribute" : "in";
  const bool vertex = openGlGlslVersion(source, defaultVersion) < 140 && (uses("gl_Vertex") || ftransform);
  if (vertex) out.declarations += input + " vec4 parity_Vertex;\n";
  if (ftransform)
    out.declarations += std::string("#define ftransform() (parity_ModelViewProjectionMatrix * ") + (vertex ? "parity_Vertex" : "gl_Vertex") + ")\n";
  if (vertex && uses("gl_Vertex")) out.declarations += "#define gl_Vertex parity_Vertex\n";
  if (uses("gl_MultiTexCoord0")) out.declarations += input + " vec4 parity_MultiTexCoord0;\n#define gl_MultiTexCoord0 parity_MultiTexCoord0\n";
  return out;
}

// `uniform T name[] = T[](a, b, c);`: GLSL sizes the array by its initialiser, glslang (which
// drops uniform initialisers) leaves it unsized: the size is written in (3 here).
std::string sizedUniformArrays(const std::string& source) {
  static const std::regex kUnsized(R"(\buniform\s+(\w+)\s+(\w+)\s*\[\s*\]\s*=\s*(\w+)\s*\[\s*\]\s*\()");
  std::string out;
  size_t from = 0;
  for (auto it = std::sregex_iterator(source.begin(), source.end(), kUnsized); it != std::sregex_iterator(); ++it) {
    const size_t open = static_cast<size_t>(it->position() + it->length());  // just after the initialiser's '('
    int depth = 1, elements = 1;
    size_t i = open;
    for (; i < source.size() && depth > 0; ++i) {
      if (source[i] == '(') ++depth;
      else if (source[i] == ')') --depth;
      else if (source[i] == ',' && depth == 1) ++elements;
    }
    if (depth != 0) continue;
    const size_t brackets = source.find('[', static_cast<size_t>(it->position()));
    out += source.substr(from, brackets - from) + "[" + std::to_string(elements) + "]";
    from = source.find(']', brackets) + 1;
  }
  return out + source.substr(from);
}

OpenGlGlsl prepareOpenGlGlsl(const std::string& source, Stage stage, int defaultVersion, const FixedFunctionState& fixedFunction,
                             bool lastBeforeRasterisation) {
  OpenGlGlsl out;
  out.source = sizedUniformArrays(joinContinuedLines(source));
  int version = defaultVersion;
  size_t v = source.find("#version");
  size_t number = v == std::string::npos ? v : source.find_first_of("0123456789", v);
  size_t numberEnd = number == std::string::npos ? number : source.find_first_not_of("0123456789", number);
  if (number != std::string::npos) version = std::stoi(source.substr(number, numberEnd - number));
  // Extensions glslang knows by another name or from a later version (kGlslangSpellings).
  // Compiled once: every piglit shader is prepared through here.
  static const std::vector<std::regex> kDirectives = [] {
    std::vector<std::regex> out;
    for (const GlslangSpelling& g : kGlslangSpellings)
      out.emplace_back(std::string(R"(#[ \t]*extension[ \t]+)") + g.extension + R"(\b([ \t]*:[ \t]*\w+)?)");
    return out;
  }();
  for (size_t i = 0; i < std::size(kGlslangSpellings); ++i) {
    const GlslangSpelling& g = kGlslangSpellings[i];
    const std::regex& directive = kDirectives[i];
    if (!std::regex_search(out.source, directive)) continue;
    if (g.glslangName) out.source = std::regex_replace(out.source, directive, std::string("#extension ") + g.glslangName + "$1");
    if (g.alsoEnable) out.declarations += std::string("#extension ") + g.alsoEnable + " : enable\n";
  }
  for (const SubgroupSpelling& g : subgroupSpellings()) {
    if (!std::regex_search(out.source, std::regex(std::string(R"(#[ \t]*extension[ \t]+)") + g.extension + "\\b"))) continue;
    out.declarations += std::string("#extension ") + g.subgroupExtensions + " : enable\n";
    for (const auto& [name, subgroupForm] : g.names) out.declarations += std::string("#define ") + name + " " + subgroupForm + "\n";
  }
  int target = std::max(version, 140);
  static const std::regex kExtension(R"(#\s*extension\s+(GL_\w+))");
  for (auto it = std::sregex_iterator(out.source.begin(), out.source.end(), kExtension); it != std::sregex_iterator(); ++it)
    target = std::max(target, std::max(coreVersion((*it)[1]), glslangMinimumVersion((*it)[1])));
  // GLSL 1.40 declares inverse(); glslang from 1.50 on.
  static const std::regex kInverse(R"(\binverse\s*\()");
  if (version == 140 && std::regex_search(source, kInverse)) target = std::max(target, 150);
  // GL_ARB_separate_shader_objects lets an interface block take a location, which glslang only
  // allows from 4.40 (where GL_ARB_enhanced_layouts made it core).
  static const std::regex kLocatedBlock(R"(layout\s*\([^)]*\blocation\b[^)]*\)\s*(?:\w+\s+)*(?:in|out)\s+\w+\s*\{)");
  if (std::regex_search(source, kLocatedBlock)) target = std::max(target, 440);
  // The relaxed rules turn atomic counters into storage-buffer atomics, which glslang allows
  // from 4.30 (GL_ARB_shader_storage_buffer_object core).
  if (std::regex_search(source, std::regex(R"(\batomic_uint\b)"))) target = std::max(target, 430);
  // GLSL 1.50 lets a shader redeclare gl_PerVertex; glslang allows it from 4.10 (where
  // GL_ARB_separate_shader_objects brought it).
  static const std::regex kPerVertexBlock(R"(\b(in|out)\s+gl_PerVertex\b)");
  if (std::regex_search(source, kPerVertexBlock)) target = std::max(target, 410);
  // An #extension directive for what the raised version has as core is dropped (line kept
  // empty): glslang's SPIR-V path does not know the GL_ARB names and refuses `require`.
  {
    static const std::regex kDirective(R"(#[ \t]*extension[ \t]+(GL_\w+)[ \t]*:[ \t]*\w+)");
    std::string kept;
    size_t from = 0;
    for (auto it = std::sregex_iterator(out.source.begin(), out.source.end(), kDirective); it != std::sregex_iterator(); ++it) {
      const int core = coreVersion((*it)[1]);
      if (core == 0 || core > target) continue;
      kept += out.source.substr(from, static_cast<size_t>(it->position()) - from);
      from = static_cast<size_t>(it->position() + it->length());
    }
    out.source = kept + out.source.substr(from);
  }
  {
    static const std::regex kFtransform(R"(\bftransform\s*\(\s*\))");
    out.source = std::regex_replace(out.source, kFtransform, "(gl_ModelViewProjectionMatrix * gl_Vertex)");
    for (const CompatibilityMatrix& m : kCompatibilityMatrices)
      if (std::regex_search(out.source, std::regex(std::string("\\b") + m.builtIn + "\\b"))) {
        out.source = replaceWord(out.source, m.builtIn, m.uniform);
        out.declarations += std::string("uniform ") + m.type + " " + m.uniform + ";\n";
      }
  }
  // GL_ARB_draw_instanced's name for what GLSL 1.40 made core, which glslang knows by its core name.
  out.source = replaceWord(out.source, "gl_InstanceIDARB", "gl_InstanceID");
  compatibilityVaryings(out, stage, fixedFunction);
  // Statements after the shader's main, in a main of our own that calls it.
  std::string epilogue;
  static const std::regex kMain(R"(\bvoid\s+main\s*\()");
  const bool hasMain = std::regex_search(out.source, kMain);
  if (stage == Stage::Vertex && hasMain && std::regex_search(out.source, std::regex("\\bgl_ClipVertex\\b"))) {
    // The user clip planes clip by the clip vertex (eye coordinates; the model-view is the
    // identity, so the planes are as given): one clip distance a plane. A disabled plane is all
    // zeros (kClipPlaneUniform), a distance that never clips.
    out.source = replaceWord(out.source, "gl_ClipVertex", "parity_ClipVertex");
    out.declarations += "vec4 parity_ClipVertex;\nuniform vec4 " + std::string(kClipPlaneUniform) + "[8];\nout float gl_ClipDistance[8];\n";
    epilogue += "  for (int i = 0; i < 8; ++i) gl_ClipDistance[i] = dot(" + std::string(kClipPlaneUniform) + "[i], parity_ClipVertex);\n";
  }
  // OpenGL's clip volume is -w <= z <= w, the RHI's Vulkan's 0 <= z <= w: the last stage before
  // rasterisation moves z into it, which keeps OpenGL's window depth (z/w + 1) / 2.
  static const char* kDepthToZeroToOne = "gl_Position.z = (gl_Position.z + gl_Position.w) * 0.5;";
  if (lastBeforeRasterisation && stage == Stage::Geometry && std::regex_search(out.source, std::regex(R"(\bEmitVertex\s*\()"))) {
    out.source = replaceWord(out.source, "EmitVertex", "parity_EmitVertex");
    out.declarations += "void parity_EmitVertex();\n";
    out.source += std::string("\nvoid parity_EmitVertex() {\n  ") + kDepthToZeroToOne + "\n  EmitVertex();\n}\n";
  } else if (lastBeforeRasterisation && stage != Stage::Geometry && hasMain) {
    epilogue += std::string("  ") + kDepthToZeroToOne + "\n";
  }
  if (!epilogue.empty()) {
    out.source = std::regex_replace(out.source, kMain, "void parity_main(");
    out.source += "\nvoid main() {\n  parity_main();\n" + epilogue + "}\n";
  }
  if (stage == Stage::Vertex && version < 140 && std::regex_search(out.source, std::regex("\\bgl_Vertex\\b"))) {
    // GLSL before 1.40 reads the position as gl_Vertex, which is generic attribute 0.
    out.source = replaceWord(out.source, "gl_Vertex", "parity_Vertex");
    out.declarations += "in vec4 parity_Vertex;\n";
  }
  if (stage == Stage::Vertex && std::regex_search(out.source, std::regex("\\bgl_MultiTexCoord0\\b"))) {
    // The texture coordinate piglit's `draw rect tex` gives (its piglit_texcoord).
    out.source = replaceWord(out.source, "gl_MultiTexCoord0", "parity_MultiTexCoord0");
    out.declarations += "in vec4 parity_MultiTexCoord0;\n";
  }
  if (std::string functions = textureFunctions(out.source); !functions.empty()) {
    out.source = replaceWord(out.source, "sampler2DRectShadow", "sampler2DShadow");
    out.declarations += functions;
  }
  if (target >= 420) {
    // Removed from the core profile in 4.20: the 1.x interface qualifiers and outputs.
    std::string& s = out.source;
    s = replaceWord(s, "attribute", "in");
    s = replaceWord(s, "varying", stage == Stage::Vertex ? "out" : "in");
    if (stage == Stage::Fragment && std::regex_search(s, std::regex("\\bgl_FragColor\\b"))) {
      s = replaceWord(s, "gl_FragColor", "parity_FragColor");
      out.declarations += "layout(location = 0) out vec4 parity_FragColor;\n";
    }
    if (stage == Stage::Fragment && std::regex_search(s, std::regex("\\bgl_FragData\\b"))) {
      s = replaceWord(s, "gl_FragData", "parity_FragData");
      out.declarations += "layout(location = 0) out vec4 parity_FragData[4];\n";
    }
  }
  std::string line = "#version " + std::to_string(target);
  if (v == std::string::npos) {
    out.source = line + "\n" + out.source;
  } else {
    size_t eol = out.source.find('\n', out.source.find("#version"));
    size_t at = out.source.find("#version");
    out.source.replace(at, (eol == std::string::npos ? out.source.size() : eol) - at, line);
  }
  return out;
}

std::optional<std::string> glslangLimitation(const std::string& source, int firstLine, const std::string& log) {
  std::smatch m;
  // GLSL (4.00 on, and ARB_gpu_shader5 / _fp64 before) makes a built-in call with constant
  // arguments a constant expression; glslang folds only some built-ins (not fma, bitfieldReverse,
  // unpackDouble2x32, ...), so a static assertion through an array size fails to compile.
  static const std::regex kNotConstant(R"(:(\d+): error: '[^']*' : array size must be a constant integer expression)");
  if (std::regex_search(log, m, kNotConstant)) {
    std::vector<std::string> lines;
    std::istringstream in(source);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    std::set<std::string> macros;
    static const std::regex kMacro(R"(#\s*define\s+(\w+)\()");
    for (auto it = std::sregex_iterator(source.begin(), source.end(), kMacro); it != std::sregex_iterator(); ++it) macros.insert((*it)[1]);
    static const std::regex kCall(R"(\b([A-Za-z_]\w*)\s*\()");
    static const std::regex kConstructor(R"((?:[iudb]?vec[234]|d?mat[234](?:x[234])?|float|double|int|uint|bool))");
    // The statement the error names, up to its semicolon.
    std::string statement;
    for (size_t at = static_cast<size_t>(std::max(0, std::stoi(m[1]) - firstLine)); at < lines.size(); ++at) {
      statement += lines[at] + " ";
      if (lines[at].find(';') != std::string::npos) break;
    }
    std::set<std::string> builtIns;
    for (auto it = std::sregex_iterator(statement.begin(), statement.end(), kCall); it != std::sregex_iterator(); ++it)
      if (!macros.count((*it)[1]) && !std::regex_match((*it)[1].str(), kConstructor)) builtIns.insert((*it)[1]);
    if (builtIns.empty()) return std::nullopt;
    std::string names;
    for (const std::string& n : builtIns) names += (names.empty() ? "" : ", ") + n + "()";
    return names + " in a constant expression (glslang does not evaluate " + (builtIns.size() > 1 ? "these built-ins" : "this built-in") +
           " at compile time)";
  }
  // The relaxed rules lower atomic counters to storage-buffer atomics for the core functions only:
  // GL_ARB_shader_atomic_counter_ops' atomicCounterAddARB, atomicCounterOrARB, ... find no overload.
  static const std::regex kCounterOp(R"('(atomicCounter\w+)' : no matching overloaded function found)");
  if (std::regex_search(log, m, kCounterOp))
    return m[1].str() + "() of GL_ARB_shader_atomic_counter_ops (glslang's relaxed rules have no form of it for atomic counters)";
  return std::nullopt;
}

namespace {

// An initialiser as a tree: a number, or a constructor / initialiser list of initialisers.
struct Initializer {
  std::string type;  // constructor name ("vec4", "S", "float[]"); empty: a number or a {...} list
  bool number = false;
  Value value;
  std::vector<Initializer> items;
};

class InitializerReader {
 public:
  explicit InitializerReader(const std::string& text) : s_(text) {}
  // False when the text is not a literal initialiser.
  bool read(Initializer* out) { return item(out) && (skipBlanks(), at_ == s_.size()); }

 private:
  const std::string& s_;
  size_t at_ = 0;
  void skipBlanks() {
    while (at_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[at_]))) ++at_;
  }
  bool take(char c) {
    skipBlanks();
    if (at_ < s_.size() && s_[at_] == c) return ++at_, true;
    return false;
  }
  bool list(char close, Initializer* out) {
    if (take(close)) return true;
    do {
      out->items.emplace_back();
      if (!item(&out->items.back())) return false;
    } while (take(','));
    return take(close);
  }
  bool item(Initializer* out) {
    skipBlanks();
    if (take('{')) return list('}', out);
    size_t start = at_;
    while (at_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[at_])) || s_[at_] == '_' || s_[at_] == '.' ||
                               ((s_[at_] == '-' || s_[at_] == '+') && (at_ == start || s_[at_ - 1] == 'e' || s_[at_ - 1] == 'E'))))
      ++at_;
    std::string word = s_.substr(start, at_ - start);
    if (word.empty()) return false;
    if (std::isdigit(static_cast<unsigned char>(word[0])) || word[0] == '-' || word[0] == '+' || word[0] == '.') {
      const size_t sign = word[0] == '-' || word[0] == '+' ? 1 : 0;
      const bool hex = word.compare(sign, 2, "0x") == 0 || word.compare(sign, 2, "0X") == 0;
      // 2.0lf, 1u, 0.5LF; a hexadecimal integer's F is a digit (0xFFul).
      const size_t suffix = word.find_last_not_of(hex ? "lLuU" : "lLfFuU");
      const std::string digits = word.substr(0, suffix + 1);
      char* end = nullptr;
      out->number = true;
      out->value.isInteger = hex || digits.find_first_of(".eE") == std::string::npos;
      if (out->value.isInteger) {
        // All 64 bits (a uint64_t's 0xBADDC0DEDEADBEEF), in GLSL's bases (0x, leading 0: octal).
        const uint64_t magnitude = std::strtoull(digits.c_str() + sign, &end, 0);
        out->value.i = static_cast<int64_t>(word[0] == '-' ? 0 - magnitude : magnitude);
        out->value.d = word[0] == '-' ? -static_cast<double>(magnitude) : static_cast<double>(magnitude);
      } else {
        out->value.d = std::strtod(digits.c_str(), &end);
        out->value.i = static_cast<int64_t>(out->value.d);
      }
      return end && *end == 0;
    }
    if (word == "true" || word == "false") {
      out->number = true;
      out->value.isInteger = true;
      out->value.d = out->value.i = word == "true";
      return true;
    }
    out->type = word;
    if (take('[')) {  // an array constructor: float[](...) or float[2](...)
      while (at_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[at_]))) ++at_;
      if (!take(']')) return false;
      out->type += "[]";
    }
    return take('(') && list(')', out);
  }
};

// Components of a GLSL scalar, vector or matrix type; 0 for other types.
size_t components(const std::string& type, size_t* columns = nullptr) {
  static const std::regex kShape(
      R"((?:(?:[iudb]|i64|u64)?vec([234]))|(?:d?mat([234])(?:x([234]))?)|float|double|int|uint|bool|int64_t|uint64_t)");
  std::smatch m;
  if (!std::regex_match(type, m, kShape)) return 0;
  if (columns) *columns = m[2].matched ? size_t(std::stoi(m[2])) : 1;
  if (m[1].matched) return size_t(std::stoi(m[1]));
  if (m[2].matched) return size_t(std::stoi(m[2])) * size_t(std::stoi(m[3].matched ? m[3].str() : m[2].str()));
  return 1;
}

// The numbers of an initialiser of a scalar, vector or matrix type, in component order.
bool flatten(const Initializer& init, const std::string& type, std::vector<Value>* out) {
  size_t columns = 1;
  const size_t n = components(type, &columns);
  std::vector<Value> leaves;
  std::function<bool(const Initializer&)> collect = [&](const Initializer& i) {
    if (i.number) return leaves.push_back(i.value), true;
    if (i.items.size() == 1 && i.items[0].number && components(i.type) > 1) {  // vec4(x): every component
      leaves.insert(leaves.end(), components(i.type), i.items[0].value);
      return true;
    }
    for (const Initializer& item : i.items)
      if (!collect(item)) return false;
    return true;
  };
  if (n == 0) return false;
  if (columns > 1 && init.items.size() == 1 && init.items[0].number) {  // mat3(x): a diagonal
    const size_t rows = n / columns;
    out->assign(n, Value{});
    for (size_t c = 0; c < columns && c < rows; ++c) (*out)[c * rows + c] = init.items[0].value;
    return true;
  }
  if (!collect(init)) return false;
  if (leaves.size() == 1 && n > 1) leaves.assign(n, leaves[0]);
  if (leaves.size() != n) return false;
  *out = leaves;
  return true;
}

struct StructMember {
  std::string type, name;
  bool array = false;
};

bool assign(const Initializer& init, const std::string& type, bool array, const std::string& path,
            const std::map<std::string, std::vector<StructMember>>& structs, std::vector<UniformInitialValue>* out) {
  if (array) {
    for (size_t i = 0; i < init.items.size(); ++i)
      if (!assign(init.items[i], type, false, path + "[" + std::to_string(i) + "]", structs, out)) return false;
    return true;
  }
  auto members = structs.find(type);
  if (members != structs.end()) {
    if (init.items.size() != members->second.size()) return false;
    for (size_t m = 0; m < init.items.size(); ++m) {
      const StructMember& member = members->second[m];
      if (!assign(init.items[m], member.type, member.array, path + "." + member.name, structs, out)) return false;
    }
    return true;
  }
  UniformInitialValue v;
  v.path = path;
  if (!flatten(init, type, &v.values)) return false;
  out->push_back(v);
  return true;
}

}  // namespace

std::set<std::string> explicitlyLocated(const std::string& source, bool outputs) {
  static const std::regex kDeclaration(R"(layout\s*\(([^)]*)\)\s*(?:\w+\s+)*?(in|out)\s+(?:\w+\s+)*?(\w+)\s*[{\[;,])");
  static const std::regex kLocation(R"(\blocation\b)");
  std::set<std::string> out;
  for (auto it = std::sregex_iterator(source.begin(), source.end(), kDeclaration); it != std::sregex_iterator(); ++it) {
    const std::string qualifiers = (*it)[1];
    if ((*it)[2] == (outputs ? "out" : "in") && std::regex_search(qualifiers, kLocation)) out.insert((*it)[3]);
  }
  return out;
}

std::vector<UniformInitialValue> uniformInitializers(const std::string& source) {
  std::map<std::string, std::vector<StructMember>> structs;
  static const std::regex kStruct(R"(\bstruct\s+(\w+)\s*\{([^}]*)\})");
  static const std::regex kMember(R"((\w+)\s+(\w+)\s*(\[[^\]]*\])?)");
  for (auto it = std::sregex_iterator(source.begin(), source.end(), kStruct); it != std::sregex_iterator(); ++it) {
    std::stringstream body((*it)[2]);
    for (std::string declaration; std::getline(body, declaration, ';');) {
      std::smatch m;
      if (std::regex_search(declaration, m, kMember)) structs[(*it)[1]].push_back({m[1], m[2], m[3].matched});
    }
  }
  std::vector<UniformInitialValue> out;
  // The array's size after the type (`mat3[3] m`) or after the name (`mat3 m[3]`).
  static const std::regex kInitialised(
      R"(\buniform\s+(?:(?:highp|mediump|lowp)\s+)?(\w+)\s*(\[[^\]]*\])?\s+(\w+)\s*(\[[^\]]*\])?\s*=\s*([^;]+);)");
  // Constants with literal values, which an initialiser may name (`uniform mat3 m = c;`).
  std::map<std::string, std::string> constants;
  static const std::regex kConstant(R"(\bconst\s+(?:(?:highp|mediump|lowp)\s+)?\w+\s+(\w+)\s*=\s*([^;]+);)");
  for (auto it = std::sregex_iterator(source.begin(), source.end(), kConstant); it != std::sregex_iterator(); ++it)
    constants[(*it)[1]] = (*it)[2];
  for (auto it = std::sregex_iterator(source.begin(), source.end(), kInitialised); it != std::sregex_iterator(); ++it) {
    Initializer init;
    std::string text = (*it)[5];
    for (int depth = 0; depth < 8; ++depth) {  // a constant may name another
      auto named = constants.find(std::regex_replace(text, std::regex(R"(^\s+|\s+$)"), ""));
      if (named == constants.end()) break;
      text = named->second;
    }
    if (!InitializerReader(text).read(&init)) continue;
    std::vector<UniformInitialValue> values;
    const bool array = (*it)[2].matched || (*it)[4].matched;
    if (assign(init, (*it)[1], array, (*it)[3], structs, &values)) out.insert(out.end(), values.begin(), values.end());
  }
  return out;
}

}  // namespace parity::harness::script
