#include "harness/shader_test_parser.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>

namespace parity::harness::script {

namespace {

struct ShaderTestError {
  int line = 0;
  std::string message;
};

std::string trim(const std::string& s) {
  size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  size_t e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// Words of a [test] line: parentheses and commas separate like blanks ("(0.5, 0.5)").
std::vector<std::string> words(const std::string& line) {
  std::string s = line;
  for (char& c : s)
    if (c == '(' || c == ')' || c == ',') c = ' ';
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// A line with its comment removed: '#' starts one in [require], [test] and data sections.
std::string uncommented(const std::string& line) {
  size_t h = line.find('#');
  return trim(h == std::string::npos ? line : line.substr(0, h));
}

bool parseNumber(const std::string& s, Value* v) {
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
  end = nullptr;
  double d = std::strtod(s.c_str(), &end);
  if (!end || *end) return false;
  v->isInteger = false;
  v->d = d;
  v->i = std::isfinite(d) && std::fabs(d) < 9.2e18 ? static_cast<int64_t>(d) : 0;
  return true;
}

// GLSL type names as Amber DATA_TYPE names: "vec3" -> "vec3<float>", "dmat2x3" -> "mat2x3<double>".
// Booleans are 32-bit words in a block. Empty when the type has no such spelling (samplers, ...).
std::string amberTypeName(const std::string& glsl) {
  static const std::map<std::string, std::string> kScalars = {
      {"float", "float"},     {"int", "int32"},       {"uint", "uint32"},       {"bool", "uint32"},
      {"double", "double"},   {"int64_t", "int64"},   {"uint64_t", "uint64"},   {"int16_t", "int16"},
      {"uint16_t", "uint16"}, {"int8_t", "int8"},     {"uint8_t", "uint8"},     {"float16_t", "float16"}};
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

class ShaderTestParser {
 public:
  ShaderTestParser(const std::string& text, const std::string& name) : name_(name) {
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) {
      if (!l.empty() && l.back() == '\r') l.pop_back();
      lines_.push_back(l);
    }
    script_.file = name;
  }

  Script run() {
    splitSections();
    // piglit files always state the GLSL or GL version they need; VkRunner's never do.
    piglit_ = false;
    for (const Section& s : sections_)
      if (s.name == "require")
        for (const auto& [line, text] : s.lines) {
          std::vector<std::string> w = words(uncommented(text));
          if (!w.empty() && (w[0] == "GLSL" || w[0] == "GL" || w[0] == "GL_ES" || w[0] == "GLSL_ES")) piglit_ = true;
        }
    tolerance_ = piglit_ ? 3.0 / 256.0 : 0.01;  // piglit: 3 steps of an 8-bit channel; VkRunner: 0.01
    for (const Section& s : sections_) {
      if (s.name == "require") require(s);
      else if (s.name.find("shader") != std::string::npos) shader(s);
      else if (s.name == "vertex data") vertexData(s);
      else if (s.name == "indices") indices(s);
      else if (s.name == "comment") continue;
      else if (s.name != "test") unsupported(s.header, "[" + s.name + "] section");
    }
    declareFramebuffer();
    for (const Section& s : sections_)
      if (s.name == "test") test(s);
    return std::move(script_);
  }

 private:
  struct Section {
    std::string name;
    int header = 0;                               // line of "[name]"
    std::vector<std::pair<int, std::string>> lines;  // 1-based line, text
  };
  struct Attribute {
    std::string name;  // piglit: the shader input's name
    uint32_t location = 0;
    ElementType type;
  };
  struct BufferUse {
    std::string kind;  // "ssbo", "ubo"
    uint32_t set = 0, binding = 0;
    uint64_t size = 0;
  };

  std::string name_;
  std::vector<std::string> lines_;
  std::vector<Section> sections_;
  Script script_;
  bool piglit_ = false;
  double tolerance_ = 0.01;
  std::vector<Tolerance> tolerances_;  // `tolerance` lines: replaces the default per channel
  uint32_t width_ = 250, height_ = 250;
  std::string framebufferFormat_ = "R8G8B8A8_UNORM", depthFormat_;
  std::vector<Attribute> attributes_;
  std::vector<std::vector<Value>> vertexRows_;
  std::vector<Value> indices_;
  std::map<std::string, Pipeline*> pipelineByRole_;
  bool drawn_ = false;
  uint32_t uboArrayIndex_ = 0;  // `ubo array index N`
  // VkRunner's depthBiasEnable and the factors, applied to the pipelines together.
  bool depthBiasEnabled_ = false;
  float depthBias_[3] = {0, 0, 0};  // constant, clamp, slope
  int lastTextureUnit_ = 0;
  int glslVersion_ = 110;  // piglit's active texture unit: the last `texture` command's

  [[noreturn]] void error(int line, const std::string& msg) { throw ShaderTestError{line, msg}; }
  void unsupported(int line, const std::string& what) { script_.unsupported.push_back({what, {line, 1}}); }

  void splitSections() {
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

  // --- [require] ---
  void require(const Section& s) {
    for (const auto& entry : s.lines) {
      // Named copies, not structured bindings: the lambda below captures them (clang 14 cannot).
      const auto line = entry.first;
      const std::string& text = entry.second;
      std::vector<std::string> w = words(uncommented(text));
      if (w.empty()) continue;
      const std::string& k = w[0];
      auto number = [&](size_t i) {
        Value v;
        if (i >= w.size() || !parseNumber(w[i], &v)) error(line, "expected a number in '" + trim(text) + "'");
        return v;
      };
      if (k == "GLSL" || k == "GL") {
        // GLSL <= 4.50 and GL <= 4.5 are what both backends run; a compatibility profile or ES is not.
        if (w.size() >= 2 && (w[1] == "COMPAT" || w[1] == "ES")) unsupported(line, "[require] " + k + " " + w[1] + " (OpenGL compatibility profile or ES)");
        if (w.size() >= 3 && w[1] != "COMPAT" && w[1] != "ES") {
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
      } else if (k.rfind("GL_", 0) == 0 && w.size() >= 3 && (w[1] == ">=" || w[1] == ">" || w[1] == "<=")) {
        // Implementation limits (GL_MAX_...): the GL 4.5 minimums cover what the sample asks.
      } else if (k.rfind("GL_ARB_", 0) == 0 || k.rfind("GL_KHR_", 0) == 0) {
        // Extensions core in GL 4.5, which glslang knows; their shaders run on both backends.
      } else if (k.rfind("GL_", 0) == 0) {
        unsupported(line, "[require] " + k);
      } else if (k == "SSO" || k == "SSO_ENABLED") {
        // Separate shader objects: the stages are linked as one pipeline either way.
      } else if (k.rfind("VK_", 0) == 0) {
        script_.requirements.push_back({"device_extension", k, {line, 1}});
      } else if (std::islower(static_cast<unsigned char>(k[0])) && w.size() == 1) {
        script_.requirements.push_back({"device_feature", k, {line, 1}});  // shaderFloat64, ...
      } else {
        unsupported(line, "[require] " + k);
      }
    }
  }

  // --- shaders ---
  void shader(const Section& s) {
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
    if (st == kStages.end() || (passthrough && (spirv || binary))) error(s.header, "unknown section [" + s.name + "]");
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
    sh.glslVersion = glslVersion_;
    if (script_.findShader(sh.name)) {
      unsupported(s.header, "two [" + stage + " shader] sections (several shader objects of one stage)");
      return;
    }
    script_.shaders.push_back(sh);
  }

  // --- [vertex data] ---
  void vertexData(const Section& s) {
    bool header = true;
    for (const auto& [line, text] : s.lines) {
      std::string t = uncommented(text);
      if (t.empty()) continue;
      std::vector<std::string> w = words(t);
      if (header) {
        header = false;
        for (const std::string& column : w) attributes_.push_back(attribute(line, column));
        continue;
      }
      std::vector<Value> row;
      for (const std::string& x : w) {
        Value v;
        if (!parseNumber(x, &v)) error(line, "expected a number in [vertex data], got '" + x + "'");
        row.push_back(v);
      }
      vertexRows_.push_back(row);
      size_t need = 0;
      for (const Attribute& a : attributes_) need += a.type.layout.fields.size();
      if (row.size() != need)
        error(line, "[vertex data] row has " + std::to_string(row.size()) + " values, the header needs " + std::to_string(need));
    }
    if (attributes_.empty()) return;
    size_t column = 0;
    for (size_t a = 0; a < attributes_.size(); ++a) {
      Buffer b;
      b.name = "vertex_data_" + std::to_string(a);
      b.hasType = true;
      b.type = attributes_[a].type;
      b.sized = true;
      b.loc = {s.header, 1};
      size_t n = b.type.layout.fields.size();
      for (size_t r = 0; r < vertexRows_.size(); ++r)
        for (size_t f = 0; f < n; ++f)
          storeValue(b.bytes, r * b.type.layout.stride + b.type.layout.fields[f].offset, b.type.layout.fields[f].scalar,
                     vertexRows_[r][column + f]);
      b.bytes.resize(vertexRows_.size() * b.type.layout.stride, 0);
      column += n;
      script_.buffers.push_back(b);
    }
  }

  // "piglit_vertex/float/2", "color/float/vec3" (piglit) or "0/R32G32_SFLOAT" (VkRunner).
  Attribute attribute(int line, const std::string& column) {
    std::vector<std::string> parts;
    std::stringstream in(column);
    for (std::string p; std::getline(in, p, '/');) parts.push_back(p);
    Attribute a;
    std::string why;
    Value location;
    bool numbered = !parts.empty() && parseNumber(parts[0], &location) && location.isInteger;
    if (numbered) a.location = static_cast<uint32_t>(location.i);
    else a.name = parts.empty() ? "" : parts[0];
    if (parts.size() == 2) {
      std::transform(parts[1].begin(), parts[1].end(), parts[1].begin(), [](unsigned char ch) { return static_cast<char>(std::toupper(ch)); });
      if (!parseFormat(parts[1], &a.type, &why)) error(line, "[vertex data] column '" + column + "': " + why);
      return a;
    }
    if (parts.size() != 3) error(line, "[vertex data] column '" + column + "' is not name/type/count");
    std::string count = parts[2];
    std::string type = parts[1] == "float" ? "float" : parts[1] == "int" ? "int32" : parts[1] == "uint" ? "uint32"
                       : parts[1] == "double" ? "double" : "";
    if (type.empty()) error(line, "[vertex data] column '" + column + "': unknown type '" + parts[1] + "'");
    if (count.rfind("vec", 0) == 0 || count.rfind("dvec", 0) == 0 || count.rfind("ivec", 0) == 0 || count.rfind("uvec", 0) == 0)
      count = count.substr(count.find("vec") + 3);
    if (count != "1" && count != "2" && count != "3" && count != "4")
      error(line, "[vertex data] column '" + column + "': unsupported component count '" + parts[2] + "'");
    std::string amber = count == "1" ? type : "vec" + count + "<" + type + ">";
    if (!parseDataType(amber, false, &a.type, &why)) error(line, why);
    return a;
  }

  void indices(const Section& s) {
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

  // --- the framebuffer and the pipelines every draw and dispatch uses ---
  void declareFramebuffer() {
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
            v.buffer = "vertex_data_" + std::to_string(a);
            v.location = attributes_[a].location;
            v.attribute = attributes_[a].name;
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

  Pipeline* pipeline(const std::string& name) {
    for (Pipeline& p : script_.pipelines)
      if (p.name == name) return &p;
    return nullptr;
  }

  // Buffers named by ssbo/ubo commands: "ssbo N", "ssbo SET:BINDING" or, for element E of a
  // descriptor array, "ssbo SET:BINDING:E".
  std::string bufferFor(int line, const std::string& kind, const std::string& where, uint64_t extent) {
    uint32_t set = 0, binding = 0, element = 0;
    std::vector<uint32_t> parts;
    for (size_t at = 0;;) {
      const size_t colon = where.find(':', at);
      Value v;
      if (!parseNumber(where.substr(at, colon == std::string::npos ? std::string::npos : colon - at), &v) || !v.isInteger || v.i < 0)
        error(line, "expected BINDING, SET:BINDING or SET:BINDING:ELEMENT, got '" + where + "'");
      parts.push_back(static_cast<uint32_t>(v.i));
      if (colon == std::string::npos) break;
      at = colon + 1;
    }
    if (parts.size() > 3) error(line, "expected BINDING, SET:BINDING or SET:BINDING:ELEMENT, got '" + where + "'");
    if (parts.size() == 1) binding = parts[0];
    else set = parts[0], binding = parts[1];
    if (parts.size() == 3) element = parts[2];
    if (extent > kMaxBufferBytes) error(line, kind + " " + where + " of " + std::to_string(extent) + " bytes is too large");
    std::string name = kind + "_" + std::to_string(set) + "_" + std::to_string(binding);
    if (element) name += "_" + std::to_string(element);
    for (Buffer& existing : script_.buffers)
      if (existing.name == name) {
        if (existing.bytes.size() < extent) existing.bytes.resize(extent, 0);
        return name;
      }
    Buffer buf;
    buf.name = name;
    buf.hasType = true;
    std::string why;
    parseDataType("uint8", false, &buf.type, &why);
    buf.sized = true;
    buf.bytes.assign(std::max<uint64_t>(extent, 4), 0);
    buf.loc = {line, 1};
    script_.buffers.push_back(buf);
    for (Pipeline& p : script_.pipelines) {
      Bind bind;
      bind.kind = kind == "ssbo" ? BindKind::Storage : BindKind::Uniform;
      bind.asWord = kind == "ssbo" ? "storage" : "uniform";
      bind.buffer = name;
      bind.set = set, bind.binding = binding;
      bind.arrayElement = element;
      bind.loc = {line, 1};
      p.binds.push_back(bind);
    }
    return name;
  }

  std::string pushBuffer(int line, uint64_t extent) {
    if (extent > 128) error(line, "push constants past byte 128");
    for (Buffer& existing : script_.buffers)
      if (existing.name == "push_constants") {
        if (existing.bytes.size() < extent) existing.bytes.resize(extent, 0);
        return existing.name;
      }
    Buffer buf;
    buf.name = "push_constants";
    buf.hasType = true;
    std::string why;
    parseDataType("uint8", false, &buf.type, &why);
    buf.sized = true;
    buf.bytes.assign(extent, 0);
    script_.buffers.push_back(buf);
    for (Pipeline& p : script_.pipelines) {
      Bind bind;
      bind.kind = BindKind::PushConstant;
      bind.asWord = "push_constant";
      bind.buffer = buf.name;
      p.binds.push_back(bind);
    }
    return buf.name;
  }

  ElementType valueType(int line, const std::string& glsl, bool std140) {
    std::string amber = amberTypeName(glsl);
    ElementType t;
    std::string why;
    if (amber.empty() || !parseDataType(amber, std140, &t, &why)) error(line, "unknown type '" + glsl + "'");
    return t;
  }

  std::vector<Value> numbers(int line, const std::vector<std::string>& w, size_t from) {
    std::vector<Value> out;
    for (size_t i = from; i < w.size(); ++i) {
      Value v;
      if (!parseNumber(w[i], &v)) error(line, "expected a number, got '" + w[i] + "'");
      out.push_back(v);
    }
    return out;
  }

  // Values of `type` packed from byte 0 in the type's array stride.
  static std::vector<uint8_t> pack(const ElementType& type, const std::vector<Value>& values) {
    std::vector<uint8_t> bytes;
    const Layout& L = type.layout;
    for (size_t i = 0; i < values.size(); ++i) {
      const Field& f = L.fields[i % L.fields.size()];
      storeValue(bytes, (i / L.fields.size()) * L.stride + f.offset, f.scalar, values[i]);
    }
    return bytes;
  }

  // `KIND TYPE OFFSET values` written into a buffer (ubo/ssbo subdata, push, VkRunner's uniform).
  void writeBuffer(int line, const std::string& kind, const std::string& where, const std::vector<std::string>& w, size_t typeAt) {
    if (w.size() < typeAt + 2) error(line, "expected TYPE OFFSET values");
    ElementType type = valueType(line, w[typeAt], kind == "ubo");
    Value offset;
    if (!parseNumber(w[typeAt + 1], &offset) || !offset.isInteger || offset.i < 0) error(line, "expected a byte offset, got '" + w[typeAt + 1] + "'");
    std::vector<Value> values = numbers(line, w, typeAt + 2);
    if (values.empty() || values.size() % type.layout.fields.size())
      error(line, std::to_string(values.size()) + " values for " + w[typeAt] + " (" + std::to_string(type.layout.fields.size()) + " per element)");
    Command c;
    c.kind = Command::Kind::WriteBuffer;
    c.loc = {line, 1};
    c.bytes = pack(type, values);
    c.px = static_cast<uint32_t>(offset.i);
    uint64_t extent = uint64_t(offset.i) + c.bytes.size();
    c.buffer = kind == "push" ? pushBuffer(line, extent) : bufferFor(line, kind, where, extent);
    if (!c.buffer.empty()) script_.commands.push_back(c);
  }

  std::vector<Tolerance> tolerances() const {
    if (!tolerances_.empty()) return tolerances_;
    return {{tolerance_ * 255.0, false}};  // in the 0..255 units of Command::color
  }

  void probe(int line, const std::vector<std::string>& w, size_t at, bool relative) {
    // probe [rect] rgb|rgba ... / probe all rgb|rgba ...
    Command c;
    c.kind = Command::Kind::ExpectProbe;
    c.loc = {line, 1};
    c.buffer = "framebuffer";
    bool all = at < w.size() && w[at] == "all";
    bool rect = at < w.size() && w[at] == "rect";
    if (all || rect) ++at;
    if (at >= w.size() || (w[at] != "rgb" && w[at] != "rgba")) {
      unsupported(line, "probe " + std::string(relative ? "(relative) " : "") + (at < w.size() ? w[at] : ""));
      return;
    }
    c.rgba = w[at++] == "rgba";
    std::vector<Value> v = numbers(line, w, at);
    size_t position = all ? 0 : rect ? 4 : 2, channels = c.rgba ? 4 : 3;
    // piglit reads the numbers it needs and ignores the rest ("probe rgb x y r g b a" occurs).
    if (v.size() < position + channels) error(line, "probe needs " + std::to_string(position + channels) + " numbers");
    auto coordinate = [&](size_t i, uint32_t size) {
      if (!relative) return static_cast<uint32_t>(std::max<int64_t>(0, v[i].i));
      return static_cast<uint32_t>(std::clamp(v[i].d * size, 0.0, double(size)));
    };
    if (all) {
      c.px = 0, c.py = 0, c.pw = width_, c.ph = height_;
    } else {
      c.px = coordinate(0, width_), c.py = coordinate(1, height_);
      if (rect) c.pw = coordinate(2, width_), c.ph = coordinate(3, height_);
      if (relative) c.px = std::min(c.px, width_ - 1), c.py = std::min(c.py, height_ - 1);
    }
    for (size_t i = 0; i < channels; ++i) c.color[i] = v[position + i].d * 255.0;
    c.tolerances = tolerances();
    script_.commands.push_back(c);
  }

  // probe ssbo TYPE BINDING OFFSET OP values
  void probeBuffer(int line, const std::vector<std::string>& w) {
    if (w.size() < 7) error(line, "expected probe ssbo TYPE BINDING OFFSET OP values");
    Command c;
    c.kind = Command::Kind::ExpectValues;
    c.loc = {line, 1};
    c.valueType = valueType(line, w[2], false);
    c.valueTypeGiven = true;
    Value offset;
    if (!parseNumber(w[4], &offset) || !offset.isInteger || offset.i < 0) error(line, "expected a byte offset, got '" + w[4] + "'");
    c.px = static_cast<uint32_t>(offset.i);
    static const std::map<std::string, Comparator> kOps = {{"==", Comparator::Eq}, {"!=", Comparator::Ne}, {"<", Comparator::Lt},
                                                          {"<=", Comparator::Le}, {">", Comparator::Gt}, {">=", Comparator::Ge},
                                                          {"~=", Comparator::FuzzyEq}};
    auto op = kOps.find(w[5]);
    if (op == kOps.end()) error(line, "unknown comparison '" + w[5] + "' (== != < <= > >= ~=)");
    c.comparator = op->second;
    c.values = numbers(line, w, 6);
    if (c.comparator == Comparator::FuzzyEq) c.tolerances = {{tolerances_.empty() ? tolerance_ : tolerances_[0].value / 255.0, false}};
    c.buffer = bufferFor(line, "ssbo", w[3], 0);
    if (!c.buffer.empty()) script_.commands.push_back(c);
  }

  // The atomic-counter buffer of OpenGL binding `binding` (piglit's atomics_bos[binding]).
  std::string atomicCounterBuffer(int line, uint32_t binding) {
    const std::string name = "atomic_counters_" + std::to_string(binding);
    if (script_.findBuffer(name)) return name;
    Buffer buf;
    buf.name = name;
    buf.hasType = buf.sized = true;
    std::string why;
    parseDataType("uint8", false, &buf.type, &why);
    buf.atomicCounterBinding = static_cast<int>(binding);
    buf.loc = {line, 1};
    script_.buffers.push_back(buf);
    return name;
  }

  // shader_runner.c: `atomic counters N` makes binding 0's buffer of N zeroed counters,
  // `atomic counter buffer B N` binding B's, and `atomic counter B I V` sets counter I of B to V.
  void atomicCounters(int line, const std::vector<std::string>& w) {
    std::vector<Value> v = numbers(line, w, w[1] == "counters" ? 2 : w.size() > 2 && w[2] == "buffer" ? 3 : 2);
    for (const Value& x : v)
      if (!x.isInteger || x.i < 0) error(line, "expected unsigned integers in '" + w[0] + " " + w[1] + " ...'");
    const bool create = w[1] == "counters" || (w.size() > 2 && w[2] == "buffer");
    if ((w[1] == "counters" && v.size() != 1) || (create && w[1] == "counter" && v.size() != 2) || (!create && v.size() != 3))
      error(line, "expected atomic counters N, atomic counter buffer BINDING N or atomic counter BINDING INDEX VALUE");
    const uint32_t binding = w[1] == "counters" ? 0 : static_cast<uint32_t>(v[0].i);
    Command c;
    c.kind = Command::Kind::WriteBuffer;
    c.loc = {line, 1};
    c.buffer = atomicCounterBuffer(line, binding);
    Buffer* buffer = nullptr;
    for (Buffer& b : script_.buffers)
      if (b.name == c.buffer) buffer = &b;
    if (create) {
      // A new buffer of zeros each time, as glBufferData makes one.
      const uint64_t bytes = uint64_t(v.back().i) * 4;
      if (bytes > kMaxBufferBytes) error(line, "too many atomic counters");
      if (buffer->bytes.size() < bytes) buffer->bytes.resize(bytes, 0);
      c.bytes.assign(bytes, 0);
    } else {
      c.px = static_cast<uint32_t>(v[1].i) * 4;
      storeValue(c.bytes, 0, Scalar::Uint32, v[2]);
      if (buffer->bytes.size() < c.px + 4u) buffer->bytes.resize(c.px + 4u, 0);
    }
    if (buffer->bytes.empty()) buffer->bytes.assign(4, 0);
    if (!c.bytes.empty()) script_.commands.push_back(c);
  }

  // probe atomic counter INDEX OP VALUE (binding 0's counter INDEX) or
  // probe atomic counter buffer BINDING BYTE_OFFSET OP VALUE.
  void probeAtomicCounter(int line, const std::vector<std::string>& w) {
    const bool buffer = w.size() > 3 && w[3] == "buffer";
    const size_t op = buffer ? 6 : 4;
    if (w.size() != op + 2) error(line, buffer ? "expected probe atomic counter buffer BINDING OFFSET OP VALUE" : "expected probe atomic counter INDEX OP VALUE");
    std::vector<std::string> numeric(w.begin() + (buffer ? 4 : 3), w.begin() + long(op));
    numeric.push_back(w[op + 1]);
    std::vector<Value> v = numbers(line, numeric, 0);
    for (const Value& x : v)
      if (!x.isInteger || x.i < 0) error(line, "expected unsigned integers in '" + trim(uncommented(lines_[size_t(line - 1)])) + "'");
    static const std::map<std::string, Comparator> kOps = {{"==", Comparator::Eq}, {"!=", Comparator::Ne}, {"<", Comparator::Lt},
                                                          {"<=", Comparator::Le}, {">", Comparator::Gt}, {">=", Comparator::Ge}};
    auto comparator = kOps.find(w[op]);
    if (comparator == kOps.end()) error(line, "unknown comparison '" + w[op] + "' (== != < <= > >=)");
    Command c;
    c.kind = Command::Kind::ExpectValues;
    c.loc = {line, 1};
    c.comparator = comparator->second;
    c.valueType = valueType(line, "uint", false);
    c.valueTypeGiven = true;
    c.buffer = atomicCounterBuffer(line, buffer ? static_cast<uint32_t>(v[0].i) : 0);
    c.px = static_cast<uint32_t>(buffer ? v[1].i : v[0].i * 4);
    c.values = {v.back()};
    script_.commands.push_back(c);
  }

  void pipelineState(int line, const std::vector<std::string>& w) {
    if (drawn_) {
      unsupported(line, w[0] + " after the first draw (one pipeline state per test)");
      return;
    }
    if (w.size() < 2) error(line, w[0] + " needs a value");
    std::string v = w[1];
    auto vkName = [](std::string s, const std::string& prefix) {
      if (s.rfind(prefix, 0) == 0) s = s.substr(prefix.size());
      for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      return s;
    };
    for (Pipeline& p : script_.pipelines) {
      if (p.compute) continue;
      if (w[0] == "depthTestEnable") p.depthTest = v == "true";
      else if (w[0] == "depthWriteEnable") p.depthWrite = v == "true";
      else if (w[0] == "depthCompareOp") p.depthCompare = vkName(v, "VK_COMPARE_OP_");
      else if (w[0] == "cullMode") {
        std::string m = vkName(v, "VK_CULL_MODE_");
        p.cullMode = m == "back_bit" ? "back" : m == "front_bit" ? "front" : m == "none" ? "none" : "front_and_back";
      } else if (w[0] == "frontFace") p.frontFace = vkName(v, "VK_FRONT_FACE_");
      else if (w[0] == "polygonMode") p.polygonMode = vkName(v, "VK_POLYGON_MODE_");
      else if (w[0] == "depthClampEnable") p.depthClamp = v == "true";
    }
    if (w[0] == "polygonMode" && v != "VK_POLYGON_MODE_FILL" && v != "VK_POLYGON_MODE_LINE" && v != "VK_POLYGON_MODE_POINT")
      error(line, "unknown polygonMode '" + v + "'");
    static const std::map<std::string, int> kBiasFactor = {
        {"depthBiasConstantFactor", 0}, {"depthBiasClamp", 1}, {"depthBiasSlopeFactor", 2}};
    if (auto f = kBiasFactor.find(w[0]); f != kBiasFactor.end()) {
      Value value;
      if (!parseNumber(v, &value)) error(line, w[0] + " needs a number, got '" + v + "'");
      depthBias_[f->second] = static_cast<float>(value.d);
    }
    if (w[0] == "depthBiasEnable") depthBiasEnabled_ = v == "true";
    for (Pipeline& p : script_.pipelines) {
      p.depthBiasConstant = depthBiasEnabled_ ? depthBias_[0] : 0;
      p.depthBiasClamp = depthBiasEnabled_ ? depthBias_[1] : 0;
      p.depthBiasSlope = depthBiasEnabled_ ? depthBias_[2] : 0;
    }
  }

  void draw(int line, const std::vector<std::string>& w) {
    drawn_ = true;
    Command c;
    c.loc = {line, 1};
    if (w[1] == "rect") {
      size_t at = 2;
      bool ortho = false;
      while (at < w.size() && (w[at] == "ortho" || w[at] == "patch")) {
        (w[at] == "patch" ? c.patch : ortho) = true;
        ++at;
      }
      std::vector<Value> v = numbers(line, w, at);
      if (v.size() != 4) error(line, "draw rect needs x y width height");
      c.kind = Command::Kind::DrawRect;
      c.pipeline = "rect";
      c.x = static_cast<float>(v[0].d), c.y = static_cast<float>(v[1].d), c.w = static_cast<float>(v[2].d), c.h = static_cast<float>(v[3].d);
      c.ndc = !ortho;
      script_.commands.push_back(c);
      return;
    }
    // draw arrays [instanced] [indexed] MODE FIRST COUNT [INSTANCES]
    size_t at = 2;
    bool instanced = false;
    while (at < w.size() && (w[at] == "instanced" || w[at] == "indexed")) {
      if (w[at] == "instanced") instanced = true;
      else c.indexed = true;
      ++at;
    }
    if (at >= w.size()) error(line, "draw arrays needs a primitive mode");
    std::string mode = w[at++];
    if (mode.rfind("GL_", 0) == 0) mode = mode.substr(3);
    static const std::map<std::string, std::string> kModes = {
        {"TRIANGLES", "TRIANGLE_LIST"}, {"TRIANGLE_LIST", "TRIANGLE_LIST"}, {"TRIANGLE_STRIP", "TRIANGLE_STRIP"},
        {"TRIANGLE_FAN", "TRIANGLE_FAN"}, {"POINTS", "POINT_LIST"}, {"POINT_LIST", "POINT_LIST"},
        {"LINES", "LINE_LIST"}, {"LINE_LIST", "LINE_LIST"}, {"LINE_STRIP", "LINE_STRIP"}, {"LINE_LOOP", "LINE_LOOP"},
        {"PATCHES", "PATCH_LIST"}, {"PATCH_LIST", "PATCH_LIST"},
        {"LINES_ADJACENCY", "LINE_LIST_WITH_ADJACENCY"}, {"LINE_LIST_WITH_ADJACENCY", "LINE_LIST_WITH_ADJACENCY"},
        {"LINE_STRIP_ADJACENCY", "LINE_STRIP_WITH_ADJACENCY"}, {"LINE_STRIP_WITH_ADJACENCY", "LINE_STRIP_WITH_ADJACENCY"},
        {"TRIANGLES_ADJACENCY", "TRIANGLE_LIST_WITH_ADJACENCY"}, {"TRIANGLE_LIST_WITH_ADJACENCY", "TRIANGLE_LIST_WITH_ADJACENCY"},
        {"TRIANGLE_STRIP_ADJACENCY", "TRIANGLE_STRIP_WITH_ADJACENCY"},
        {"TRIANGLE_STRIP_WITH_ADJACENCY", "TRIANGLE_STRIP_WITH_ADJACENCY"}};
    auto m = kModes.find(mode);
    if (m == kModes.end()) error(line, "unknown primitive mode '" + w[at - 1] + "'");
    c.topology = m->second;
    std::vector<Value> v = numbers(line, w, at);
    if (v.size() < 2 || v.size() > 3) error(line, "draw arrays needs FIRST COUNT [INSTANCES]");
    c.kind = Command::Kind::DrawArray;
    c.pipeline = pipeline("arrays") ? "arrays" : "rect";
    // Indexed draws (VkRunner) read the indices from the first and add FIRST to each one.
    if (c.indexed) c.baseVertex = static_cast<int32_t>(v[0].i);
    else c.start = static_cast<uint32_t>(v[0].i);
    c.count = static_cast<uint32_t>(v[1].i);
    c.countGiven = true;
    if (v.size() == 3) c.instanceCount = static_cast<uint32_t>(v[2].i);
    else if (instanced) error(line, "draw arrays instanced needs an instance count");
    if (c.indexed && indices_.empty()) error(line, "draw arrays indexed without an [indices] section");
    script_.commands.push_back(c);
  }

  void test(const Section& s) {
    for (const auto& [line, text] : s.lines) {
      std::vector<std::string> w = words(uncommented(text));
      if (w.empty()) continue;
      const std::string& k = w[0];
      if (k == "clear" && w.size() == 1) {
        script_.commands.push_back(clearCommand(line, Command::Kind::Clear));
      } else if (k == "clear" && w[1] == "color") {
        std::vector<Value> v = numbers(line, w, 2);
        if (v.size() != 4) error(line, "clear color needs r g b a");
        Command c = clearCommand(line, Command::Kind::ClearColor);
        for (int i = 0; i < 4; ++i) c.color[i] = v[i].d * 255.0;
        script_.commands.push_back(c);
      } else if (k == "clear" && (w[1] == "depth" || w[1] == "stencil")) {
        std::vector<Value> v = numbers(line, w, 2);
        if (v.size() != 1) error(line, "clear " + w[1] + " needs one value");
        Command c = clearCommand(line, w[1] == "depth" ? Command::Kind::ClearDepth : Command::Kind::ClearStencil);
        c.color[0] = v[0].d;
        script_.commands.push_back(c);
      } else if (k == "draw" && w.size() >= 2 && (w[1] == "rect" || w[1] == "arrays")) {
        draw(line, w);
      } else if (k == "compute") {
        std::vector<Value> v = numbers(line, w, 1);
        if (v.size() != 3) error(line, "compute needs x y z");
        if (!pipeline("compute")) error(line, "compute without a [compute shader]");
        Command c;
        c.kind = Command::Kind::Compute;
        c.loc = {line, 1};
        c.pipeline = "compute";
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
      } else if (k == "uniform" && w.size() >= 2 && w[1] == "frame_num") {
        unsupported(line, "uniform frame_num (animation frames)");
      } else if (k == "uniform" && w.size() >= 3) {
        Value offset;
        if (parseNumber(w[2], &offset) && !piglit_) writeBuffer(line, "push", "", w, 1);  // VkRunner: push constants
        else setUniform(line, w);
      } else if (k == "depthTestEnable" || k == "depthWriteEnable" || k == "depthCompareOp" || k == "cullMode" ||
                 k == "frontFace" || k == "polygonMode" || k == "depthClampEnable" || k == "depthBiasEnable" ||
                 k == "depthBiasConstantFactor" || k == "depthBiasClamp" || k == "depthBiasSlopeFactor") {
        pipelineState(line, w);
      } else if (k == "texture" && w.size() >= 2 && (w[1] == "rgbw" || w[1] == "checkerboard" || w[1] == "quads") && piglit_) {
        texture(line, w);
      } else if (k == "texparameter" && w.size() == 4 && (w[2] == "min" || w[2] == "mag") && piglit_) {
        texparameter(line, w);
      } else if (k == "patch" && w.size() == 4 && w[1] == "parameter" && w[2] == "vertices") {
        Value n;
        if (!parseNumber(w[3], &n) || !n.isInteger || n.i < 1) error(line, "expected a vertex count, got '" + w[3] + "'");
        if (drawn_) {
          unsupported(line, "patch parameter vertices after the first draw (one pipeline state per test)");
        } else {
          for (Pipeline& p : script_.pipelines) p.patchControlPoints = static_cast<uint32_t>(n.i);
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

  // piglit's procedural textures (piglit-util-gl.c), as RGBA8 images on a texture unit, with the
  // sampler state piglit gives them: `texture rgbw UNIT (W, H)` is red, green, blue and white
  // quadrants (red at the first row and column), nearest, clamped to the edge;
  // `texture quads UNIT LEVEL (W, H) (SX, SY) (bl) (br) (tl) (tr)` is squares of SX x SY, bl where
  // the square's row and column (from the first row and column) are even, br at an odd column,
  // tl at an odd row, tr where both are odd, nearest; `texture checkerboard UNIT LEVEL (W, H)
  // (colour0) (colour1)` is quads of W/2 x H/2 with colour1 where exactly one is odd. piglit clamps
  // both to a red border, which Vulkan's border colours cannot express: they are clamped to the
  // edge here, which only differs for coordinates outside [0, 1].
  void texture(int line, const std::vector<std::string>& w) {
    const bool checkerboard = w[1] == "checkerboard", quads = w[1] == "quads";
    Value first;
    if (w.size() > 2 && !parseNumber(w[2], &first)) return unsupported(line, "texture " + w[1] + " " + w[2]);  // 2DArray, 1D, ...
    std::vector<std::string> numeric(w.begin(), w.end());
    // An internal format after the size: RGBA8 is what piglit makes anyway.
    if (w[1] == "rgbw" && numeric.size() == 6) {
      if (numeric.back() != "GL_RGBA8" && numeric.back() != "GL_RGBA") return unsupported(line, "texture rgbw " + numeric.back());
      numeric.pop_back();
    }
    std::vector<Value> v = numbers(line, numeric, 2);
    const size_t need = checkerboard ? 12 : quads ? 22 : 3;
    if (v.size() != need) error(line, "texture " + w[1] + " needs " + std::to_string(need) + " numbers");
    const int unit = static_cast<int>(v[0].i);
    const size_t size = checkerboard || quads ? 2 : 1;
    if (size == 2 && v[1].i != 0) return unsupported(line, "texture " + w[1] + " at mip level " + std::to_string(v[1].i));
    const uint32_t width = static_cast<uint32_t>(v[size].i), height = static_cast<uint32_t>(v[size + 1].i);
    if (width == 0 || height == 0 || width > kMaxImageDimension || height > kMaxImageDimension)
      error(line, "texture size out of range");
    // Square sizes and the four colours (at v[first colour + 4k]) of the quads pattern.
    uint32_t squareWidth = std::max(1u, width / 2), squareHeight = std::max(1u, height / 2);
    std::array<size_t, 4> colourAt{4, 8, 8, 4};  // checkerboard: bl, br, tl, tr
    if (quads) {
      if (v[4].i <= 0 || v[5].i <= 0) error(line, "texture quads needs square sizes above 0");
      squareWidth = static_cast<uint32_t>(v[4].i), squareHeight = static_cast<uint32_t>(v[5].i);
      colourAt = {6, 10, 14, 18};
    }
    Buffer image;
    image.name = "texture_unit_" + std::to_string(unit);
    image.isImage = image.hasType = image.sized = true;
    image.textureUnit = unit;
    image.width = width, image.height = height;
    image.loc = {line, 1};
    std::string why;
    parseFormat("R8G8B8A8_UNORM", &image.type, &why);
    auto byte = [](double x) { return static_cast<uint8_t>(std::lround(std::clamp(x, 0.0, 1.0) * 255.0)); };
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x) {
        std::array<double, 4> c{};
        if (checkerboard || quads) {
          const size_t quadrant = ((y / squareHeight) & 1) * 2 + ((x / squareWidth) & 1);
          for (size_t i = 0; i < 4; ++i) c[i] = v[colourAt[quadrant] + i].d;
        } else {
          bool left = x < width / 2, bottom = y < height / 2;
          c = bottom ? (left ? std::array<double, 4>{1, 0, 0, 1} : std::array<double, 4>{0, 1, 0, 1})
                     : (left ? std::array<double, 4>{0, 0, 1, 1} : std::array<double, 4>{1, 1, 1, 1});
        }
        for (double component : c) image.bytes.push_back(byte(component));
      }
    Sampler sampler;
    sampler.name = "sampler_unit_" + std::to_string(unit);
    sampler.textureUnit = unit;
    sampler.addressMode = {"clamp_to_edge", "clamp_to_edge", "clamp_to_edge"};
    sampler.loc = {line, 1};
    // A later texture on the same unit replaces the earlier one.
    script_.buffers.erase(std::remove_if(script_.buffers.begin(), script_.buffers.end(), [&](const Buffer& b) { return b.textureUnit == unit; }),
                          script_.buffers.end());
    script_.samplers.erase(std::remove_if(script_.samplers.begin(), script_.samplers.end(), [&](const Sampler& x) { return x.textureUnit == unit; }),
                           script_.samplers.end());
    script_.buffers.push_back(image);
    script_.samplers.push_back(sampler);
    lastTextureUnit_ = unit;
  }

  // texparameter 2D min|mag nearest|linear: the filter of the last texture's unit.
  void texparameter(int line, const std::vector<std::string>& w) {
    if (w[1] != "2D") return unsupported(line, "texparameter " + w[1]);
    if (w[3] != "nearest" && w[3] != "linear") return unsupported(line, "texparameter " + w[2] + " " + w[3]);
    for (Sampler& sampler : script_.samplers)
      if (sampler.textureUnit == lastTextureUnit_) (w[2] == "min" ? sampler.linearMin : sampler.linearMag) = w[3] == "linear";
  }

  Command clearCommand(int line, Command::Kind kind) {
    Command c;
    c.kind = kind;
    c.loc = {line, 1};
    c.pipeline = "rect";
    return c;
  }

  // piglit: uniform TYPE NAME values
  void setUniform(int line, const std::vector<std::string>& w) {
    std::string amber = amberTypeName(w[1]);
    if (amber.empty()) return unsupported(line, "uniform " + w[1]);
    Command c;
    c.kind = Command::Kind::SetUniform;
    c.loc = {line, 1};
    c.uniform = w[2];
    c.arrayElement = uboArrayIndex_;
    c.valueType = valueType(line, w[1], true);
    c.valueTypeGiven = true;
    // piglit sets as many components as are given (some of its files give fewer than the type has).
    c.values = numbers(line, w, 3);
    if (c.values.empty()) error(line, "uniform " + w[2] + " needs values");
    script_.commands.push_back(c);
  }
};

}  // namespace

bool isShaderTestPath(const std::string& path) {
  const std::string suffix = ".shader_test";
  return path.size() >= suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
}

ParseResult parseShaderTest(const std::string& text, const std::string& name) {
  ParseResult r;
  try {
    ShaderTestParser p(text, name);
    r.script = p.run();
    r.ok = true;
  } catch (const ShaderTestError& e) {
    r.error = name + ":" + std::to_string(e.line) + ": error: " + e.message;
  }
  return r;
}

}  // namespace parity::harness::script
