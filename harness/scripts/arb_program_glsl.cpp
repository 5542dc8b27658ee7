// ARB assembly programs as Vulkan GLSL 4.50, following ARB_vertex_program and
// ARB_fragment_program: each instruction reads its operands into vec4s (negation and swizzles
// applied), computes a vec4 as the specification defines it, and writes it through the
// destination's write mask (clamped for _SAT). Registers are vec4 variables in main(); outputs
// are kept in variables and written once at the end.
#include "harness/scripts/arb_program_glsl.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <set>
#include <vector>

namespace parity::harness::script {

namespace {

struct Untranslated {
  std::string what;
};

// Tokens: identifiers (with `1D`, `2D`, `3D` as texture targets), numbers, `..` and single
// punctuation characters. `#` starts a comment to the end of the line.
struct Token {
  enum Kind { Identifier, Number, Punct, End } kind = End;
  std::string text;
};

std::vector<Token> tokenize(const std::string& s) {
  std::vector<Token> out;
  size_t i = 0;
  auto isIdent = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '$'; };
  while (i < s.size()) {
    const char c = s[i];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '#') {
      while (i < s.size() && s[i] != '\n') ++i;
    } else if (std::isdigit(static_cast<unsigned char>(c)) && i + 1 < s.size() && s[i + 1] == 'D' &&
               (i + 2 >= s.size() || !isIdent(s[i + 2]))) {
      out.push_back({Token::Identifier, s.substr(i, 2)});
      i += 2;
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == '$') {
      size_t j = i;
      while (j < s.size() && isIdent(s[j])) ++j;
      out.push_back({Token::Identifier, s.substr(i, j - i)});
      i = j;
    } else if (std::isdigit(static_cast<unsigned char>(c)) || (c == '.' && i + 1 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 1])))) {
      size_t j = i;
      while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
      if (j < s.size() && s[j] == '.' && !(j + 1 < s.size() && s[j + 1] == '.')) {
        ++j;
        while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
      }
      if (j < s.size() && (s[j] == 'e' || s[j] == 'E')) {
        size_t k = j + 1;
        if (k < s.size() && (s[k] == '+' || s[k] == '-')) ++k;
        if (k < s.size() && std::isdigit(static_cast<unsigned char>(s[k]))) {
          j = k;
          while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
        }
      }
      out.push_back({Token::Number, s.substr(i, j - i)});
      i = j;
    } else if (c == '.' && i + 1 < s.size() && s[i + 1] == '.') {
      out.push_back({Token::Punct, ".."});
      i += 2;
    } else {
      out.push_back({Token::Punct, std::string(1, c)});
      ++i;
    }
  }
  out.push_back({Token::End, ""});
  return out;
}

std::string glslFloat(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  std::string s = buf;
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string vec4Of(const double (&v)[4]) {
  return "vec4(" + glslFloat(v[0]) + ", " + glslFloat(v[1]) + ", " + glslFloat(v[2]) + ", " + glslFloat(v[3]) + ")";
}

// An index in brackets: a number, a range a..b, or an address register's x plus an offset.
struct Index {
  int first = 0, last = -1;  // last >= 0: a range
  std::string address;       // relative: the register's name
};

struct Segment {
  std::string name;
  std::optional<Index> index;
};

class Translator {
 public:
  Translator(const std::string& text, uint32_t stateSet, uint32_t stateBinding)
      : stateSet_(stateSet), stateBinding_(stateBinding) {
    const size_t header = text.find("!!ARB");
    if (header == std::string::npos) throw Untranslated{"a program without an !!ARBvp1.0 or !!ARBfp1.0 header"};
    if (text.compare(header, 10, "!!ARBvp1.0") == 0) vertex_ = true;
    else if (text.compare(header, 10, "!!ARBfp1.0") != 0) throw Untranslated{"program header " + text.substr(header, 10)};
    tokens_ = tokenize(text.substr(header + 10));
  }

  ArbProgramGlsl run() {
    while (!(peek().kind == Token::Identifier && peek().text == "END")) {
      if (peek().kind == Token::End) throw Untranslated{"a program without END"};
      statement();
    }
    ArbProgramGlsl out;
    out.vertex = vertex_;
    out.state.envCount = envCount_;
    out.state.localCount = localCount_;
    out.textures = textures_;
    out.glsl = assemble();
    return out;
  }

 private:
  // ---- tokens ----
  const Token& peek(size_t ahead = 0) const { return tokens_[std::min(at_ + ahead, tokens_.size() - 1)]; }
  Token next() { return tokens_[std::min(at_++, tokens_.size() - 1)]; }
  bool accept(const std::string& punct) {
    if (peek().kind != Token::Punct || peek().text != punct) return false;
    ++at_;
    return true;
  }
  void expect(const std::string& punct) {
    if (!accept(punct)) throw Untranslated{"'" + punct + "' expected before '" + peek().text + "'"};
  }
  std::string identifier() {
    if (peek().kind != Token::Identifier) throw Untranslated{"a name expected before '" + peek().text + "'"};
    return next().text;
  }
  int integer() {
    if (peek().kind != Token::Number) throw Untranslated{"an integer expected before '" + peek().text + "'"};
    return std::atoi(next().text.c_str());
  }
  double signedNumber() {
    double sign = 1;
    if (accept("-")) sign = -1;
    else accept("+");
    if (peek().kind != Token::Number) throw Untranslated{"a number expected before '" + peek().text + "'"};
    return sign * std::strtod(next().text.c_str(), nullptr);
  }

  // ---- statements ----
  void statement() {
    const std::string word = identifier();
    if (word == "OPTION") option(identifier());
    else if (word == "TEMP" || word == "ADDRESS") {
      do declareRegister(word == "TEMP", identifier());
      while (accept(","));
    } else if (word == "ATTRIB") {
      const std::string name = identifier();
      expect("=");
      Variable v;
      v.kind = Variable::Attrib;
      v.glsl = sourceBinding(path());
      declare(name, v);
    } else if (word == "OUTPUT") {
      const std::string name = identifier();
      expect("=");
      Variable v;
      v.kind = Variable::Output;
      v.glsl = resultBinding(path());
      declare(name, v);
    } else if (word == "ALIAS") {
      const std::string name = identifier();
      expect("=");
      const std::string target = identifier();
      auto it = variables_.find(target);
      if (it == variables_.end()) throw Untranslated{"ALIAS of undeclared '" + target + "'"};
      declare(name, it->second);
    } else if (word == "PARAM") {
      param();
    } else {
      instruction(word);
    }
    expect(";");
  }

  void option(const std::string& name) {
    static const std::set<std::string> kHints = {"ARB_precision_hint_fastest", "ARB_precision_hint_nicest"};
    if (vertex_ && name == "ARB_position_invariant") positionInvariant_ = true;
    else if (!vertex_ && (kHints.count(name) || name == "ARB_fragment_program_shadow" || name == "ARB_draw_buffers")) {
    } else throw Untranslated{"OPTION " + name};
  }

  struct Variable {
    enum Kind { Temp, Address, Param, ParamArray, Attrib, Output } kind = Temp;
    std::string glsl;  // the GLSL variable, or expression of an attribute
    int size = 1;      // of a parameter array
  };

  void declare(const std::string& name, const Variable& v) {
    if (!variables_.emplace(name, v).second) throw Untranslated{"'" + name + "' declared twice"};
  }

  std::string freshName() { return "parity_r" + std::to_string(names_++); }

  void declareRegister(bool temp, const std::string& name) {
    Variable v;
    v.kind = temp ? Variable::Temp : Variable::Address;
    v.glsl = freshName();
    body_ += temp ? "  vec4 " + v.glsl + " = vec4(0.0);\n" : "  ivec4 " + v.glsl + " = ivec4(0);\n";
    declare(name, v);
  }

  // PARAM name = item; PARAM name[n] = { item, ... }; PARAM name[] = { ... }.
  void param() {
    const std::string name = identifier();
    Variable v;
    v.glsl = freshName();
    int declared = -1;
    bool array = false;
    if (accept("[")) {
      array = true;
      if (!accept("]")) {
        declared = integer();
        expect("]");
      }
    }
    expect("=");
    std::vector<std::string> items;
    if (array) {
      expect("{");
      do {
        std::vector<std::string> more = paramItems(true);
        items.insert(items.end(), more.begin(), more.end());
      } while (accept(","));
      expect("}");
    } else {
      items = paramItems(false);
    }
    if (items.empty() || (!array && items.size() != 1) || (declared >= 0 && size_t(declared) != items.size()))
      throw Untranslated{"PARAM " + name + " of " + std::to_string(items.size()) + " items"};
    if (array) {
      v.kind = Variable::ParamArray;
      v.size = static_cast<int>(items.size());
      std::string list;
      for (const std::string& item : items) list += (list.empty() ? "" : ",\n    ") + item;
      body_ += "  vec4 " + v.glsl + "[" + std::to_string(v.size) + "] = vec4[](" + list + ");\n";
    } else {
      v.kind = Variable::Param;
      body_ += "  vec4 " + v.glsl + " = " + items[0] + ";\n";
    }
    declare(name, v);
  }

  // One item of a PARAM's initialiser: a constant or state or program parameters (a range or a
  // whole matrix in an array's list).
  std::vector<std::string> paramItems(bool inArray) {
    if (peek().text == "{") return {vectorConstant()};
    if (peek().kind == Token::Number || peek().text == "-" || peek().text == "+") {
      const std::string x = glslFloat(signedNumber());
      return {"vec4(" + x + ")"};
    }
    std::vector<std::string> rows = bindingRows(path(), inArray);
    return rows;
  }

  std::string vectorConstant() {
    expect("{");
    double v[4] = {0, 0, 0, 1};
    int n = 0;
    do {
      if (n == 4) throw Untranslated{"a constant of more than four components"};
      v[n++] = signedNumber();
    } while (accept(","));
    expect("}");
    return vec4Of(v);
  }

  // A dotted reference: name[index].name[index]... (a final swizzle or mask is one segment).
  std::vector<Segment> path() {
    std::vector<Segment> segments;
    do {
      Segment s;
      s.name = identifier();
      if (accept("[")) s.index = index(), expect("]");
      segments.push_back(s);
    } while (peek().text == "." && peek(1).kind == Token::Identifier && (++at_, true));
    return segments;
  }

  Index index() {
    Index i;
    if (peek().kind == Token::Identifier) {
      i.address = identifier();
      expect(".");
      if (identifier() != "x") throw Untranslated{"relative addressing through a component other than x"};
      if (accept("+")) i.first = integer();
      else if (accept("-")) i.first = -integer();
      return i;
    }
    i.first = integer();
    if (accept("..")) i.last = integer();
    return i;
  }

  static int single(const Segment& s) {
    if (!s.index || s.index->last >= 0 || !s.index->address.empty()) throw Untranslated{"'" + s.name + "' needs one index"};
    return s.index->first;
  }

  // ---- bindings ----
  // Rows of state or program parameters; `many`: a range or a whole matrix is allowed.
  std::vector<std::string> bindingRows(const std::vector<Segment>& p, bool many) {
    size_t used = 0;
    std::vector<std::string> rows = builtinRows(p, used);
    if (used != p.size()) throw Untranslated{"'" + p[used].name + "' after a parameter binding"};
    if (!many && rows.size() != 1) throw Untranslated{"a range of parameters where one is read"};
    return rows;
  }

  std::vector<std::string> builtinRows(const std::vector<Segment>& p, size_t& used) {
    const std::string& root = p[0].name;
    if (root == "program" && p.size() >= 2 && (p[1].name == "env" || p[1].name == "local")) {
      const bool env = p[1].name == "env";
      if (!p[1].index || !p[1].index->address.empty()) throw Untranslated{"program." + p[1].name + " without an index"};
      const int first = p[1].index->first, last = p[1].index->last >= 0 ? p[1].index->last : first;
      if (first < 0 || last < first || last >= 4096) throw Untranslated{"program." + p[1].name + " index " + std::to_string(last)};
      uint32_t& count = env ? envCount_ : localCount_;
      count = std::max(count, uint32_t(last + 1));
      std::vector<std::string> rows;
      for (int i = first; i <= last; ++i) rows.push_back("parity_state." + std::string(env ? "env" : "local") + "[" + std::to_string(i) + "]");
      used = 2;
      return rows;
    }
    if (root == "state" && p.size() >= 3 && p[1].name == "matrix") return matrixRows(p, used);
    if (root == "state" && p.size() >= 3 && p[1].name == "depth" && p[2].name == "range") {
      used = 3;
      return {"vec4(0.0, 1.0, 1.0, 1.0)"};  // glDepthRange(0, 1): near, far, far - near
    }
    throw Untranslated{"the binding " + joined(p)};
  }

  std::vector<std::string> matrixRows(const std::vector<Segment>& p, size_t& used) {
    const Segment& which = p[2];
    std::string m;
    if (which.name == "modelview" && (!which.index || single(which) == 0)) m = "parity_state.modelView";
    else if (which.name == "projection" && !which.index) m = "parity_state.projection";
    else if (which.name == "mvp" && !which.index) m = "(parity_state.projection * parity_state.modelView)";
    else if (which.name == "texture" && (!which.index || single(which) < 8)) m = "mat4(1.0)";  // piglit loads none
    else throw Untranslated{"state.matrix." + which.name + (which.index ? "[" + std::to_string(which.index->first) + "]" : "")};
    used = 3;
    if (used < p.size() && (p[used].name == "inverse" || p[used].name == "transpose" || p[used].name == "invtrans")) {
      const std::string& k = p[used++].name;
      m = k == "inverse" ? "inverse(" + m + ")" : k == "transpose" ? "transpose(" + m + ")" : "transpose(inverse(" + m + "))";
    }
    int first = 0, last = 3;
    if (used < p.size() && p[used].name == "row") {
      if (!p[used].index || !p[used].index->address.empty()) throw Untranslated{"state.matrix row without an index"};
      first = p[used].index->first;
      last = p[used].index->last >= 0 ? p[used].index->last : first;
      ++used;
      if (first < 0 || last > 3 || last < first) throw Untranslated{"matrix rows " + std::to_string(first) + ".." + std::to_string(last)};
    }
    std::vector<std::string> rows;  // row i of a column-major matrix is column i of its transpose
    for (int i = first; i <= last; ++i) rows.push_back("transpose(" + m + ")[" + std::to_string(i) + "]");
    return rows;
  }

  static std::string joined(const std::vector<Segment>& p) {
    std::string s;
    for (const Segment& seg : p) s += (s.empty() ? "" : ".") + seg.name + (seg.index ? "[..]" : "");
    return s;
  }

  // An input attribute (vertex.* or fragment.*), `used` segments of the path.
  std::optional<std::string> attribute(const std::vector<Segment>& p, size_t& used) {
    const std::string& root = p[0].name;
    if (root != "vertex" && root != "fragment") return std::nullopt;
    if (p.size() < 2) throw Untranslated{"'" + root + "' without an attribute"};
    const Segment& a = p[1];
    used = 2;
    if ((root == "vertex") != vertex_) throw Untranslated{root + " attributes in a " + (vertex_ ? "vertex" : "fragment") + " program"};
    auto colour = [&](const char* primary, const char* secondary) {
      const bool named = used < p.size() && (p[used].name == "primary" || p[used].name == "secondary");
      const bool isSecondary = named && p[used].name == "secondary";
      if (named) ++used;
      return std::string(isSecondary ? secondary : primary);
    };
    auto unit = [&]() {
      const int n = a.index ? single(a) : 0;
      if (n < 0 || n >= 8) throw Untranslated{root + ".texcoord[" + std::to_string(n) + "]"};
      return std::to_string(n);
    };
    if (root == "vertex") {
      if (a.name == "position" || (a.name == "attrib" && single(a) == 0)) return std::string("parity_Vertex");
      if (a.name == "color") return colour("parity_state.color", "parity_state.secondaryColor");
      if (a.name == "texcoord") return "parity_state.texCoord[" + unit() + "]";
      if (a.name == "normal") return std::string("vec4(0.0, 0.0, 1.0, 1.0)");  // OpenGL's initial current normal
      if (a.name == "fogcoord") return std::string("vec4(0.0, 0.0, 0.0, 1.0)");
      throw Untranslated{"vertex." + a.name + (a.index ? "[" + std::to_string(a.index->first) + "]" : "")};
    }
    if (a.name == "color") return colour("parity_Color", "parity_SecondaryColor");
    if (a.name == "texcoord") return "parity_TexCoord[" + unit() + "]";
    if (a.name == "fogcoord") return std::string("vec4(parity_FogCoord, 0.0, 0.0, 1.0)");
    if (a.name == "position") return std::string("gl_FragCoord");
    throw Untranslated{"fragment." + a.name};
  }

  std::string sourceBinding(const std::vector<Segment>& p) {
    size_t used = 0;
    std::optional<std::string> a = attribute(p, used);
    if (!a || used != p.size()) throw Untranslated{"ATTRIB " + joined(p)};
    return *a;
  }

  // An output register (result.*): the variable main() keeps it in.
  std::string resultBinding(const std::vector<Segment>& p, size_t* usedOut = nullptr) {
    if (p[0].name != "result" || p.size() < 2) throw Untranslated{"output " + joined(p)};
    const Segment& r = p[1];
    size_t used = 2;
    std::string out;
    if (vertex_) {
      if (r.name == "position") out = "parity_out_position";
      else if (r.name == "fogcoord") out = "parity_out_fog";
      else if (r.name == "pointsize") out = "parity_out_unused";
      else if (r.name == "texcoord") {
        const int n = r.index ? single(r) : 0;
        if (n < 0 || n >= 8) throw Untranslated{"result.texcoord[" + std::to_string(n) + "]"};
        out = "parity_out_texcoord[" + std::to_string(n) + "]";
      } else if (r.name == "color") {
        // result.color[.front|.back][.primary|.secondary]: the back colours are read only with
        // two-sided lighting, which no command enables.
        bool back = false, secondary = false;
        if (used < p.size() && (p[used].name == "front" || p[used].name == "back")) back = p[used++].name == "back";
        if (used < p.size() && (p[used].name == "primary" || p[used].name == "secondary")) secondary = p[used++].name == "secondary";
        out = back ? "parity_out_unused" : secondary ? "parity_out_secondary" : "parity_out_color";
      } else throw Untranslated{"result." + r.name};
    } else {
      if (r.name == "color" && (!r.index || single(r) == 0)) out = "parity_out_color";
      else if (r.name == "depth") out = "parity_out_depth", writesDepth_ = true;
      else throw Untranslated{"result." + r.name + (r.index ? "[" + std::to_string(r.index->first) + "]" : "")};
    }
    if (usedOut) *usedOut = used;
    else if (used != p.size()) throw Untranslated{"output " + joined(p)};
    return out;
  }

  // ---- operands ----
  static bool isSwizzle(const std::string& s, bool maskOrder) {
    if (s.empty() || s.size() > 4) return false;
    const bool xyzw = s.find_first_not_of("xyzw") == std::string::npos, rgba = s.find_first_not_of("rgba") == std::string::npos;
    if (!xyzw && !rgba) return false;
    if (!maskOrder) return true;
    const std::string order = xyzw ? "xyzw" : "rgba";  // a write mask names each component once, in order
    int previous = -1;
    for (char c : s) {
      const int at = static_cast<int>(order.find(c));
      if (at <= previous) return false;
      previous = at;
    }
    return true;
  }

  static std::string xyzwOf(const std::string& s) {
    std::string out;
    for (char c : s) out += "xyzw"[std::string(c == 'r' || c == 'g' || c == 'b' || c == 'a' ? "rgba" : "xyzw").find(c)];
    return out;
  }

  // A source register without its swizzle, as a vec4 expression; `rest`: the segments after it.
  std::string sourceRegister(const std::vector<Segment>& p, size_t& used) {
    used = 1;
    auto var = variables_.find(p[0].name);
    if (var != variables_.end()) {
      const Variable& v = var->second;
      if (v.kind == Variable::ParamArray) {
        if (!p[0].index) throw Untranslated{"parameter array '" + p[0].name + "' read without an index"};
        const Index& i = *p[0].index;
        if (!i.address.empty()) {
          auto a = variables_.find(i.address);
          if (a == variables_.end() || a->second.kind != Variable::Address) throw Untranslated{"'" + i.address + "' is no address register"};
          // Out of range is undefined (ARB_vertex_program 2.14.4.1); the nearest element is read.
          return v.glsl + "[clamp(" + a->second.glsl + ".x + (" + std::to_string(i.first) + "), 0, " + std::to_string(v.size - 1) + ")]";
        }
        if (i.last >= 0 || i.first < 0 || i.first >= v.size) throw Untranslated{"parameter array '" + p[0].name + "' index"};
        return v.glsl + "[" + std::to_string(i.first) + "]";
      }
      if (p[0].index) throw Untranslated{"'" + p[0].name + "' indexed"};
      if (v.kind == Variable::Address || v.kind == Variable::Output) throw Untranslated{"'" + p[0].name + "' read as a source"};
      return v.glsl;
    }
    if (std::optional<std::string> a = attribute(p, used)) return *a;
    std::vector<std::string> rows = builtinRows(p, used);
    if (rows.size() != 1) throw Untranslated{"a range of parameters as an operand"};
    return rows[0];
  }

  // [-] register [.swizzle] | [-] scalar constant | [-] {vector constant} [.swizzle]
  std::string operand() {
    bool negate = false;
    if (accept("-")) negate = true;
    else accept("+");
    std::string value;
    if (peek().kind == Token::Number) {
      value = "vec4(" + glslFloat(std::strtod(next().text.c_str(), nullptr)) + ")";
    } else if (peek().text == "{") {
      value = vectorConstant();
      if (peek().text == "." && peek(1).kind == Token::Identifier) {
        ++at_;
        value = swizzled(value, identifier());
      }
    } else {
      std::vector<Segment> p = path();
      size_t used = 0;
      value = sourceRegister(p, used);
      if (used + 1 == p.size() && !p[used].index && isSwizzle(p[used].name, false)) value = swizzled(value, p[used++].name);
      if (used != p.size()) throw Untranslated{"operand " + joined(p)};
    }
    return negate ? "(-" + value + ")" : value;
  }

  static std::string swizzled(const std::string& value, const std::string& s) {
    if (!isSwizzle(s, false) || (s.size() != 1 && s.size() != 4)) throw Untranslated{"swizzle ." + s};
    const std::string c = xyzwOf(s);
    return value + "." + (c.size() == 1 ? std::string(4, c[0]) : c);
  }

  // ---- instructions ----
  struct Destination {
    std::string glsl;
    std::string mask = "xyzw";
    bool address = false;
  };

  Destination destination() {
    std::vector<Segment> p = path();
    Destination d;
    size_t used = 1;
    auto var = variables_.find(p[0].name);
    if (var != variables_.end()) {
      const Variable& v = var->second;
      if (v.kind != Variable::Temp && v.kind != Variable::Output && v.kind != Variable::Address)
        throw Untranslated{"'" + p[0].name + "' written"};
      d.glsl = v.glsl;
      d.address = v.kind == Variable::Address;
    } else {
      d.glsl = resultBinding(p, &used);
    }
    if (used + 1 == p.size() && !p[used].index && isSwizzle(p[used].name, true)) d.mask = xyzwOf(p[used++].name);
    if (used != p.size()) throw Untranslated{"destination " + joined(p)};
    return d;
  }

  void instruction(const std::string& word) {
    std::string op = word;
    bool saturate = false;
    if (op.size() > 4 && op.compare(op.size() - 4, 4, "_SAT") == 0) saturate = true, op.resize(op.size() - 4);
    static const std::map<std::string, int> kOperands = {
        {"ABS", 1}, {"ADD", 2}, {"ARL", 1}, {"DP3", 2}, {"DP4", 2}, {"DPH", 2}, {"DST", 2}, {"EX2", 1}, {"EXP", 1},
        {"FLR", 1}, {"FRC", 1}, {"LG2", 1}, {"LIT", 1}, {"LOG", 1}, {"MAD", 3}, {"MAX", 2}, {"MIN", 2}, {"MOV", 1},
        {"MUL", 2}, {"POW", 2}, {"RCP", 1}, {"RSQ", 1}, {"SGE", 2}, {"SLT", 2}, {"SUB", 2}, {"SWZ", 1}, {"XPD", 2},
        {"CMP", 3}, {"COS", 1}, {"KIL", 1}, {"LRP", 3}, {"SCS", 1}, {"SIN", 1}, {"TEX", 1}, {"TXB", 1}, {"TXP", 1}};
    static const std::set<std::string> kFragmentOnly = {"CMP", "COS", "KIL", "LRP", "SCS", "SIN", "TEX", "TXB", "TXP"};
    static const std::set<std::string> kVertexOnly = {"ARL", "EXP", "LOG"};
    auto arity = kOperands.find(op);
    if (arity == kOperands.end() || (vertex_ && kFragmentOnly.count(op)) || (!vertex_ && kVertexOnly.count(op)))
      throw Untranslated{"instruction " + word + " in a " + (vertex_ ? "vertex" : "fragment") + " program"};
    if (op == "KIL") {
      body_ += "  if (any(lessThan(" + operand() + ", vec4(0.0)))) discard;\n";
      return;
    }
    const Destination d = destination();
    std::vector<std::string> s;
    for (int i = 0; i < arity->second; ++i) {
      expect(",");
      s.push_back(operand());
    }
    std::string r;
    auto scalar = [](const std::string& e) { return "vec4((" + e + ").x)"; };
    const std::string a = s[0], b = s.size() > 1 ? s[1] : "", c = s.size() > 2 ? s[2] : "";
    if (op == "ABS") r = "abs(" + a + ")";
    else if (op == "ADD") r = a + " + " + b;
    else if (op == "SUB") r = a + " - " + b;
    else if (op == "MUL") r = a + " * " + b;
    else if (op == "MAD") r = a + " * " + b + " + " + c;
    else if (op == "MOV") r = a;
    else if (op == "MAX") r = "max(" + a + ", " + b + ")";
    else if (op == "MIN") r = "min(" + a + ", " + b + ")";
    else if (op == "FLR") r = "floor(" + a + ")";
    else if (op == "FRC") r = "fract(" + a + ")";
    else if (op == "SGE") r = "vec4(greaterThanEqual(" + a + ", " + b + "))";
    else if (op == "SLT") r = "vec4(lessThan(" + a + ", " + b + "))";
    else if (op == "DP3") r = "vec4(dot((" + a + ").xyz, (" + b + ").xyz))";
    else if (op == "DP4") r = "vec4(dot(" + a + ", " + b + "))";
    else if (op == "DPH") r = "vec4(dot((" + a + ").xyz, (" + b + ").xyz) + (" + b + ").w)";
    else if (op == "DST") r = "vec4(1.0, (" + a + ").y * (" + b + ").y, (" + a + ").z, (" + b + ").w)";
    else if (op == "XPD") r = "vec4(cross((" + a + ").xyz, (" + b + ").xyz), 1.0)";  // w is undefined
    else if (op == "EX2") r = scalar("exp2((" + a + ").x)");
    else if (op == "LG2") r = scalar("log2((" + a + ").x)");
    else if (op == "RCP") r = scalar("1.0 / (" + a + ").x");
    else if (op == "RSQ") r = scalar("inversesqrt(abs((" + a + ").x))");  // of |x| in both specifications
    else if (op == "POW") r = scalar("pow((" + a + ").x, (" + b + ").x)");
    else if (op == "COS") r = scalar("cos((" + a + ").x)");
    else if (op == "SIN") r = scalar("sin((" + a + ").x)");
    else if (op == "SCS") r = "vec4(cos((" + a + ").x), sin((" + a + ").x), 0.0, 0.0)";  // z and w undefined
    else if (op == "CMP") r = "mix(" + c + ", " + b + ", lessThan(" + a + ", vec4(0.0)))";
    else if (op == "LRP") r = a + " * " + b + " + (vec4(1.0) - " + a + ") * " + c;
    else if (op == "EXP") r = "parity_exp((" + a + ").x)", helpers_.insert("exp");
    else if (op == "LOG") r = "parity_log((" + a + ").x)", helpers_.insert("log");
    else if (op == "LIT") r = "parity_lit(" + a + ")", helpers_.insert("lit");
    else if (op == "ARL") r = a;
    else if (op == "SWZ") r = extendedSwizzle(a);
    else r = texture(op, a);
    if (d.address != (op == "ARL")) throw Untranslated{op + " writing " + (d.address ? "an address register" : "a vector register")};
    if (saturate) r = "clamp(" + r + ", 0.0, 1.0)";
    if (op == "ARL") {
      body_ += "  " + d.glsl + ".x = int(floor((" + r + ").x));\n";
      return;
    }
    body_ += "  { vec4 parity_value = " + r + "; " + d.glsl + "." + d.mask + " = parity_value." + d.mask + "; }\n";
  }

  // SWZ: each component 0, 1 or one of the source's, each optionally negated.
  std::string extendedSwizzle(const std::string& source) {
    std::string parts;
    for (int i = 0; i < 4; ++i) {
      expect(",");
      bool negate = accept("-");
      if (!negate) accept("+");
      std::string c;
      if (peek().kind == Token::Number) {
        const std::string n = next().text;
        if (n != "0" && n != "1") throw Untranslated{"SWZ component " + n};
        c = n + ".0";
      } else {
        const std::string name = identifier();
        if (name.size() != 1 || !isSwizzle(name, false)) throw Untranslated{"SWZ component " + name};
        c = "(" + source + ")." + xyzwOf(name);
      }
      parts += std::string(i ? ", " : "") + (negate ? "-" : "") + c;
    }
    return "vec4(" + parts + ")";
  }

  // TEX, TXB, TXP: coordinates, texture[unit], target. A shadow target's comparison is the
  // red channel of a LUMINANCE depth texture, OpenGL's initial depth texture mode.
  std::string texture(const std::string& op, const std::string& coords) {
    expect(",");
    if (identifier() != "texture") throw Untranslated{op + " without texture[N]"};
    int unit = 0;
    if (accept("[")) unit = integer(), expect("]");
    expect(",");
    const std::string target = identifier();
    static const std::map<std::string, std::string> kSamplers = {
        {"1D", "sampler1D"}, {"2D", "sampler2D"}, {"3D", "sampler3D"}, {"CUBE", "samplerCube"},
        {"SHADOW1D", "sampler1DShadow"}, {"SHADOW2D", "sampler2DShadow"}};
    auto type = kSamplers.find(target);
    if (type == kSamplers.end()) throw Untranslated{"texture target " + target};
    if (unit < 0 || unit >= 16) throw Untranslated{"texture unit " + std::to_string(unit)};
    auto [it, added] = textures_.emplace(unit, type->second);
    if (!added && it->second != type->second) throw Untranslated{"texture unit " + std::to_string(unit) + " read as two targets"};
    const std::string sampler = "parity_texture_" + std::to_string(unit);
    std::string t = "(" + coords + ")";
    if (op == "TXP" && target != "CUBE") t = "vec4((" + coords + ").xyz / (" + coords + ").w, (" + coords + ").w)";
    const std::string bias = op == "TXB" ? ", (" + coords + ").w" : "";
    if (target == "SHADOW1D" || target == "SHADOW2D") {
      const std::string at = target == "SHADOW1D" ? "vec3(" + t + ".x, 0.0, " + t + ".z)" : t + ".xyz";
      return "vec4(vec3(texture(" + sampler + ", " + at + bias + ")), 1.0)";
    }
    const std::string at = target == "1D" ? t + ".x" : target == "2D" ? t + ".xy" : t + ".xyz";
    return "texture(" + sampler + ", " + at + bias + ")";
  }

  // ---- the shader ----
  std::string assemble() const {
    std::string s = "#version 450\n";
    s += "layout(std140, set = " + std::to_string(stateSet_) + ", binding = " + std::to_string(stateBinding_) +
         ") uniform ParityArbState {\n  mat4 modelView;\n  mat4 projection;\n  vec4 color;\n  vec4 secondaryColor;\n"
         "  vec4 texCoord[8];\n  vec4 env[" + std::to_string(envCount_) + "];\n  vec4 local[" + std::to_string(localCount_) +
         "];\n} parity_state;\n";
    for (const auto& [unit, type] : textures_)
      s += "layout(binding = " + std::to_string(unit) + ") uniform " + type + " parity_texture_" + std::to_string(unit) + ";\n";
    // The varyings at fixed locations: primary and secondary colour, texture coordinates, fog.
    const char* io = vertex_ ? "out" : "in";
    s += std::string("layout(location = 0) ") + io + " vec4 parity_Color;\n";
    s += std::string("layout(location = 1) ") + io + " vec4 parity_SecondaryColor;\n";
    s += std::string("layout(location = 2) ") + io + " vec4 parity_TexCoord[8];\n";
    s += std::string("layout(location = 10) ") + io + " float parity_FogCoord;\n";
    if (vertex_) s += "layout(location = 0) in vec4 parity_Vertex;\n";
    else s += "layout(location = 0) out vec4 parity_FragColor;\n";
    if (helpers_.count("exp"))  // ARB_vertex_program's EXP: 2^floor(x), x - floor(x), 2^x, 1
      s += "vec4 parity_exp(float x) { return vec4(exp2(floor(x)), x - floor(x), exp2(x), 1.0); }\n";
    if (helpers_.count("log"))  // LOG of |x|: floor(log2), the mantissa, log2, 1
      s += "vec4 parity_log(float x) {\n  float a = abs(x), e = floor(log2(a));\n  return vec4(e, a / exp2(e), log2(a), 1.0);\n}\n";
    if (helpers_.count("lit"))  // LIT: the specification's clamps; 0^0 is 1
      s += "vec4 parity_lit(vec4 t) {\n  float x = max(t.x, 0.0), y = max(t.y, 0.0), w = clamp(t.w, -128.0, 128.0);\n"
           "  float specular = x > 0.0 ? (w == 0.0 ? 1.0 : exp2(w * log2(y))) : 0.0;\n"
           "  return vec4(1.0, x, specular, 1.0);\n}\n";
    s += "void main() {\n";
    s += "  vec4 parity_out_color = vec4(0.0, 0.0, 0.0, 1.0), parity_out_unused = vec4(0.0);\n";
    if (vertex_) {
      s += "  vec4 parity_out_position = vec4(0.0, 0.0, 0.0, 1.0), parity_out_secondary = vec4(0.0, 0.0, 0.0, 1.0), parity_out_fog = vec4(0.0);\n";
      s += "  vec4 parity_out_texcoord[8] = vec4[8](vec4(0.0, 0.0, 0.0, 1.0), vec4(0.0, 0.0, 0.0, 1.0), vec4(0.0, 0.0, 0.0, 1.0), vec4(0.0, 0.0, 0.0, 1.0),"
           " vec4(0.0, 0.0, 0.0, 1.0), vec4(0.0, 0.0, 0.0, 1.0), vec4(0.0, 0.0, 0.0, 1.0), vec4(0.0, 0.0, 0.0, 1.0));\n";
    } else {
      s += "  vec4 parity_out_depth = vec4(gl_FragCoord.z);\n";
    }
    s += body_;
    if (vertex_) {
      if (positionInvariant_) s += "  parity_out_position = parity_state.projection * (parity_state.modelView * parity_Vertex);\n";
      s += "  gl_Position = parity_out_position;\n";
      s += "  gl_Position.z = (gl_Position.z + gl_Position.w) * 0.5;  // OpenGL's clip-space depth\n";
      s += "  parity_Color = clamp(parity_out_color, 0.0, 1.0);\n";
      s += "  parity_SecondaryColor = clamp(parity_out_secondary, 0.0, 1.0);\n";
      s += "  parity_TexCoord = parity_out_texcoord;\n";
      s += "  parity_FogCoord = parity_out_fog.x;\n";
    } else {
      s += "  parity_FragColor = parity_out_color;\n";
      if (writesDepth_) s += "  gl_FragDepth = parity_out_depth.z;\n";
    }
    s += "}\n";
    return s;
  }

  uint32_t stateSet_, stateBinding_;
  bool vertex_ = false, positionInvariant_ = false, writesDepth_ = false;
  std::vector<Token> tokens_;
  size_t at_ = 0;
  std::map<std::string, Variable> variables_;
  int names_ = 0;
  std::string body_;
  std::set<std::string> helpers_;
  uint32_t envCount_ = 1, localCount_ = 1;
  std::map<uint32_t, std::string> textures_;
};

}  // namespace

ArbProgramGlsl translateArbProgram(const std::string& text, uint32_t stateSet, uint32_t stateBinding) {
  try {
    return Translator(text, stateSet, stateBinding).run();
  } catch (const Untranslated& u) {
    ArbProgramGlsl out;
    out.vertex = text.find("!!ARBvp") != std::string::npos;
    out.unsupported = u.what;
    return out;
  }
}

}  // namespace parity::harness::script
