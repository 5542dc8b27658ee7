// shader_test sections: [require], shaders, [vertex data], [indices]; the helpers every step uses.
#include "harness/scripts/shader_test/steps.h"

#include "rhi/rhi.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <regex>
#include <sstream>

namespace parity::harness::script::shader_test {

std::string trim(const std::string& s) {
  size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  size_t e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> words(const std::string& line) {
  std::string s = line;
  for (char& c : s)
    if (c == '(' || c == ')' || c == ',') c = ' ';
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

std::string uncommented(const std::string& line) {
  size_t h = line.find('#');
  return trim(h == std::string::npos ? line : line.substr(0, h));
}

bool parseNumber(const std::string& text, Value* v) {
  // GLSL's unsigned suffix (`0u`, `0x10U`), which piglit's strtoul stops before.
  const bool unsignedSuffix = text.size() > 1 && (text.back() == 'u' || text.back() == 'U') && std::isdigit(static_cast<unsigned char>(text[text.size() - 2]));
  const std::string s = unsignedSuffix ? text.substr(0, text.size() - 1) : text;
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  bool looksInt = s.find_first_of(".eEnN") == std::string::npos || (s.size() > 2 && (s[1] == 'x' || s[1] == 'X'));
  if (looksInt) {
    long long x = s[0] == '-' ? std::strtoll(s.c_str(), &end, 0) : static_cast<long long>(std::strtoull(s.c_str(), &end, 0));
    if (*end == 0 && errno == 0) {
      v->isInteger = true;
      v->i = x;
      v->d = s[0] == '-' ? static_cast<double>(x) : static_cast<double>(static_cast<unsigned long long>(x));
      return true;
    }
  }
  if (unsignedSuffix) return false;  // an integer's suffix only
  end = nullptr;
  double d = std::strtod(s.c_str(), &end);
  if (!end || *end) return false;
  v->isInteger = false;
  v->d = d;
  v->i = std::isfinite(d) && std::fabs(d) < 9.2e18 ? static_cast<int64_t>(d) : 0;
  return true;
}

std::string amberTypeName(const std::string& glsl) {
  static const std::map<std::string, std::string> kScalars = {
      {"float", "float"},     {"int", "int32"},       {"uint", "uint32"},       {"bool", "uint32"},
      {"double", "double"},   {"int64_t", "int64"},   {"uint64_t", "uint64"},   {"int16_t", "int16"},
      {"uint16_t", "uint16"}, {"int8_t", "int8"},     {"uint8_t", "uint8"},     {"float16_t", "float16"},
      // piglit's spellings of `ssbo N subdata TYPE`
      {"int64", "int64"},     {"uint64", "uint64"},   {"int16", "int16"},       {"uint16", "uint16"},
      {"int8", "int8"},       {"uint8", "uint8"}};
  auto scalar = kScalars.find(glsl);
  if (scalar != kScalars.end()) return scalar->second;
  static const std::map<std::string, std::string> kPrefixes = {
      {"", "float"}, {"d", "double"}, {"i", "int32"}, {"u", "uint32"}, {"b", "uint32"},
      {"i64", "int64"}, {"u64", "uint64"}, {"i16", "int16"}, {"u16", "uint16"}, {"f16", "float16"},
      {"i8", "int8"}, {"u8", "uint8"}};
  for (const char* kind : {"vec", "mat"}) {
    size_t at = glsl.find(kind);
    if (at == std::string::npos) continue;
    auto prefix = kPrefixes.find(glsl.substr(0, at));
    if (prefix == kPrefixes.end()) return {};
    std::string shape = glsl.substr(at + 3);
    if (std::string(kind) == "vec") {
      if (shape.size() != 1 || shape[0] < '2' || shape[0] > '4') return {};
      return "vec" + shape + "<" + prefix->second + ">";
    }
    if (shape.size() == 1) shape = shape + "x" + shape;  // mat3 = mat3x3
    if (shape.size() != 3 || shape[1] != 'x') return {};
    return "mat" + shape + "<" + prefix->second + ">";
  }
  return {};
}

void ShaderTestState::splitSections() {
  Section* current = nullptr;
  for (size_t i = 0; i < lines_.size(); ++i) {
    std::string t = trim(lines_[i]);
    int line = static_cast<int>(i + 1);
    if (t.size() > 2 && t.front() == '[' && t.back() == ']') {
      sections_.push_back({t.substr(1, t.size() - 2), line, {}});
      current = &sections_.back();
      continue;
    }
    if (!current) continue;  // piglit reads nothing before the first section: licence or notes
    current->lines.push_back({line, lines_[i]});
  }
  if (sections_.empty()) error(1, "no [section]: not a shader_test file");
}

void ShaderTestState::joinContinuedLines() {
  for (Section& s : sections_) {
    if (s.name.find("shader") != std::string::npos) continue;
    std::vector<std::pair<int, std::string>> joined;
    bool continues = false;
    for (auto& [line, text] : s.lines) {
      if (continues) joined.back().second += " " + text;
      else joined.push_back({line, text});
      std::string& last = joined.back().second;
      while (!last.empty() && std::isspace(static_cast<unsigned char>(last.back()))) last.pop_back();
      continues = !last.empty() && last.back() == '\\';
      if (continues) last.pop_back();
    }
    s.lines = std::move(joined);
  }
}

void SectionSteps::require(const Section& s) {
  for (const auto& entry : s.lines) {
    // Named copies, not structured bindings: the lambda below captures them (clang 14 cannot).
    const auto line = entry.first;
    const std::string& text = entry.second;
    std::vector<std::string> w = words(uncommented(text));
    // piglit's typed limits (`INT GL_MAX_... >= n`, `FLOAT ...`) are its untyped ones.
    if (w.size() >= 4 && (w[0] == "INT" || w[0] == "FLOAT") && w[1].rfind("GL_", 0) == 0) w.erase(w.begin());
    if (w.empty()) continue;
    const std::string& k = w[0];
    auto number = [&](size_t i) {
      Value v;
      if (i >= w.size() || !parseNumber(w[i], &v)) error(line, "expected a number in '" + trim(text) + "'");
      return v;
    };
    if (k == "GLSL" || k == "GL") {
      // GLSL <= 4.50 and GL <= 4.5 are what both backends run, in a compatibility profile where
      // the file asks for one (`GL COMPAT >= 3.2`; compatibilityProfile); ES is not.
      if (w.size() >= 2 && w[1] == "ES") unsupported(line, "[require] " + k + " ES (OpenGL ES)");
      const bool compat = k == "GL" && w.size() >= 2 && w[1] == "COMPAT";
      if (compat) {
        script_.compatibilityContext = true;
        w.erase(w.begin() + 1);
        // OpenGL 3.1 has no profiles: piglit asks for a 3.1 context and needs GL_ARB_compatibility
        // in it (Mesa's has none); parity's compatibility context is the driver's newest profile.
        if (w.size() >= 3 && w[2] == "3.1") unsupported(line, "[require] GL COMPAT 3.1 (a GL 3.1 context with GL_ARB_compatibility)");
      }
      if (w.size() >= 3 && w[1] != "ES") {
        double version = number(2).d;
        // piglit gives a shader without #version the GLSL version the file requires.
        if (k == "GLSL") glslVersion_ = std::max(glslVersion_, static_cast<int>(std::lround(version * 100)));
        if ((k == "GLSL" && version > 4.50 + 1e-9) || (k == "GL" && version > 4.5 + 1e-9))
          unsupported(line, "[require] " + k + " " + w[1] + " " + w[2]);
      }
    } else if (k == "GL_ES" || k == "GLSL_ES") {
      unsupported(line, "[require] " + k + " (OpenGL ES)");
    } else if (k == "SIZE" || k == "fbsize") {
      width_ = static_cast<uint32_t>(number(1).i);
      height_ = static_cast<uint32_t>(number(2).i);
      if (width_ == 0 || height_ == 0 || width_ > kMaxImageDimension || height_ > kMaxImageDimension)
        error(line, "framebuffer size " + w[1] + "x" + w[2] + " out of range");
    } else if (k == "framebuffer") {
      if (w.size() < 2) error(line, "framebuffer needs a format");
      framebufferFormat_ = w[1];
    } else if (k == "depthstencil") {
      if (w.size() < 2) error(line, "depthstencil needs a format");
      depthFormat_ = w[1];
    } else if (k == "GL_MAX_VERTEX_ATTRIBS" && w.size() >= 3) {
      // Both backends take the attribute locations GL and Vulkan guarantee, 16.
      const int64_t need = number(2).i + (w[1] == ">" ? 1 : 0);
      if ((w[1] == ">=" || w[1] == ">") && need > int64_t(rhi::kMaxVertexAttributes))
        unsupported(line, "[require] GL_MAX_VERTEX_ATTRIBS " + w[1] + " " + w[2] + " (the device takes " +
                              std::to_string(rhi::kMaxVertexAttributes) + ")");
    } else if (k.rfind("GL_", 0) == 0 && w.size() >= 3 && (w[1] == ">=" || w[1] == ">" || w[1] == "<=")) {
      // Implementation limits (GL_MAX_...): the GL 4.5 minimums cover what the sample asks, but
      // for atomic counters outside fragment and compute shaders, whose minimum is 0. Both
      // backends run atomic counters as storage-buffer words, so what such a limit asks is the
      // device's stores and atomics in the pre-rasterisation stages.
      for (const char* stage : {"GL_MAX_VERTEX_ATOMIC_COUNTER", "GL_MAX_TESS_CONTROL_ATOMIC_COUNTER",
                                "GL_MAX_TESS_EVALUATION_ATOMIC_COUNTER", "GL_MAX_GEOMETRY_ATOMIC_COUNTER"})
        if (k.rfind(stage, 0) == 0) script_.requirements.push_back({"device_feature", "vertexPipelineStoresAndAtomics", {line, 1}});
    } else if (k == "ARB_vertex_program" || k == "ARB_fragment_program") {
      // piglit names the assembly languages' extensions without their GL_ prefix.
      script_.requirements.push_back({"opengl_extension", "GL_" + k, {line, 1}});
    } else if (k.rfind("GL_", 0) == 0) {
      // Checked against the device when the script runs (deviceRequirementMissing).
      script_.requirements.push_back({"opengl_extension", k, {line, 1}});
    } else if (k == "SPIRV") {
      // piglit: YES and ONLY run the [X shader spirv] sections in place of the GLSL ones (ONLY:
      // the GLSL is there as a reference only), NO the GLSL ones.
      if (w.size() != 2 || (w[1] != "YES" && w[1] != "ONLY" && w[1] != "NO")) error(line, "SPIRV takes YES, ONLY or NO, got '" + trim(text) + "'");
      spirvMode_ = w[1];
    } else if (k == "SEPARABLE" && w.size() == 3 && w[1] == "PROGRAM" && w[2] == "ENABLED") {
      // One program of all the stages, linked separable (GL_PROGRAM_SEPARABLE), under the rules
      // OpenGL adds for those (rhi::PipelineDesc::separablePrograms).
      script_.separableProgram = true;
    } else if (k == "SSO" || k == "SSO_ENABLED") {
      // Separate shader objects: the stages are linked as one pipeline either way, matched by
      // location as separate programs match (the port's rules; runsOpenGlGlsl).
      script_.separateShaderObjects = true;
    } else if (k.rfind("VK_", 0) == 0) {
      script_.requirements.push_back({"device_extension", k, {line, 1}});
    } else if (std::islower(static_cast<unsigned char>(k[0])) && w.size() == 1) {
      script_.requirements.push_back({"device_feature", k, {line, 1}});  // shaderFloat64, ...
    } else {
      unsupported(line, "[require] " + k);
    }
  }
}

void SectionSteps::shader(const Section& s) {
  static const std::map<std::string, Stage> kStages = {
      {"vertex", Stage::Vertex}, {"fragment", Stage::Fragment}, {"compute", Stage::Compute}, {"geometry", Stage::Geometry},
      {"tessellation control", Stage::TessControl}, {"tessellation evaluation", Stage::TessEvaluation}};
  std::vector<std::string> w = words(s.name);
  std::string stage = w.empty() ? "" : w[0];
  if (stage == "tessellation" && w.size() > 1) stage += " " + w[1];
  bool spirv = s.name.find(" spirv") != std::string::npos, binary = s.name.find(" binary") != std::string::npos;
  bool passthrough = s.name == "vertex shader passthrough";
  Shader sh;
  sh.loc = {s.header, 1};
  sh.sourceLine = s.header + 1;
  for (const auto& [line, text] : s.lines) sh.source += text + "\n";
  auto st = kStages.find(stage);
  const bool specialization = w.size() >= 3 && w.back() == "specializations";
  if (specialization && st != kStages.end()) {
    std::string shaderName = stage;
    std::replace(shaderName.begin(), shaderName.end(), ' ', '_');
    if (spirvProgram()) specializations(s, shaderName);  // piglit specializes SPIR-V only
    return;
  }
  if (st == kStages.end() || (passthrough && (spirv || binary))) error(s.header, "unknown section [" + s.name + "]");
  // piglit runs either a file's SPIR-V sections or its GLSL ones ([require] SPIRV) and ignores
  // the others; the pass-through vertex shader stands in for either (a GLSL one here: its SPIR-V
  // is what glslang makes of it).
  if (piglit_ && !passthrough && spirv != spirvProgram()) return;
  if (binary) {
    unsupported(s.header, "[" + s.name + "] (SPIR-V as hexadecimal words)");
    return;
  }
  sh.stage = st->second;
  sh.name = stage;
  std::replace(sh.name.begin(), sh.name.end(), ' ', '_');
  sh.passthrough = passthrough;
  sh.format = spirv ? "SPIRV-ASM" : "GLSL";
  sh.openGl = piglit_ && !spirv;
  sh.openGlSpirv = piglit_ && spirv;
  sh.glslVersion = glslVersion_;
  auto first = std::find_if(script_.shaders.begin(), script_.shaders.end(), [&](const Shader& x) { return x.name == sh.name; });
  if (first != script_.shaders.end()) {
    // GLSL sections of one stage link into one module; SPIR-V stands alone (VkRunner refuses it).
    if (spirv || first->format != "GLSL" || first->passthrough || passthrough)
      unsupported(s.header, "[" + s.name + "] beside another " + stage + " shader (SPIR-V or a passthrough shader links with no other)");
    else
      first->linkedUnits.push_back({sh.source, sh.sourceLine});
    return;
  }
  script_.shaders.push_back(sh);
}

// [vertex program] and [fragment program]: an ARB assembly program, which the GL driver loads
// itself (rhi::ShaderDesc::arbProgram); one a stage.
void SectionSteps::arbProgram(const Section& s) {
  Shader sh;
  sh.loc = {s.header, 1};
  sh.sourceLine = s.header + 1;
  for (const auto& [line, text] : s.lines) sh.source += text + "\n";
  sh.stage = s.name == "vertex program" ? Stage::Vertex : Stage::Fragment;
  sh.name = s.name == "vertex program" ? "vertex" : "fragment";
  sh.format = "ARB";
  if (script_.findShader(sh.name)) return unsupported(s.header, "[" + s.name + "] beside a " + sh.name + " shader");
  script_.shaders.push_back(sh);
}

// [vertex data]: a header of columns, then a row of values per vertex. Every column goes into one
// interleaved buffer, as piglit's one vertex buffer object: each at an offset aligned to its
// component size, the row's stride a multiple of the largest.
void SectionSteps::vertexData(const Section& s) {
  bool header = true;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> rowLines;
  for (const auto& [line, text] : s.lines) {
    std::string t = uncommented(text);
    if (t.empty()) continue;
    std::vector<std::string> w = words(t);
    if (header) {
      header = false;
      for (const std::string& column : w) attributes_.push_back(attribute(line, column));
      continue;
    }
    size_t need = 0;
    for (const Attribute& a : attributes_) need += a.type.layout.fields.size();
    if (w.size() != need)
      error(line, "[vertex data] row has " + std::to_string(w.size()) + " values, the header needs " + std::to_string(need));
    rows.push_back(w);
    rowLines.push_back(line);
  }
  if (attributes_.empty()) return;
  std::vector<uint32_t> offsets;
  uint32_t stride = 0, align = 1;
  for (const Attribute& a : attributes_) {
    const uint32_t size = scalarSize(a.type.layout.fields[0].scalar);
    stride = (stride + size - 1) / size * size;
    offsets.push_back(stride);
    stride += a.type.layout.stride;
    align = std::max(align, size);
  }
  stride = (stride + align - 1) / align * align;
  Buffer b;
  b.name = "vertex_data";
  std::string why;
  parseDataType("uint8", false, &b.type, &why);  // raw bytes: each column reads its own format
  b.hasType = true;
  b.sized = true;
  b.loc = {s.header, 1};
  b.bytes.assign(rows.size() * stride, 0);
  for (size_t r = 0; r < rows.size(); ++r) {
    size_t word = 0;
    for (size_t a = 0; a < attributes_.size(); ++a)
      for (const Field& f : attributes_[a].type.layout.fields) {
        Value v;
        const std::string& text = rows[r][word++];
        if (!parseNumber(text, &v)) error(rowLines[r], "expected a number in [vertex data], got '" + text + "'");
        applyHexFloatBits(text, f.scalar, &v);
        storeValue(b.bytes, r * stride + offsets[a] + f.offset, f.scalar, v);
      }
  }
  script_.buffers.push_back(b);
  vertexOffsets_ = offsets;
  vertexStride_ = stride;
}

// A column of [vertex data]: piglit's NAME[INDEX]/GL_TYPE/GLSL_TYPE[/COLUMN] (piglit_vertex/float/vec3,
// value[1]/double/dmat3x2/0, color/ubyte/uvec4) or NAME/GL_TYPE/COUNT (vertex/float/2), or
// VkRunner's LOCATION/FORMAT (0/R32G32_SFLOAT). GL_TYPE is how the values are stored (byte,
// ubyte, short, ushort, int, uint, half, float, double); the GLSL type, the input they feed (an
// integer input reads them as integers); a matrix column, or an element of an array input, is fed
// at the input's location plus the locations before it (a dvec3 or dvec4 column takes two).
SectionSteps::Attribute SectionSteps::attribute(int line, const std::string& column) {
  std::vector<std::string> parts;
  std::stringstream in(column);
  for (std::string p; std::getline(in, p, '/');) parts.push_back(p);
  Attribute a;
  std::string why;
  Value location;
  bool numbered = !parts.empty() && parseNumber(parts[0], &location) && location.isInteger;
  if (numbered && parts.size() == 2) {
    a.location = static_cast<uint32_t>(location.i);
    std::transform(parts[1].begin(), parts[1].end(), parts[1].begin(), [](unsigned char ch) { return static_cast<char>(std::toupper(ch)); });
    if (!parseFormat(parts[1], &a.type, &why)) error(line, "[vertex data] column '" + column + "': " + why);
    a.format = parts[1];
    return a;
  }
  auto bad = [&](const std::string& what) {
    error(line, "[vertex data] column '" + column + "': " + what +
                    " (NAME[INDEX]/TYPE/GLSL_TYPE[/COLUMN], NAME/TYPE/COUNT or LOCATION/FORMAT)");
  };
  if (parts.size() != 3 && parts.size() != 4) bad("not a column header");
  // NAME[INDEX]
  uint32_t index = 0;
  a.name = parts[0];
  if (const size_t open = a.name.find('['); open != std::string::npos) {
    Value i;
    if (a.name.back() != ']' || !parseNumber(a.name.substr(open + 1, a.name.size() - open - 2), &i) || !i.isInteger || i.i < 0)
      bad("array index is not [N]");
    index = static_cast<uint32_t>(i.i);
    a.name = a.name.substr(0, open);
  }
  if (a.name.empty()) bad("no input name");
  // GL_TYPE: the stored components.
  struct Stored {
    const char* name;
    uint32_t bits;
    const char* kind;  // the Vulkan format's numeric kind
  };
  static const Stored kStored[] = {{"byte", 8, "SINT"},   {"ubyte", 8, "UINT"}, {"short", 16, "SINT"},
                                   {"ushort", 16, "UINT"}, {"int", 32, "SINT"}, {"uint", 32, "UINT"},
                                   {"half", 16, "SFLOAT"}, {"float", 32, "SFLOAT"}, {"double", 64, "SFLOAT"}};
  const Stored* stored = nullptr;
  for (const Stored& t : kStored)
    if (parts[1] == t.name) stored = &t;
  if (!stored) bad("unknown type '" + parts[1] + "'");
  // GLSL_TYPE or COUNT: components per location, columns, and whether the input is an integer.
  uint32_t components = 0, columns = 1;
  char base = 0;  // 0 float, 'd' double, 'i' int, 'u' uint
  const std::string& g = parts[2];
  static const std::regex glsl(R"(^(d|i|u)?(?:vec([234])|mat([234])(?:x([234]))?)$)");
  std::smatch m;
  Value count;
  if (parseNumber(g, &count) && count.isInteger && count.i >= 1 && count.i <= 4) {
    components = static_cast<uint32_t>(count.i);
    base = std::string(stored->kind) == "SFLOAT" ? (stored->bits == 64 ? 'd' : 0) : (stored->kind[0] == 'S' ? 'i' : 'u');
  } else if (g == "float" || g == "double" || g == "int" || g == "uint") {
    components = 1;
    base = g == "float" ? 0 : g[0];
  } else if (std::regex_match(g, m, glsl)) {
    base = m[1].matched ? m[1].str()[0] : 0;
    if (m[2].matched) {
      components = static_cast<uint32_t>(std::stoi(m[2].str()));
    } else {
      if (base == 'i' || base == 'u') bad("no integer matrices");
      columns = static_cast<uint32_t>(std::stoi(m[3].str()));
      components = m[4].matched ? static_cast<uint32_t>(std::stoi(m[4].str())) : columns;
    }
  } else {
    bad("unknown GLSL type '" + g + "'");
  }
  uint32_t matrixColumn = 0;
  if (columns > 1) {
    Value c;
    if (parts.size() != 4 || !parseNumber(parts[3], &c) || !c.isInteger || c.i < 0 || c.i >= columns)
      bad("a matrix column needs its index, 0 to " + std::to_string(columns - 1));
    matrixColumn = static_cast<uint32_t>(c.i);
  } else if (parts.size() == 4) {
    bad("a column index on a type that is no matrix");
  }
  const bool integerInput = base == 'i' || base == 'u', doubleInput = base == 'd';
  if (integerInput != (std::string(stored->kind) != "SFLOAT"))
    unsupported(line, "[vertex data] " + column + " (" + parts[1] + " values into a " + g + " input: a converting fetch)");
  if (doubleInput != (stored->bits == 64)) bad("double inputs take double values and only they");
  const uint32_t perColumn = doubleInput && components >= 3 ? 2 : 1;
  a.locationOffset = (index * columns + matrixColumn) * perColumn;
  static const char kChannels[] = "RGBA";
  for (uint32_t c = 0; c < components; ++c) a.format += std::string(1, kChannels[c]) + std::to_string(stored->bits);
  a.format += std::string("_") + stored->kind;
  if (!parseFormat(a.format, &a.type, &why)) bad(why);
  return a;
}

void SectionSteps::indices(const Section& s) {
  for (const auto& [line, text] : s.lines)
    for (const std::string& x : words(uncommented(text))) {
      Value v;
      if (!parseNumber(x, &v) || !v.isInteger || v.i < 0 || v.i > 0xFFFF) error(line, "expected a 16-bit index, got '" + x + "'");
      indices_.push_back(v);
    }
  Buffer b;
  b.name = "indices";
  b.hasType = true;
  std::string why;
  parseDataType("uint16", false, &b.type, &why);
  b.sized = true;
  for (size_t i = 0; i < indices_.size(); ++i) storeValue(b.bytes, i * 2, Scalar::Uint16, indices_[i]);
  b.loc = {s.header, 1};
  script_.buffers.push_back(b);
}

void SectionSteps::declareFramebuffer() {
  Buffer fb;
  fb.name = "framebuffer";
  fb.hasType = true;
  std::string why;
  if (!parseFormat(framebufferFormat_, &fb.type, &why)) {
    unsupported(1, "framebuffer " + framebufferFormat_);
    parseFormat("R8G8B8A8_UNORM", &fb.type, &why);
  }
  script_.buffers.push_back(fb);
  if (!depthFormat_.empty()) {
    Buffer depth;
    depth.name = "depthstencil";
    depth.hasType = true;
    if (!parseFormat(depthFormat_, &depth.type, &why)) unsupported(1, "depthstencil " + depthFormat_);
    script_.buffers.push_back(depth);
  }
  bool graphics = false, compute = false;
  for (const Shader& s : script_.shaders) (s.stage == Stage::Compute ? compute : graphics) = true;
  auto add = [&](const std::string& name, bool isCompute, bool withVertexData) {
    Pipeline p;
    p.name = name;
    p.compute = isCompute;
    for (const Shader& s : script_.shaders)
      if ((s.stage == Stage::Compute) == isCompute) p.shaders.push_back(s.name);
    if (!isCompute) {
      p.fbWidth = width_, p.fbHeight = height_;
      // OpenGL's window y points up, Vulkan's framebuffer y down, and both put NDC y = -1 in
      // memory row 0: a triangle counter-clockwise in OpenGL (front-facing in piglit) is
      // clockwise to the RHI.
      if (piglit_) p.frontFace = "clockwise";
      // OpenGL's flat inputs take the last vertex's values.
      p.provokingVertexLast = piglit_;
      Bind color;
      color.kind = BindKind::Color;
      color.buffer = "framebuffer";
      color.asWord = "color";
      p.binds.push_back(color);
      if (!depthFormat_.empty()) {
        Bind depth;
        depth.kind = BindKind::DepthStencil;
        depth.buffer = "depthstencil";
        depth.asWord = "depth_stencil";
        p.binds.push_back(depth);
      }
      if (withVertexData)
        for (size_t a = 0; a < attributes_.size(); ++a) {
          VertexData v;
          v.buffer = "vertex_data";
          v.location = attributes_[a].location;
          v.attribute = attributes_[a].name;
          v.locationOffset = attributes_[a].locationOffset;
          v.offset = vertexOffsets_[a];
          v.stride = vertexStride_;
          v.format = attributes_[a].format;
          p.vertexData.push_back(v);
        }
      if (withVertexData && !indices_.empty()) p.indexData = "indices";
    }
    script_.pipelines.push_back(p);
  };
  // `draw rect` brings its own vertices, `draw arrays` uses [vertex data]: one pipeline each.
  // The window exists without graphics shaders too: a compute test may clear and probe it.
  add("rect", false, false);
  if (graphics && !attributes_.empty()) add("arrays", false, true);
  if (compute) add("compute", true, false);
}

}  // namespace parity::harness::script::shader_test
