#include "harness/script_parser.h"

#include <OpenImageIO/imagebuf.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "harness/image_io.h"
#include "harness/shader_test_parser.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"

namespace parity::harness::script {

namespace fs = std::filesystem;

uint32_t scalarSize(Scalar s) {
  switch (s) {
    case Scalar::Int8: case Scalar::Uint8: return 1;
    case Scalar::Int16: case Scalar::Uint16: case Scalar::Float16: return 2;
    case Scalar::Int32: case Scalar::Uint32: case Scalar::Float32: return 4;
    default: return 8;
  }
}

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

Mode modeOf(Scalar s) {
  switch (s) {
    case Scalar::Int8: case Scalar::Int16: case Scalar::Int32: case Scalar::Int64: return Mode::Int;
    case Scalar::Uint8: case Scalar::Uint16: case Scalar::Uint32: case Scalar::Uint64: return Mode::Uint;
    default: return Mode::Float;
  }
}

bool scalarFromName(const std::string& n, Scalar* s) {
  static const std::map<std::string, Scalar> kNames = {
      {"int8", Scalar::Int8},       {"int16", Scalar::Int16},     {"int32", Scalar::Int32},
      {"int64", Scalar::Int64},     {"uint8", Scalar::Uint8},     {"uint16", Scalar::Uint16},
      {"uint32", Scalar::Uint32},   {"uint64", Scalar::Uint64},   {"float16", Scalar::Float16},
      {"float", Scalar::Float32},   {"double", Scalar::Float64}};
  auto it = kNames.find(n);
  if (it == kNames.end()) return false;
  *s = it->second;
  return true;
}

}  // namespace

bool parseDataType(const std::string& text, bool std140, ElementType* out, std::string* error) {
  ElementType t;
  t.name = text;
  t.std140 = std140;
  // "float[]": Amber's array spelling; every buffer is an array of its element type already.
  std::string plain = text.size() > 2 && text.compare(text.size() - 2, 2, "[]") == 0 ? text.substr(0, text.size() - 2) : text;
  std::string base = plain, inner;
  size_t lt = plain.find('<');
  if (lt != std::string::npos) {
    if (plain.back() != '>') {
      *error = "invalid DATA_TYPE '" + text + "'";
      return false;
    }
    base = plain.substr(0, lt);
    inner = plain.substr(lt + 1, plain.size() - lt - 2);
  }
  if (inner.empty()) {
    if (!scalarFromName(base, &t.scalar)) {
      *error = "unknown DATA_TYPE '" + text + "' (int8..int64, uint8..uint64, float16, float, double, vecN<T>, matCxR<T>)";
      return false;
    }
  } else {
    if (!scalarFromName(inner, &t.scalar)) {
      *error = "unknown component type '" + inner + "' in DATA_TYPE '" + text + "'";
      return false;
    }
    if (base.size() == 4 && base.compare(0, 3, "vec") == 0 && base[3] >= '2' && base[3] <= '4') {
      t.rows = static_cast<uint32_t>(base[3] - '0');
    } else if (base.size() == 6 && base.compare(0, 3, "mat") == 0 && base[4] == 'x' && base[3] >= '2' &&
               base[3] <= '4' && base[5] >= '2' && base[5] <= '4') {
      t.columns = static_cast<uint32_t>(base[3] - '0');
      t.rows = static_cast<uint32_t>(base[5] - '0');
    } else {
      *error = "unknown DATA_TYPE '" + text + "'";
      return false;
    }
  }
  // std430 / std140 layout of one array element.
  uint32_t s = scalarSize(t.scalar);
  uint32_t vecAlign = (t.rows == 1 ? 1 : t.rows == 2 ? 2 : 4) * s;
  bool isMatrix = t.columns > 1;
  uint32_t columnStride = t.rows == 1 ? s : vecAlign;
  if (std140 && isMatrix) columnStride = std::max(columnStride, 16u);
  for (uint32_t c = 0; c < t.columns; ++c)
    for (uint32_t r = 0; r < t.rows; ++r) t.layout.fields.push_back({c * columnStride + r * s, t.scalar, modeOf(t.scalar), 0});
  uint32_t size = isMatrix ? t.columns * columnStride : t.rows * s;
  uint32_t align = isMatrix ? columnStride : (t.rows == 1 ? s : vecAlign);
  if (std140) align = std::max(align, 16u);
  t.layout.stride = (size + align - 1) / align * align;
  *out = t;
  return true;
}

bool parseFormat(const std::string& text, ElementType* out, std::string* error) {
  ElementType t;
  t.isFormat = true;
  t.name = text;
  // Split "R8G8B8A8_UNORM" into channel/bit pairs and a numeric mode; depth/stencil formats
  // ("D32_SFLOAT_S8_UINT", "D24_UNORM_S8_UINT", "X8_D24_UNORM_PACK32") are special-cased.
  struct Comp {
    char ch;
    uint32_t bits;
  };
  auto fail = [&](const std::string& why) {
    *error = "unsupported FORMAT '" + text + "'" + (why.empty() ? "" : " (" + why + ")");
    return false;
  };
  auto fieldFor = [](uint32_t bits, Mode mode, Scalar* s) {
    bool isFloat = mode == Mode::Float;
    bool isSigned = mode == Mode::Int || mode == Mode::Snorm;
    switch (bits) {
      case 8: *s = isSigned ? Scalar::Int8 : Scalar::Uint8; return !isFloat;
      case 16: *s = isFloat ? Scalar::Float16 : isSigned ? Scalar::Int16 : Scalar::Uint16; return true;
      case 32: *s = isFloat ? Scalar::Float32 : isSigned ? Scalar::Int32 : Scalar::Uint32; return true;
      case 64: *s = isFloat ? Scalar::Float64 : isSigned ? Scalar::Int64 : Scalar::Uint64; return true;
      default: return false;
    }
  };
  if (text == "D32_SFLOAT_S8_UINT" || text == "D24_UNORM_S8_UINT" || text == "X8_D24_UNORM_PACK32" ||
      text == "D32_SFLOAT" || text == "D16_UNORM") {
    // Stored as the RHI stores depth read back: one float per texel (the stencil is separate).
    t.layout.fields.push_back({0, Scalar::Float32, Mode::Float, 'D'});
    t.layout.stride = 4;
    *out = t;
    return true;
  }
  // Packed formats (B10G11R11_UFLOAT_PACK32, ...): one unsigned word per texel, as the texture
  // stores it; the bit fields are the format's business.
  for (uint32_t bits : {8u, 16u, 32u}) {
    const std::string suffix = "_PACK" + std::to_string(bits);
    if (text.size() > suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0) {
      Scalar word = bits == 8 ? Scalar::Uint8 : bits == 16 ? Scalar::Uint16 : Scalar::Uint32;
      t.layout.fields.push_back({0, word, Mode::Uint, 0});
      t.layout.stride = bits / 8;
      t.scalar = word;
      *out = t;
      return true;
    }
  }
  size_t us = text.find('_');
  if (us == std::string::npos) return fail("");
  std::string comps = text.substr(0, us), modeText = text.substr(us + 1);
  Mode mode;
  if (modeText == "UNORM") mode = Mode::Unorm;
  else if (modeText == "SNORM") mode = Mode::Snorm;
  else if (modeText == "UINT") mode = Mode::Uint;
  else if (modeText == "SINT") mode = Mode::Int;
  else if (modeText == "SFLOAT") mode = Mode::Float;
  else if (modeText == "SRGB") mode = Mode::Srgb;
  else return fail("numeric format '" + modeText + "'");
  std::vector<Comp> cs;
  for (size_t i = 0; i < comps.size();) {
    char ch = comps[i++];
    if (!std::strchr("RGBA", ch)) return fail("");
    size_t j = i;
    while (j < comps.size() && std::isdigit(static_cast<unsigned char>(comps[j]))) ++j;
    // At most 3 digits (component sizes are 8..64): a longer number is no format, and
    // std::stoul would throw out_of_range on it (found by fuzz_script, tests/fuzz_regressions/).
    if (j == i || j - i > 3) return fail("");
    cs.push_back({ch, static_cast<uint32_t>(std::stoul(comps.substr(i, j - i)))});
    i = j;
  }
  if (cs.empty()) return fail("");  // "_UNORM": no component (fuzz_script, tests/fuzz_regressions/)
  uint32_t offset = 0;
  for (const Comp& c : cs) {
    Scalar s;
    if (!fieldFor(c.bits, mode == Mode::Srgb ? Mode::Unorm : mode, &s)) return fail("component size " + std::to_string(c.bits));
    t.layout.fields.push_back({offset, s, mode, c.ch});
    offset += c.bits / 8;
  }
  t.layout.stride = offset;
  t.scalar = t.layout.fields.front().scalar;
  t.rows = static_cast<uint32_t>(cs.size());
  *out = t;
  return true;
}

const Shader* Script::findShader(const std::string& n) const {
  for (const auto& s : shaders) if (s.name == n) return &s;
  return nullptr;
}
const Buffer* Script::findBuffer(const std::string& n) const {
  for (const auto& s : buffers) if (s.name == n) return &s;
  return nullptr;
}
const Sampler* Script::findSampler(const std::string& n) const {
  for (const auto& s : samplers) if (s.name == n) return &s;
  return nullptr;
}
const Pipeline* Script::findPipeline(const std::string& n) const {
  for (const auto& s : pipelines) if (s.name == n) return &s;
  return nullptr;
}

// PNG as tightly packed RGBA8 texels, row 0 (the top row) first.
bool loadPng(const std::string& path, std::vector<uint8_t>* bytes, uint32_t* width, uint32_t* height, std::string* error) {
  OIIO::ImageBuf image;
  if (!readImage(path, &image, error)) return false;
  const OIIO::ImageSpec& spec = image.spec();
  *width = static_cast<uint32_t>(spec.width);
  *height = static_cast<uint32_t>(spec.height);
  bytes->assign(size_t(*width) * *height * 4, 255);
  OIIO::ROI roi(0, spec.width, 0, spec.height, 0, 1, 0, std::min(spec.nchannels, 4));
  std::vector<uint8_t> tmp(size_t(*width) * *height * roi.nchannels());
  if (!image.get_pixels(roi, OIIO::TypeDesc::UINT8, tmp.data())) {
    *error = path + ": cannot read pixels";
    return false;
  }
  for (size_t i = 0; i < size_t(*width) * *height; ++i)
    for (int c = 0; c < roi.nchannels(); ++c) (*bytes)[i * 4 + c] = tmp[i * roi.nchannels() + c];
  return true;
}

namespace {

// A float outside int64's range (or NaN) has no integer value: converting it is undefined
// behaviour, found by fuzz_script with "-1.11111e43" (tests/fuzz_regressions/script/). Such a
// value saturates (NaN: 0), like the literal's integer types wrap below.
int64_t saturatingInt64(double d) {
  constexpr double kLimit = 9223372036854775808.0;  // 2^63, the first double out of range
  if (std::isnan(d)) return 0;
  if (d >= kLimit) return INT64_MAX;
  if (d < -kLimit) return INT64_MIN;
  return static_cast<int64_t>(d);
}

uint16_t floatToHalf(float f) {
  uint32_t x;
  std::memcpy(&x, &f, 4);
  uint32_t sign = (x >> 16) & 0x8000, exp = (x >> 23) & 0xFF, man = x & 0x7FFFFF;
  if (exp == 0xFF) return static_cast<uint16_t>(sign | 0x7C00 | (man ? 0x200 : 0));
  int e = static_cast<int>(exp) - 127 + 15;
  if (e >= 31) return static_cast<uint16_t>(sign | 0x7C00);
  if (e <= 0) {
    if (e < -10) return static_cast<uint16_t>(sign);
    man |= 0x800000;
    uint32_t shift = static_cast<uint32_t>(14 - e);
    uint32_t h = man >> shift, rem = man & ((1u << shift) - 1), half = 1u << (shift - 1);
    if (rem > half || (rem == half && (h & 1))) ++h;
    return static_cast<uint16_t>(sign | h);
  }
  uint32_t h = (static_cast<uint32_t>(e) << 10) | (man >> 13), rem = man & 0x1FFF;
  if (rem > 0x1000 || (rem == 0x1000 && (h & 1))) ++h;
  return static_cast<uint16_t>(sign | h);
}
}  // namespace

void storeValue(std::vector<uint8_t>& bytes, size_t offset, Scalar s, const Value& v) {
  if (bytes.size() < offset + scalarSize(s)) bytes.resize(offset + scalarSize(s), 0);
  uint8_t* p = bytes.data() + offset;
  auto put = [&](auto x) { std::memcpy(p, &x, sizeof(x)); };
  const int64_t i = v.isInteger ? v.i : saturatingInt64(v.d);
  switch (s) {
    case Scalar::Int8: put(static_cast<int8_t>(i)); break;
    case Scalar::Int16: put(static_cast<int16_t>(i)); break;
    case Scalar::Int32: put(static_cast<int32_t>(i)); break;
    case Scalar::Int64: put(static_cast<int64_t>(i)); break;
    case Scalar::Uint8: put(static_cast<uint8_t>(i)); break;
    case Scalar::Uint16: put(static_cast<uint16_t>(i)); break;
    case Scalar::Uint32: put(static_cast<uint32_t>(i)); break;
    case Scalar::Uint64:  // a float in [2^63, 2^64) still fits
      put(!v.isInteger && v.d >= 9223372036854775808.0 && v.d < 18446744073709551616.0 ? static_cast<uint64_t>(v.d)
                                                                                        : static_cast<uint64_t>(i));
      break;
    case Scalar::Float16: put(floatToHalf(static_cast<float>(v.d))); break;
    case Scalar::Float32: put(static_cast<float>(v.d)); break;
    case Scalar::Float64: put(v.d); break;
  }
}

namespace {

struct Token {
  std::string text;
  int line = 0, col = 0;
  int logical = 0;  // line the token belongs to after joining continued lines
  bool valid() const { return line > 0; }
};

struct ParseError {
  Location loc;
  std::string message;
};

class Parser {
 public:
  Parser(const std::string& text, const std::string& name) : name_(name) {
    std::string line;
    std::istringstream in(text);
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines_.push_back(line);
    }
    // Amber's line continuation: a '\\' ending a line joins the next line to it. logical_[i] is
    // the 1-based line a physical line belongs to.
    logical_.resize(lines_.size());
    for (size_t i = 0; i < lines_.size(); ++i)
      logical_[i] = i > 0 && continues(lines_[i - 1]) ? logical_[i - 1] : static_cast<int>(i + 1);
    script_.file = name;
  }

  Script run() {
    while (true) {
      Token t = next();
      if (!t.valid()) break;
      statement(t);
    }
    return std::move(script_);
  }

 private:
  std::string name_;
  struct StructMember {
    std::string type, name;
    std::optional<uint32_t> offset;
  };
  std::map<std::string, std::vector<StructMember>> structs_;
  std::map<std::string, uint32_t> structStrides_;        // STRUCT name STRIDE n
  std::map<std::string, std::string> virtualFiles_;      // VIRTUAL_FILE path -> contents
  std::vector<std::string> lines_;
  std::vector<int> logical_;
  size_t li_ = 0, ci_ = 0;  // next unread character
  int lastLine_ = 0;        // logical line of the last token read
  int lastPhysical_ = 0;    // physical line of the last token read

  static bool continues(const std::string& l) {
    size_t hash = l.find('#');
    std::string code = l.substr(0, hash);
    size_t e = code.find_last_not_of(" \t");
    return e != std::string::npos && code[e] == '\\' && (e == 0 || std::isspace(static_cast<unsigned char>(code[e - 1])));
  }
  Script script_;

  [[noreturn]] void error(const Token& t, const std::string& msg) { throw ParseError{{t.line, t.col}, msg}; }
  [[noreturn]] void errorAfter(const std::string& msg) {
    // Column just past the last token of the current line.
    int line = lastPhysical_ ? lastPhysical_ : 1;
    int col = static_cast<int>(lines_.empty() ? 1 : lines_[line - 1].size() + 1);
    throw ParseError{{line, col}, msg};
  }

  // Next token, crossing lines; '#' starts a comment to the end of the line.
  Token next() {
    while (li_ < lines_.size()) {
      const std::string& l = lines_[li_];
      while (ci_ < l.size() && std::isspace(static_cast<unsigned char>(l[ci_]))) ++ci_;
      if (ci_ >= l.size() || l[ci_] == '#') {
        ++li_;
        ci_ = 0;
        continue;
      }
      size_t b = ci_;
      while (ci_ < l.size() && !std::isspace(static_cast<unsigned char>(l[ci_]))) ++ci_;
      if (l.compare(b, ci_ - b, "\\") == 0 && continues(l)) continue;  // line continuation
      Token t{l.substr(b, ci_ - b), static_cast<int>(li_ + 1), static_cast<int>(b + 1)};
      t.logical = logical_[li_];
      lastLine_ = t.logical;
      lastPhysical_ = t.line;
      return t;
    }
    return {};
  }
  // The next token if it is on the line of the last token read; the stream does not advance.
  Token peekSameLine() {
    size_t li = li_, ci = ci_;
    int last = lastLine_, lastP = lastPhysical_;
    Token t = next();
    li_ = li, ci_ = ci, lastLine_ = last, lastPhysical_ = lastP;
    if (t.valid() && t.logical == last) return t;
    return {};
  }
  Token nextSameLine(const std::string& what) {
    int last = lastLine_, lastP = lastPhysical_;
    size_t li = li_, ci = ci_;
    Token t = next();
    if (!t.valid() || t.logical != last) {
      li_ = li, ci_ = ci, lastLine_ = last, lastPhysical_ = lastP;
      errorAfter("expected " + what);
    }
    return t;
  }
  void expectEndOfLine() {
    Token t = peekSameLine();
    if (t.valid()) error(t, "unexpected '" + t.text + "'");
  }
  // Skips to the line after the current one.
  void skipLine() {
    if (li_ < lines_.size() && logical_[li_] == lastLine_) {
      ++li_;
      ci_ = 0;
      while (li_ < lines_.size() && logical_[li_] == lastLine_) ++li_;
    }
  }
  // Skips lines until one whose only token is END (for blocks we do not execute).
  void skipBlock(const Token& start) {
    skipLine();
    while (li_ < lines_.size()) {
      std::string l = lines_[li_];
      size_t b = l.find_first_not_of(" \t");
      ++li_;
      ci_ = 0;
      if (b != std::string::npos && l.compare(b, 3, "END") == 0 && l.find_first_not_of(" \t", b + 3) == std::string::npos) {
        lastLine_ = logical_[li_ - 1];
        lastPhysical_ = static_cast<int>(li_);
        return;
      }
    }
    error(start, "missing END for '" + start.text + "'");
  }

  static bool isNumber(const std::string& s) {
    if (s.empty()) return false;
    char* end = nullptr;
    std::strtod(s.c_str(), &end);
    return end && *end == 0;
  }
  uint32_t uintToken(const Token& t) {
    char* end = nullptr;
    errno = 0;
    unsigned long long v = std::strtoull(t.text.c_str(), &end, 0);
    if (t.text.empty() || *end || t.text[0] == '-' || errno || v > 0xFFFFFFFFull)
      error(t, "expected a non-negative integer, got '" + t.text + "'");
    return static_cast<uint32_t>(v);
  }
  uint32_t uintSameLine(const std::string& what) { return uintToken(nextSameLine(what)); }
  uint32_t dimensionSameLine(const Token& keyword, const std::string& what) {
    Token t = nextSameLine(what);
    uint32_t v = uintToken(t);
    if (v > kMaxImageDimension)
      error(t, keyword.text + " " + t.text + " is larger than the " + std::to_string(kMaxImageDimension) +
                   " a script may use");
    return v;
  }
  double numberToken(const Token& t) {
    if (!isNumber(t.text)) error(t, "expected a number, got '" + t.text + "'");
    return std::strtod(t.text.c_str(), nullptr);
  }
  double numberSameLine(const std::string& what) { return numberToken(nextSameLine(what)); }
  Value valueToken(const Token& t) {
    Value v;
    const std::string& s = t.text;
    bool looksInt = !s.empty() && s.find_first_of(".eE") == std::string::npos;
    if (s.size() > 2 && (s[0] == '0' && (s[1] == 'x' || s[1] == 'X'))) looksInt = true;
    if (looksInt) {
      char* end = nullptr;
      errno = 0;
      long long x = s[0] == '-' ? std::strtoll(s.c_str(), &end, 0) : static_cast<long long>(std::strtoull(s.c_str(), &end, 0));
      if (*end == 0 && errno == 0) {
        v.isInteger = true;
        v.i = x;
        v.d = s[0] == '-' ? static_cast<double>(x) : static_cast<double>(static_cast<unsigned long long>(x));
        return v;
      }
    }
    v.d = numberToken(t);
    v.i = saturatingInt64(v.d);
    return v;
  }
  void expectWord(const std::string& word) {
    Token t = nextSameLine(word);
    if (t.text != word) error(t, "expected " + word + ", got '" + t.text + "'");
  }
  void unsupported(const Token& t, const std::string& feature) { script_.unsupported.push_back({feature, {t.line, t.col}}); }

  // --- values into bytes ---
  static void storeValue(std::vector<uint8_t>& bytes, size_t offset, Scalar s, const Value& v) {
    script::storeValue(bytes, offset, s, v);
  }
  static void storeElement(std::vector<uint8_t>& bytes, const Layout& layout, size_t index, size_t field, const Value& v) {
    const Field& f = layout.fields[field];
    storeValue(bytes, index * layout.stride + f.offset, f.scalar, v);
  }

  // --- statements ---
  void statement(const Token& t) {
    const std::string& k = t.text;
    if (k == "#!amber") return skipLine();
    if (k == "SHADER") return shader(t);
    if (k == "BUFFER" || k == "IMAGE") return buffer(t, k == "IMAGE");
    if (k == "SAMPLER") return sampler(t);
    if (k == "PIPELINE") return pipeline(t);
    if (k == "DERIVE_PIPELINE") return derivePipeline(t);
    if (k == "CLEAR_COLOR" || k == "CLEAR_DEPTH" || k == "CLEAR_STENCIL" || k == "CLEAR") return clear(t);
    if (k == "RUN") return run(t);
    if (k == "EXPECT") return expect(t);
    if (k == "REQUIRE") return require(t);
    if (k == "DEVICE_FEATURE") return deviceFeature(t);
    if (k == "DEVICE_EXTENSION" || k == "INSTANCE_EXTENSION") {
      Token n = nextSameLine("extension name");
      // Checked against the device when the script runs (runScript); instance extensions other
      // than the one Vulkan 1.1 made core are not queried.
      if (k == "DEVICE_EXTENSION") script_.requirements.push_back({"device_extension", n.text, {t.line, t.col}});
      else if (n.text != "VK_KHR_get_physical_device_properties2") unsupported(t, k + " " + n.text);
      return expectEndOfLine();
    }
    if (k == "DEVICE_PROPERTY") {
      Token n = nextSameLine("property name");
      unsupported(t, "DEVICE_PROPERTY " + n.text + " (device properties are not queried)");
      return expectEndOfLine();
    }
    if (k == "SET") return set(t);
    if (k == "RESOLVE") return resolve(t);
    if (k == "REPEAT") {  // the body's commands, unrolled
      uint32_t n = uintSameLine("repeat count");
      expectEndOfLine();
      size_t first = script_.commands.size();
      while (true) {
        Token w = next();
        if (!w.valid()) error(t, "missing END for REPEAT");
        if (w.text == "END") break;
        if (w.text != "RUN" && w.text != "CLEAR" && w.text != "CLEAR_COLOR" && w.text != "CLEAR_DEPTH" &&
            w.text != "CLEAR_STENCIL" && w.text != "EXPECT" && w.text != "COPY")
          error(w, "'" + w.text + "' cannot be repeated (commands only)");
        statement(w);
      }
      std::vector<Command> body(script_.commands.begin() + static_cast<long>(first), script_.commands.end());
      if (n == 0) script_.commands.resize(first);
      for (uint32_t i = 1; i < n; ++i) script_.commands.insert(script_.commands.end(), body.begin(), body.end());
      return;
    }
    if (k == "STRUCT") return structDecl(t);
    if (k == "VIRTUAL_FILE") return virtualFile(t);
    if (k == "COPY") {
      Command c;
      c.kind = Command::Kind::Copy;
      c.loc = {t.line, t.col};
      Token a = nextSameLine("source buffer");
      if (!script_.findBuffer(a.text)) error(a, "unknown buffer '" + a.text + "'");
      expectWord("TO");
      Token d = nextSameLine("destination buffer");
      if (!script_.findBuffer(d.text)) error(d, "unknown buffer '" + d.text + "'");
      c.buffer = a.text;
      c.other = d.text;
      expectEndOfLine();
      script_.commands.push_back(c);
      return;
    }
    if (k == "DEBUG") {
      unsupported(t, k);
      return skipBlock(t);
    }
    error(t, "unknown command '" + k + "'");
  }

  // VIRTUAL_FILE path NEWLINE lines END: a file that SHADER ... VIRTUAL_FILE path (or FILE path)
  // reads instead of the disk.
  void virtualFile(const Token& t) {
    Token path = nextSameLine("virtual file path");
    expectEndOfLine();
    if (virtualFiles_.count(path.text)) error(path, "duplicate VIRTUAL_FILE '" + path.text + "'");
    std::string content;
    if (!blockLines(&content)) error(t, "missing END for VIRTUAL_FILE '" + path.text + "'");
    virtualFiles_[path.text] = content;
  }

  // The lines after the current one up to a line holding only END, verbatim; false without END.
  bool blockLines(std::string* out) {
    skipLine();
    bool found = false;
    while (li_ < lines_.size()) {
      const std::string& l = lines_[li_++];
      size_t b = l.find_first_not_of(" \t");
      if (b != std::string::npos && l.compare(b, 3, "END") == 0 && l.find_first_not_of(" \t", b + 3) == std::string::npos) {
        found = true;
        break;
      }
      *out += l + "\n";
    }
    ci_ = 0;
    if (li_ > 0) lastLine_ = logical_[li_ - 1], lastPhysical_ = static_cast<int>(li_);
    return found;
  }

  // STRUCT name [STRIDE n] NEWLINE (type member [OFFSET n])* END
  void structDecl(const Token& t) {
    Token name = nextSameLine("struct name");
    if (structs_.count(name.text)) error(name, "duplicate STRUCT '" + name.text + "'");
    if (peekSameLine().valid()) {
      expectWord("STRIDE");
      structStrides_[name.text] = uintSameLine("stride");
    }
    expectEndOfLine();
    std::vector<StructMember> members;
    while (true) {
      Token type = next();
      if (!type.valid()) error(t, "missing END for STRUCT '" + name.text + "'");
      if (type.text == "END") break;
      StructMember m;
      m.type = type.text;
      ElementType probe;
      std::string why;
      if (!structs_.count(m.type) && !parseDataType(m.type, false, &probe, &why)) error(type, why);
      m.name = nextSameLine("member name").text;
      while (peekSameLine().valid()) {
        Token o = next();
        if (o.text == "OFFSET") m.offset = uintSameLine("offset");
        else error(o, "unexpected '" + o.text + "' in STRUCT member (OFFSET)");
      }
      members.push_back(m);
    }
    structs_[name.text] = members;
  }

  // std430/std140 layout of a struct: flattened fields, size, alignment.
  void structLayout(const std::string& name, bool std140, Layout* out, uint32_t* size, uint32_t* align) {
    uint32_t offset = 0, maxAlign = 1;
    for (const StructMember& m : structs_.at(name)) {
      Layout sub;
      uint32_t msize = 0, malign = 1;
      if (structs_.count(m.type)) {
        structLayout(m.type, std140, &sub, &msize, &malign);
      } else {
        ElementType et;
        std::string why;
        parseDataType(m.type, std140, &et, &why);
        uint32_t sc = scalarSize(et.scalar);
        uint32_t vecAlign = (et.rows == 1 ? 1 : et.rows == 2 ? 2 : 4) * sc;
        if (et.columns > 1) {
          malign = std140 ? std::max(vecAlign, 16u) : vecAlign;
          msize = et.columns * malign;
        } else {
          malign = vecAlign;
          msize = et.rows * sc;
        }
        ElementType plain;
        parseDataType(m.type, false, &plain, &why);
        sub = et.columns > 1 ? et.layout : plain.layout;
      }
      offset = m.offset ? *m.offset : (offset + malign - 1) / malign * malign;
      for (Field f : sub.fields) {
        f.offset += offset;
        out->fields.push_back(f);
      }
      offset += msize;
      maxAlign = std::max(maxAlign, malign);
    }
    if (std140) maxAlign = std::max(maxAlign, 16u);
    *align = maxAlign;
    *size = (offset + maxAlign - 1) / maxAlign * maxAlign;
    auto stride = structStrides_.find(name);
    if (stride != structStrides_.end()) *size = std::max(*size, stride->second);
    out->stride = *size;
  }

  void require(const Token& t) {
    Token what = nextSameLine("backend, platform or capability");
    if (what.text != "backend" && what.text != "platform" && what.text != "capability")
      error(what, "REQUIRE takes backend, platform or capability, got '" + what.text + "'");
    Token v = nextSameLine(what.text + " name");
    if (what.text == "backend" && v.text != "gl" && v.text != "vk") error(v, "unknown backend '" + v.text + "' (gl or vk)");
    if (what.text == "platform" && !platforms::platformFromName(v.text))
      error(v, "unknown platform '" + v.text + "' (reference, dx10, ps3, x360)");
    script_.requirements.push_back({what.text, v.text, {t.line, t.col}});
    expectEndOfLine();
  }

  void set(const Token& t) {
    Token what = nextSameLine("PLATFORM_PARAM or ENGINE_DATA");
    if (what.text == "PLATFORM_PARAM") {
      Token n = nextSameLine("parameter name");
      Token v = nextSameLine("parameter value");
      // Short names for the parameters scripts set most; the catalogue names work as well.
      static const std::map<std::string, std::string> kAliases = {
          {"HALFPIXELOFFSET", "x360.halfpixeloffset"},     {"RESOLVE_PATH", "x360.dsf_resolve_path"},
          {"SIGNED_K16_RESOLVE", "x360.signed_k16_resolve"}, {"K16_UNPACK_CLAMP", "x360.k16_unpack_clamp"},
          {"TEXDEPTH2D_PRECISE", "ps3.texdepth2d_precise"}};
      std::string name = kAliases.count(n.text) ? kAliases.at(n.text) : n.text;
      std::string value = v.text;
      if (name == "x360.halfpixeloffset") value = value == "1" || lower(value) == "true" ? "true" : value == "0" || lower(value) == "false" ? "false" : value;
      if (!platforms::findParameter(name)) error(n, "unknown platform parameter '" + n.text + "' (`parity explain` lists them)");
      platforms::PlatformParams scratch;
      std::string why;
      if (!platforms::setParameter(scratch, name, value, &why)) error(v, why);
      script_.platformParams[name] = value;
      return expectEndOfLine();
    }
    if (what.text == "ENGINE_DATA") return skipLine();  // fence timeouts: nothing to do here
    error(what, "SET takes PLATFORM_PARAM or ENGINE_DATA, got '" + what.text + "'");
  }

  // Checked against the device's features when the script runs (runScript).
  void deviceFeature(const Token& t) {
    Token n = nextSameLine("feature name");
    script_.requirements.push_back({"device_feature", n.text, {t.line, t.col}});
    expectEndOfLine();
  }

  void shader(const Token& t) {
    Shader s;
    s.loc = {t.line, t.col};
    Token stage = nextSameLine("shader stage (vertex, fragment or compute)");
    std::string st = stage.text;
    Token name = nextSameLine("shader name");
    s.name = name.text;
    if (script_.findShader(s.name)) error(name, "duplicate shader name '" + s.name + "'");
    Token fmt = nextSameLine("shader format (GLSL or PASSTHROUGH)");
    if (st == "vertex") s.stage = Stage::Vertex;
    else if (st == "fragment") s.stage = Stage::Fragment;
    else if (st == "compute") s.stage = Stage::Compute;
    else if (st == "geometry") s.stage = Stage::Geometry;
    else if (st == "tessellation_control") s.stage = Stage::TessControl;
    else if (st == "tessellation_evaluation") s.stage = Stage::TessEvaluation;
    else if (st == "multi") {
      unsupported(stage, "SHADER stage " + st);
      s.stage = Stage::Vertex;
    } else {
      error(stage, "unknown shader stage '" + st + "' (vertex, fragment, compute)");
    }
    if (fmt.text == "PASSTHROUGH") {
      if (s.stage != Stage::Vertex) error(fmt, "PASSTHROUGH is only valid for vertex shaders");
      s.passthrough = true;
      expectEndOfLine();
      script_.shaders.push_back(s);
      return;
    }
    s.format = fmt.text;
    // GLSL is compiled, SPIR-V assembly assembled and SPIR-V binaries run as they are.
    bool glsl = fmt.text == "GLSL" || fmt.text == "SPIRV-BIN" || fmt.text == "SPIRV-ASM";
    if (!glsl) {
      if (fmt.text != "SPIRV-HEX" && fmt.text != "HLSL" && fmt.text != "OPENCL-C")
        error(fmt, "unknown shader format '" + fmt.text + "' (GLSL, SPIRV-ASM, SPIRV-BIN, PASSTHROUGH)");
      unsupported(fmt, "SHADER format " + fmt.text);
    }
    Token opt = peekSameLine();
    if (opt.valid() && opt.text == "TARGET_ENV") {
      next();
      Token env = nextSameLine("target environment");
      // spv1.0 .. spv1.6; Vulkan environments (vulkan1.1spv1.4, ...) name the SPIR-V they mean.
      size_t spv = env.text.find("spv1.");
      if (spv != std::string::npos && spv + 5 < env.text.size() && std::isdigit(static_cast<unsigned char>(env.text[spv + 5])))
        s.spirvMinor = env.text[spv + 5] - '0';
      else if (env.text == "vulkan1.1") s.spirvMinor = 3;
      else if (env.text == "vulkan1.2") s.spirvMinor = 5;
      else if (env.text == "vulkan1.3") s.spirvMinor = 6;
      opt = peekSameLine();
    }
    if (opt.valid() && (opt.text == "FILE" || opt.text == "VIRTUAL_FILE")) {
      next();
      Token file = nextSameLine("file name");
      expectEndOfLine();
      auto virtualFile = virtualFiles_.find(file.text);
      if (virtualFile != virtualFiles_.end()) {
        s.source = virtualFile->second;
        s.sourceLine = 1;
      } else if (opt.text == "VIRTUAL_FILE") {
        error(file, "no VIRTUAL_FILE '" + file.text + "' declared before");
      } else if (glsl) {
        fs::path p = fs::path(name_).parent_path() / file.text;
        std::ifstream in(p, std::ios::binary);
        if (!in) error(file, "cannot read shader file '" + p.string() + "'");
        std::stringstream ss;
        ss << in.rdbuf();
        s.source = ss.str();
        s.sourceLine = 1;
      }
      script_.shaders.push_back(s);
      return;
    }
    expectEndOfLine();
    skipLine();
    s.sourceLine = static_cast<int>(li_ + 1);
    bool found = false;
    while (li_ < lines_.size()) {
      const std::string& l = lines_[li_++];
      size_t b = l.find_first_not_of(" \t");
      if (b != std::string::npos && l.compare(b, 3, "END") == 0 && l.find_first_not_of(" \t", b + 3) == std::string::npos) {
        found = true;
        break;
      }
      s.source += l + "\n";
    }
    ci_ = 0;
    if (li_ > 0) lastLine_ = logical_[li_ - 1], lastPhysical_ = static_cast<int>(li_);
    if (!found) error(t, "missing END for SHADER '" + s.name + "'");
    script_.shaders.push_back(s);
  }

  void buffer(const Token& t, bool isImage) {
    Buffer b;
    b.isImage = isImage;
    b.loc = {t.line, t.col};
    Token name = nextSameLine(std::string(isImage ? "image" : "buffer") + " name");
    b.name = name.text;
    if (script_.findBuffer(b.name)) error(name, "duplicate buffer name '" + b.name + "'");
    bool std140 = false;
    std::vector<Value> data;
    std::vector<Token> dataTokens;
    std::optional<Value> fill, seriesFrom, seriesInc;
    uint32_t size = 0;
    Token sizeTok = name;
    bool hasSize = false, hasData = false, hasFileBytes = false;
    std::vector<uint8_t> fileBytes;
    Token typeTok;
    std::string typeWord, typeName;
    while (true) {
      Token w = peekSameLine();
      if (!w.valid()) break;
      next();
      const std::string& k = w.text;
      if (k == "LOGICAL" && isImage) {  // ours: the platform layer decides the real format
        Token f = nextSameLine("logical format");
        bool known = false;
        for (auto lf : {platforms::LogicalFormat::Rgba8Unorm, platforms::LogicalFormat::Rg16Unorm,
                        platforms::LogicalFormat::Rgba16Hdr, platforms::LogicalFormat::Depth24Stencil8})
          known |= platforms::logicalFormatName(lf) == f.text;
        if (!known) error(f, "unknown logical format '" + f.text + "' (rgba8_unorm, rg16_unorm, rgba16_hdr, depth24_stencil8)");
        b.logical = f.text;
        typeTok = f;
        typeWord = "LOGICAL";
        typeName = f.text;
      } else if (k == "DATA_TYPE" || k == "FORMAT") {
        typeTok = nextSameLine(k == "FORMAT" ? "format name" : "data type");
        typeWord = k;
        typeName = typeTok.text;
      } else if (k == "STD140") {
        std140 = true;
      } else if (k == "STD430") {
        std140 = false;
      } else if (k == "SIZE") {
        sizeTok = w;
        size = uintSameLine("element count");
        hasSize = true;
      } else if (k == "FILL") {
        fill = valueToken(nextSameLine("fill value"));
      } else if (k == "SERIES_FROM") {
        seriesFrom = valueToken(nextSameLine("series start"));
        expectWord("INC_BY");
        seriesInc = valueToken(nextSameLine("series increment"));
      } else if (k == "DATA") {
        hasData = true;
        while (true) {
          Token v = next();
          if (!v.valid()) error(w, "missing END for DATA of '" + b.name + "'");
          if (v.text == "END") break;
          dataTokens.push_back(v);
        }
        break;
      } else if (k == "FILE") {
        Token kind = nextSameLine("TEXT, BINARY or PNG");
        Token file = nextSameLine("file name");
        fs::path path = fs::path(name_).parent_path() / file.text;
        std::ifstream in(path, std::ios::binary);
        if (!in) error(file, "cannot read '" + path.string() + "'");
        std::stringstream ss;
        ss << in.rdbuf();
        std::string content = ss.str();
        if (kind.text == "TEXT") {
          std::istringstream words(content);
          std::string w;
          while (words >> w) dataTokens.push_back({w, file.line, file.col, file.logical});
          hasData = true;
        } else if (kind.text == "BINARY") {
          fileBytes.assign(content.begin(), content.end());
          hasFileBytes = true;
        } else if (kind.text == "PNG") {
          std::string why;
          if (!loadPng(path.string(), &fileBytes, &b.width, &b.height, &why)) error(file, why);
          hasFileBytes = true;
        } else {
          error(kind, "unknown file kind '" + kind.text + "' (TEXT, BINARY, PNG)");
        }
      } else if (k == "WIDTH") {
        b.width = dimensionSameLine(w, "width");
      } else if (k == "HEIGHT") {
        b.height = dimensionSameLine(w, "height");
      } else if (k == "DEPTH") {
        b.depth = dimensionSameLine(w, "depth");
      } else if (k == "SAMPLES") {
        b.samples = uintSameLine("sample count");
      } else if (k == "MIP_LEVELS") {
        b.mipLevels = uintSameLine("mip level count");
      } else if (k == "VIEW_OF" && isImage) {  // ours
        Token parent = nextSameLine("parent image name");
        const Buffer* pb = script_.findBuffer(parent.text);
        if (!pb) error(parent, "unknown image '" + parent.text + "' (declare it before its views)");
        if (!pb->viewOf.empty()) error(parent, "'" + parent.text + "' is itself a view");
        b.viewOf = parent.text;
        b.width = pb->width, b.height = pb->height, b.samples = pb->samples;
      } else if (k == "DIM_1D" || k == "DIM_2D" || k == "DIM_3D") {
        b.dim = k;
      } else {
        error(w, "unexpected '" + k + "' in " + (isImage ? "IMAGE" : "BUFFER"));
      }
    }
    if (typeWord.empty()) {
      if (hasData || hasSize) errorAfter("BUFFER '" + b.name + "' needs DATA_TYPE or FORMAT");
      error(name, std::string(isImage ? "IMAGE" : "BUFFER") + " '" + b.name + "' needs DATA_TYPE or FORMAT");
    }
    std::string why;
    bool ok = false;
    if (typeWord == "LOGICAL") {
      // Texels are platform-specific: a byte layout only so that declarations stay uniform.
      if (hasData || hasSize || hasFileBytes) error(name, "LOGICAL image '" + b.name + "' takes no contents");
      b.type.name = "LOGICAL " + typeName;
      b.type.layout = {{{0, Scalar::Uint8, Mode::Uint, 0}}, 1};
      b.hasType = true;
      script_.buffers.push_back(std::move(b));
      return;
    }
    if (typeWord == "DATA_TYPE" && structs_.count(typeName)) {
      uint32_t size = 0, align = 1;
      b.type = ElementType{};
      b.type.name = typeName;
      b.type.std140 = std140;
      structLayout(typeName, std140, &b.type.layout, &size, &align);
      b.type.scalar = b.type.layout.fields.empty() ? Scalar::Uint8 : b.type.layout.fields[0].scalar;
      ok = !b.type.layout.fields.empty();
    } else {
      ok = typeWord == "FORMAT" ? parseFormat(typeName, &b.type, &why) : parseDataType(typeName, std140, &b.type, &why);
    }
    if (!ok && typeWord == "DATA_TYPE" && typeName.find('_') != std::string::npos) {
      std::string why2;  // Amber accepts format names as DATA_TYPE too
      ok = parseFormat(typeName, &b.type, &why2);
      if (ok) typeWord = "FORMAT";
      else why = why2;
    }
    if (!ok) {
      // A type Amber knows but we cannot lay out (packed formats, STRUCT names) is unsupported.
      if (typeWord == "DATA_TYPE" && typeName.find('_') != std::string::npos)
        unsupported(typeTok, "DATA_TYPE " + typeName);
      else if (typeWord == "DATA_TYPE" && typeName.find('<') == std::string::npos && !typeName.empty() &&
               !std::isdigit(static_cast<unsigned char>(typeName.back())))
        unsupported(typeTok, "DATA_TYPE " + typeName + " (STRUCT types)");
      else if (typeWord == "FORMAT")
        unsupported(typeTok, "FORMAT " + typeName);
      else
        error(typeTok, why);
      b.type.layout = {{{0, Scalar::Uint8, Mode::Uint, 0}}, 1};
    }
    b.hasType = true;
    const Layout& L = b.type.layout;
    if (isImage) {
      if (b.width == 0) b.width = 1;
      if (b.height == 0) b.height = 1;
      // As in Amber, a 1D image has one row and only a 3D image has depth.
      if (b.dim == "DIM_1D") b.height = 1;
      if (b.dim != "DIM_3D") b.depth = 1;
      uint64_t texels = uint64_t(b.width) * b.height * std::max(1u, b.depth);
      if (texels * L.stride > kMaxBufferBytes)
        error(name, "IMAGE '" + b.name + "' needs " + std::to_string(texels * L.stride) + " bytes, more than the " +
                        std::to_string(kMaxBufferBytes) + " a script may allocate");
      size = static_cast<uint32_t>(texels);
      hasSize = true;
    }
    // Checked before anything is allocated: a typo'd SIZE must fail the script, not the machine.
    if (hasSize && uint64_t(size) * L.stride > kMaxBufferBytes)
      error(sizeTok, "SIZE " + std::to_string(size) + " of " + (isImage ? "IMAGE" : "BUFFER") + " '" + b.name +
                         "' needs " + std::to_string(uint64_t(size) * L.stride) + " bytes, more than the " +
                         std::to_string(kMaxBufferBytes) + " a script may allocate");
    if (hasFileBytes) {
      b.bytes = fileBytes;
      if (hasSize) b.bytes.resize(size_t(size) * L.stride, 0);
      b.sized = true;
    } else if (hasData) {
      size_t n = L.fields.size();
      size_t elements = (dataTokens.size() + n - 1) / n;
      if (dataTokens.size() % n != 0)
        error(dataTokens.back(), "DATA of '" + b.name + "' has " + std::to_string(dataTokens.size()) +
                                     " values, not a multiple of " + std::to_string(n) + " per element");
      b.bytes.assign(elements * L.stride, 0);
      for (size_t i = 0; i < dataTokens.size(); ++i) storeElement(b.bytes, L, i / n, i % n, valueToken(dataTokens[i]));
      b.sized = true;
      if (isImage && elements != size)
        error(dataTokens.back(), "IMAGE '" + b.name + "' DATA has " + std::to_string(elements) + " texels, expected " +
                                     std::to_string(size));
    } else if (hasSize) {
      b.bytes.assign(size_t(size) * L.stride, 0);
      b.sized = true;
      if (fill || seriesFrom) {
        for (size_t e = 0; e < size; ++e)
          for (size_t f = 0; f < L.fields.size(); ++f) {
            Value v;
            if (fill) v = *fill;
            else {
              size_t k = e * L.fields.size() + f;
              v.isInteger = seriesFrom->isInteger && seriesInc->isInteger;
              // Wraps like the buffer's integer types (signed overflow would be undefined).
              v.i = static_cast<int64_t>(static_cast<uint64_t>(seriesFrom->i) +
                                         static_cast<uint64_t>(k) * static_cast<uint64_t>(seriesInc->i));
              v.d = seriesFrom->d + static_cast<double>(k) * seriesInc->d;
            }
            storeElement(b.bytes, L, e, f, v);
          }
      }
    }
    script_.buffers.push_back(std::move(b));
  }

  void sampler(const Token& t) {
    Sampler s;
    s.loc = {t.line, t.col};
    s.name = nextSameLine("sampler name").text;
    while (true) {
      Token w = peekSameLine();
      if (!w.valid()) break;
      next();
      std::string k = w.text;
      if (k == "MAG_FILTER") s.linearMag = lower(nextSameLine("filter").text) == "linear";
      else if (k == "MIN_FILTER") s.linearMin = lower(nextSameLine("filter").text) == "linear";
      else if (k == "MIPMAP_MODE") s.mipmapMode = lower(nextSameLine("mipmap mode").text);
      else if (k == "ADDRESS_MODE_U") s.addressMode[0] = lower(nextSameLine("address mode").text);
      else if (k == "ADDRESS_MODE_V") s.addressMode[1] = lower(nextSameLine("address mode").text);
      else if (k == "ADDRESS_MODE_W") s.addressMode[2] = lower(nextSameLine("address mode").text);
      else if (k == "BORDER_COLOR") {
        Token v = nextSameLine("border colour");
        static const std::set<std::string> kBorder = {"float_transparent_black", "int_transparent_black",
                                                       "float_opaque_black",      "int_opaque_black",
                                                       "float_opaque_white",      "int_opaque_white"};
        s.borderColor = lower(v.text);
        if (!kBorder.count(s.borderColor)) error(v, "unknown BORDER_COLOR '" + v.text + "'");
      } else if (k == "MIN_LOD" || k == "MAX_LOD" || k == "COMPARE_OP") {
        Token v = nextSameLine("value");
        if (k == "MAX_LOD") s.maxLod = numberToken(v);
        if (k == "COMPARE_OP" || (k == "MIN_LOD" && numberToken(v) != 0)) unsupported(w, "SAMPLER " + k);
      } else if (k == "NORMALIZED_COORDS") {
      } else if (k == "UNNORMALIZED_COORDS" || k == "COMPARE") {
        unsupported(w, "SAMPLER " + k);
        if (k == "COMPARE") nextSameLine("on/off");
      } else error(w, "unexpected '" + k + "' in SAMPLER");
    }
    script_.samplers.push_back(s);
  }

  static bool onOff(const std::string& s) { return lower(s) == "on" || lower(s) == "true"; }

  void pipelineBody(Pipeline& p, const Token& start) {
    while (true) {
      Token w = next();
      if (!w.valid()) error(start, "missing END for PIPELINE '" + p.name + "'");
      const std::string& k = w.text;
      if (k == "END") break;
      if (k == "ATTACH") {
        Token s = nextSameLine("shader name");
        const Shader* sh = script_.findShader(s.text);
        if (!sh) error(s, "unknown shader '" + s.text + "'");
        if (p.compute != (sh->stage == Stage::Compute))
          error(s, "shader '" + s.text + "' does not fit a " + std::string(p.compute ? "compute" : "graphics") + " pipeline");
        p.shaders.push_back(s.text);
        while (true) {
          Token o = peekSameLine();
          if (!o.valid()) break;
          next();
          if (o.text == "ENTRY_POINT") p.entryPoints[s.text] = nextSameLine("entry point").text;
          else if (o.text == "TYPE") {
            nextSameLine("stage");
            if (peekSameLine().valid() && peekSameLine().text == "ENTRY_POINT") continue;
          } else if (o.text == "SPECIALIZE") {
            // SPECIALIZE id AS uint32|int32|float value: the constant's 32 bits.
            uint32_t id = uintSameLine("specialization constant id");
            Token as = nextSameLine("AS");
            if (as.text != "AS") error(as, "expected AS, got '" + as.text + "'");
            Token type = nextSameLine("type (uint32, int32, float)");
            Token value = nextSameLine("value");
            uint32_t bits = 0;
            if (type.text == "uint32") {
              bits = uintToken(value);
            } else if (type.text == "int32") {
              char* end = nullptr;
              errno = 0;
              long long v = std::strtoll(value.text.c_str(), &end, 0);
              if (value.text.empty() || *end || errno || v < INT32_MIN || v > INT32_MAX)
                error(value, "expected a 32-bit integer, got '" + value.text + "'");
              bits = static_cast<uint32_t>(static_cast<int32_t>(v));
            } else if (type.text == "float") {
              float f = static_cast<float>(numberToken(value));
              std::memcpy(&bits, &f, 4);
            } else {
              error(type, "unknown SPECIALIZE type '" + type.text + "' (uint32, int32, float)");
            }
            p.specializations[s.text][id] = bits;
          } else error(o, "unexpected '" + o.text + "' after ATTACH");
        }
      } else if (k == "FRAMEBUFFER_SIZE") {
        p.fbWidth = dimensionSameLine(w, "width");
        p.fbHeight = dimensionSameLine(w, "height");
        expectEndOfLine();
      } else if (k == "BIND") {
        bind(p, w);
      } else if (k == "VERTEX_DATA") {
        VertexData v;
        v.loc = {w.line, w.col};
        Token b = nextSameLine("buffer name");
        if (!script_.findBuffer(b.text)) error(b, "unknown buffer '" + b.text + "'");
        v.buffer = b.text;
        expectWord("LOCATION");
        v.location = uintSameLine("location");
        while (true) {
          Token o = peekSameLine();
          if (!o.valid()) break;
          next();
          if (o.text == "RATE") v.perInstance = lower(nextSameLine("vertex or instance").text) == "instance";
          else if (o.text == "OFFSET") v.offset = uintSameLine("offset");
          else if (o.text == "STRIDE") v.stride = uintSameLine("stride");
          else if (o.text == "FORMAT") v.format = nextSameLine("format").text;
          else error(o, "unexpected '" + o.text + "' in VERTEX_DATA");
        }
        p.vertexData.push_back(v);
      } else if (k == "INDEX_DATA") {
        Token b = nextSameLine("buffer name");
        if (!script_.findBuffer(b.text)) error(b, "unknown buffer '" + b.text + "'");
        p.indexData = b.text;
        expectEndOfLine();
      } else if (k == "DEPTH") {
        depthBlock(p, w);
      } else if (k == "STENCIL") {
        stencilBlock(p, w);
      } else if (k == "BLEND") {
        blendBlock(p, w);
      } else if (k == "CULL_MODE") {
        p.cullMode = lower(nextSameLine("cull mode").text);
        if (p.cullMode == "front_and_back") unsupported(w, "CULL_MODE front_and_back");
      } else if (k == "FRONT_FACE") {
        p.frontFace = lower(nextSameLine("front face").text);
      } else if (k == "VIEWPORT") {
        std::array<float, 4> vp{};
        vp[0] = static_cast<float>(numberSameLine("x"));
        vp[1] = static_cast<float>(numberSameLine("y"));
        expectWord("SIZE");
        vp[2] = static_cast<float>(numberSameLine("width"));
        vp[3] = static_cast<float>(numberSameLine("height"));
        while (peekSameLine().valid()) {
          Token o = next();
          if (o.text == "MIN_DEPTH") p.viewportDepth[0] = static_cast<float>(numberSameLine("min depth"));
          else if (o.text == "MAX_DEPTH") p.viewportDepth[1] = static_cast<float>(numberSameLine("max depth"));
          else error(o, "unexpected '" + o.text + "' in VIEWPORT");
        }
        p.viewport = vp;
      } else if (k == "SET") {  // SET KERNEL ARG_NAME|ARG_NUMBER a AS type value (OpenCL)
        Token kernel = nextSameLine("KERNEL");
        if (kernel.text != "KERNEL") error(kernel, "expected KERNEL, got '" + kernel.text + "'");
        unsupported(w, "SET KERNEL (OpenCL kernel arguments)");
        skipLine();
      } else if (k == "POLYGON_MODE") {
        Token m = nextSameLine("fill, line or point");
        if (m.text != "fill" && m.text != "line" && m.text != "point")
          error(m, "unknown POLYGON_MODE '" + m.text + "' (fill, line or point)");
        p.polygonMode = m.text;
        expectEndOfLine();
      } else if (k == "PATCH_CONTROL_POINTS") {
        p.patchControlPoints = uintSameLine("control points");
        expectEndOfLine();
      } else if (k == "SHADER_OPTIMIZATION") {
        Token s = nextSameLine("shader name");
        if (!script_.findShader(s.text)) error(s, "unknown shader '" + s.text + "'");
        expectEndOfLine();
        std::vector<std::string>& passes = p.optimizations[s.text];
        passes.clear();  // DERIVE_PIPELINE: the derived block replaces the parent's
        while (true) {
          Token o = next();
          if (!o.valid()) error(w, "missing END for SHADER_OPTIMIZATION");
          if (o.text == "END") break;
          passes.push_back(o.text);
        }
      } else if (k == "COMPILE_OPTIONS" || k == "LINE_WIDTH" || k == "SUBGROUP") {
        unsupported(w, k);
        if (k == "COMPILE_OPTIONS" || k == "SUBGROUP") skipBlock(w);
        else skipLine();
      } else {
        error(w, "unexpected '" + k + "' in PIPELINE");
      }
    }
  }

  void bind(Pipeline& p, const Token& w) {
    Bind b;
    b.loc = {w.line, w.col};
    std::vector<std::string> elements;   // per element of BUFFER_ARRAY / SAMPLER_ARRAY (BUFFER: one)
    std::vector<uint64_t> offsets, ranges;  // per element, as many as given
    // OFFSET, DESCRIPTOR_OFFSET and DESCRIPTOR_RANGE take one value per element.
    auto perElement = [&](std::vector<uint64_t>& into, const char* what) {
      const size_t n = std::max<size_t>(elements.size(), 1);
      into.resize(std::max(into.size(), n), 0);
      for (size_t i = 0; i < n; ++i) into[i] += uintSameLine(what);
    };
    Token what = nextSameLine("BUFFER or SAMPLER");
    if (what.text == "SAMPLER") {
      Token s = nextSameLine("sampler name");
      if (!script_.findSampler(s.text)) error(s, "unknown sampler '" + s.text + "'");
      b.kind = BindKind::Sampler;
      b.buffer = s.text;
      if (peekSameLine().valid() && peekSameLine().text == "KERNEL") {
        Token kernel = next();
        unsupported(kernel, "BIND SAMPLER ... KERNEL (OpenCL kernel arguments)");
        return skipLine();
      }
    } else if (what.text == "SAMPLER_ARRAY") {  // BIND SAMPLER_ARRAY s0 s1 ... DESCRIPTOR_SET d BINDING b
      b.kind = BindKind::Sampler;
      while (peekSameLine().valid() && peekSameLine().text != "DESCRIPTOR_SET" && peekSameLine().text != "BINDING") {
        Token s = next();
        if (!script_.findSampler(s.text)) error(s, "unknown sampler '" + s.text + "'");
        elements.push_back(s.text);
      }
      if (elements.empty()) error(what, "SAMPLER_ARRAY without samplers");
    } else if (what.text == "BUFFER" || what.text == "BUFFER_ARRAY") {
      // BUFFER_ARRAY: the buffers of a descriptor array's elements, in order, up to AS.
      do {
        Token n = nextSameLine("buffer name");
        if (!script_.findBuffer(n.text)) error(n, "unknown buffer '" + n.text + "'");
        elements.push_back(n.text);
      } while (what.text == "BUFFER_ARRAY" && peekSameLine().valid() && peekSameLine().text != "AS");
      b.buffer = elements[0];
      if (peekSameLine().valid() && peekSameLine().text == "KERNEL") {  // OpenCL: KERNEL ARG_NAME a | ARG_NUMBER n
        Token kernel = next();
        Token how = nextSameLine("ARG_NAME or ARG_NUMBER");
        if (how.text != "ARG_NAME" && how.text != "ARG_NUMBER") error(how, "expected ARG_NAME or ARG_NUMBER, got '" + how.text + "'");
        nextSameLine("kernel argument");
        unsupported(kernel, "BIND BUFFER ... KERNEL " + how.text + " (OpenCL kernel arguments)");
        return skipLine();
      }
      expectWord("AS");
      Token as = nextSameLine("binding type");
      b.asWord = as.text;
      static const std::map<std::string, BindKind> kKinds = {
          {"color", BindKind::Color}, {"depth_stencil", BindKind::DepthStencil}, {"resolve", BindKind::Resolve},
          {"storage", BindKind::Storage}, {"uniform", BindKind::Uniform},
          {"combined_image_sampler", BindKind::CombinedImageSampler}, {"sampled_image", BindKind::SampledImage},
          {"storage_image", BindKind::StorageImage}, {"push_constant", BindKind::PushConstant}};
      auto it = kKinds.find(as.text);
      if (it != kKinds.end()) {
        b.kind = it->second;
      } else if (as.text == "storage_dynamic" || as.text == "uniform_dynamic") {
        b.kind = as.text == "storage_dynamic" ? BindKind::Storage : BindKind::Uniform;
      } else if (as.text == "uniform_texel_buffer" || as.text == "storage_texel_buffer") {
        b.kind = as.text == "uniform_texel_buffer" ? BindKind::UniformTexelBuffer : BindKind::StorageTexelBuffer;
      } else {
        error(as, "unknown binding type '" + as.text + "'");
      }
    } else {
      error(what, "expected BUFFER or SAMPLER after BIND, got '" + what.text + "'");
    }
    while (true) {
      Token o = peekSameLine();
      if (!o.valid()) break;
      next();
      if (o.text == "LOCATION") b.location = uintSameLine("location");
      else if (o.text == "DESCRIPTOR_SET") b.set = uintSameLine("descriptor set");
      else if (o.text == "BINDING") b.binding = uintSameLine("binding");
      else if (o.text == "SAMPLER") {
        Token s = nextSameLine("sampler name");
        if (!script_.findSampler(s.text)) error(s, "unknown sampler '" + s.text + "'");
        b.sampler = s.text;
      } else if (o.text == "BASE_MIP_LEVEL") {
        b.baseMipLevel = uintSameLine("mip level");
        // Colour attachments render to that level; sampled and storage images bind it and up.
        if (b.baseMipLevel && b.kind != BindKind::Color && b.kind != BindKind::CombinedImageSampler &&
            b.kind != BindKind::SampledImage && b.kind != BindKind::StorageImage)
          unsupported(o, "BASE_MIP_LEVEL on " + b.asWord);
      } else if (o.text == "DESCRIPTOR_OFFSET" || o.text == "OFFSET") {
        // Both add up to the start of the bound range (a dynamic offset is applied on top of
        // the descriptor's own); VK_WHOLE_SIZE and "to the end" are the default range.
        perElement(offsets, "offset");
        if (b.kind != BindKind::Storage && b.kind != BindKind::Uniform && b.kind != BindKind::UniformTexelBuffer &&
            b.kind != BindKind::StorageTexelBuffer)
          error(o, o.text + " applies to storage and uniform buffers");
      } else if (o.text == "DESCRIPTOR_RANGE") {
        ranges.clear();
        perElement(ranges, "range");
        if (b.kind != BindKind::Storage && b.kind != BindKind::Uniform && b.kind != BindKind::UniformTexelBuffer &&
            b.kind != BindKind::StorageTexelBuffer)
          error(o, o.text + " applies to storage and uniform buffers");
      } else error(o, "unexpected '" + o.text + "' in BIND");
    }
    if (elements.empty()) elements.push_back(b.buffer);  // BIND SAMPLER
    for (size_t i = 0; i < elements.size(); ++i) {
      Bind element = b;
      element.buffer = elements[i];
      element.arrayElement = static_cast<uint32_t>(i);
      if (i < offsets.size()) element.offset = offsets[i];
      if (i < ranges.size()) element.range = ranges[i];
      addBind(p, element);
    }
  }

  static void addBind(Pipeline& p, const Bind& b) {
    for (auto& e : p.binds)
      if (e.kind == b.kind && (b.kind == BindKind::Color ? e.location == b.location
                              : b.kind == BindKind::DepthStencil || b.kind == BindKind::Resolve || b.kind == BindKind::PushConstant
                                  ? true
                                  : e.set == b.set && e.binding == b.binding && e.arrayElement == b.arrayElement)) {
        e = b;  // DERIVE_PIPELINE rebinding replaces
        return;
      }
    p.binds.push_back(b);
  }

  void depthBlock(Pipeline& p, const Token& start) {
    while (true) {
      Token w = next();
      if (!w.valid()) error(start, "missing END for DEPTH");
      if (w.text == "END") return;
      if (w.text == "TEST") p.depthTest = onOff(nextSameLine("on/off").text);
      else if (w.text == "WRITE") p.depthWrite = onOff(nextSameLine("on/off").text);
      else if (w.text == "COMPARE_OP") p.depthCompare = lower(nextSameLine("compare op").text);
      else if (w.text == "CLAMP") {
        p.depthClamp = onOff(nextSameLine("on/off").text);
      } else if (w.text == "BOUNDS") {
        expectWord("min");
        double mn = numberSameLine("min");
        expectWord("max");
        double mx = numberSameLine("max");
        if (mn != 0.0 || mx != 1.0) unsupported(w, "DEPTH BOUNDS");
      } else if (w.text == "BIAS") {  // Amber: BIAS constant c clamp k slope s, in this order
        for (auto [word, value] : {std::pair{"constant", &p.depthBiasConstant}, std::pair{"clamp", &p.depthBiasClamp},
                                   std::pair{"slope", &p.depthBiasSlope}}) {
          expectWord(word);
          *value = static_cast<float>(numberSameLine(word));
        }
      } else error(w, "unexpected '" + w.text + "' in DEPTH");
    }
  }

  void stencilBlock(Pipeline& p, const Token& start) {
    Token face = nextSameLine("front, back or front_and_back");
    bool front = face.text == "front" || face.text == "front_and_back";
    bool back = face.text == "back" || face.text == "front_and_back";
    if (!front && !back) error(face, "expected front, back or front_and_back");
    StencilFace s = front ? p.front : p.back;
    while (true) {
      Token w = next();
      if (!w.valid()) error(start, "missing END for STENCIL");
      if (w.text == "END") break;
      if (w.text == "TEST") s.test = onOff(nextSameLine("on/off").text);
      else if (w.text == "FAIL_OP") s.failOp = lower(nextSameLine("op").text);
      else if (w.text == "PASS_OP") s.passOp = lower(nextSameLine("op").text);
      else if (w.text == "DEPTH_FAIL_OP") s.depthFailOp = lower(nextSameLine("op").text);
      else if (w.text == "COMPARE_OP") s.compareOp = lower(nextSameLine("op").text);
      else if (w.text == "COMPARE_MASK") s.compareMask = uintSameLine("mask");
      else if (w.text == "WRITE_MASK") s.writeMask = uintSameLine("mask");
      else if (w.text == "REFERENCE") s.reference = uintSameLine("reference");
      else error(w, "unexpected '" + w.text + "' in STENCIL");
    }
    if (front) p.front = s;
    if (back) p.back = s;
  }

  void blendBlock(Pipeline& p, const Token& start) {
    p.blend.enabled = true;
    while (true) {
      Token w = next();
      if (!w.valid()) error(start, "missing END for BLEND");
      if (w.text == "END") return;
      if (w.text == "CONSTANT") {  // ours: the blend constant colour, four floats 0..1
        for (int i = 0; i < 4; ++i) p.blend.constant[i] = static_cast<float>(numberSameLine("blend constant component"));
        expectEndOfLine();
        continue;
      }
      std::string v = lower(nextSameLine("value").text);
      if (w.text == "SRC_COLOR_FACTOR") p.blend.srcColor = v;
      else if (w.text == "DST_COLOR_FACTOR") p.blend.dstColor = v;
      else if (w.text == "COLOR_OP") p.blend.colorOp = v;
      else if (w.text == "SRC_ALPHA_FACTOR") p.blend.srcAlpha = v;
      else if (w.text == "DST_ALPHA_FACTOR") p.blend.dstAlpha = v;
      else if (w.text == "ALPHA_OP") p.blend.alphaOp = v;
      else error(w, "unexpected '" + w.text + "' in BLEND");
    }
  }

  void pipeline(const Token& t) {
    Pipeline p;
    p.loc = {t.line, t.col};
    Token kind = nextSameLine("graphics or compute");
    if (kind.text == "compute") p.compute = true;
    else if (kind.text != "graphics") error(kind, "expected graphics or compute, got '" + kind.text + "'");
    Token name = nextSameLine("pipeline name");
    if (script_.findPipeline(name.text)) error(name, "duplicate pipeline name '" + name.text + "'");
    p.name = name.text;
    expectEndOfLine();
    pipelineBody(p, t);
    script_.pipelines.push_back(p);
  }

  void derivePipeline(const Token& t) {
    Token name = nextSameLine("pipeline name");
    expectWord("FROM");
    Token parent = nextSameLine("parent pipeline name");
    const Pipeline* base = script_.findPipeline(parent.text);
    if (!base) error(parent, "unknown pipeline '" + parent.text + "'");
    if (script_.findPipeline(name.text)) error(name, "duplicate pipeline name '" + name.text + "'");
    Pipeline p = *base;
    p.name = name.text;
    p.loc = {t.line, t.col};
    expectEndOfLine();
    pipelineBody(p, t);
    script_.pipelines.push_back(p);
  }

  Pipeline* pipelineRef(const Token& n) {
    for (auto& p : script_.pipelines)
      if (p.name == n.text) return &p;
    error(n, "unknown pipeline '" + n.text + "'");
  }

  void clear(const Token& t) {
    Command c;
    c.loc = {t.line, t.col};
    Token n = nextSameLine("pipeline name");
    pipelineRef(n);
    c.pipeline = n.text;
    if (t.text == "CLEAR_COLOR") {
      c.kind = Command::Kind::ClearColor;
      for (int i = 0; i < 4; ++i) c.color[i] = numberSameLine("colour component (0-255)");
    } else if (t.text == "CLEAR_DEPTH") {
      c.kind = Command::Kind::ClearDepth;
      c.color[0] = numberSameLine("depth");
    } else if (t.text == "CLEAR_STENCIL") {
      c.kind = Command::Kind::ClearStencil;
      c.color[0] = uintSameLine("stencil value");
    } else {
      c.kind = Command::Kind::Clear;
    }
    expectEndOfLine();
    script_.commands.push_back(c);
  }

  void run(const Token& t) {
    Command c;
    c.loc = {t.line, t.col};
    Token n = nextSameLine("pipeline name");
    if (n.text == "TIMED_EXECUTION") n = nextSameLine("pipeline name");  // timing is only logged by Amber
    const Pipeline* p = pipelineRef(n);
    c.pipeline = n.text;
    Token w = nextSameLine("DRAW_RECT, DRAW_GRID, DRAW_ARRAY or workgroup counts");
    if (p->compute) {
      c.kind = Command::Kind::Compute;
      c.groups[0] = uintToken(w);
      c.groups[1] = uintSameLine("workgroup count y");
      c.groups[2] = uintSameLine("workgroup count z");
      expectEndOfLine();
    } else if (w.text == "DRAW_RECT" || w.text == "DRAW_GRID") {
      c.kind = w.text == "DRAW_RECT" ? Command::Kind::DrawRect : Command::Kind::DrawGrid;
      Token o = nextSameLine("POS");
      if (o.text == "ORTHO") {
        unsupported(o, "DRAW_RECT ORTHO");
        o = nextSameLine("POS");
      }
      if (o.text == "PATCH") {
        unsupported(o, "DRAW_RECT PATCH");
        o = nextSameLine("POS");
      }
      if (o.text != "POS") error(o, "expected POS, got '" + o.text + "'");
      c.x = static_cast<float>(numberSameLine("x"));
      c.y = static_cast<float>(numberSameLine("y"));
      expectWord("SIZE");
      c.w = static_cast<float>(numberSameLine("width"));
      c.h = static_cast<float>(numberSameLine("height"));
      if (c.kind == Command::Kind::DrawGrid) {
        expectWord("CELLS");
        c.cellsX = uintSameLine("columns");
        c.cellsY = uintSameLine("rows");
      }
      expectEndOfLine();
    } else if (w.text == "DRAW_ARRAY") {
      c.kind = Command::Kind::DrawArray;
      expectWord("AS");
      c.topology = nextSameLine("topology").text;
      while (true) {
        Token o = peekSameLine();
        if (!o.valid()) break;
        next();
        if (o.text == "INDEXED") c.indexed = true;
        else if (o.text == "START_IDX") c.start = uintSameLine("start index");
        else if (o.text == "COUNT") {
          c.count = uintSameLine("count");
          c.countGiven = true;
        } else if (o.text == "START_INSTANCE" || o.text == "INSTANCE_START") c.instanceStart = uintSameLine("first instance");
        else if (o.text == "INSTANCE_COUNT") c.instanceCount = uintSameLine("instance count");
        else error(o, "unexpected '" + o.text + "' in DRAW_ARRAY");
      }
    } else {
      error(w, "expected DRAW_RECT, DRAW_GRID or DRAW_ARRAY, got '" + w.text + "'");
    }
    script_.commands.push_back(c);
  }

  // Ours: RESOLVE img [SAMPLES n]: the platform's resolve (or copy) of a LOGICAL image.
  void resolve(const Token& t) {
    Command c;
    c.kind = Command::Kind::Resolve;
    c.loc = {t.line, t.col};
    Token n = nextSameLine("image name");
    const Buffer* b = script_.findBuffer(n.text);
    if (!b) error(n, "unknown image '" + n.text + "'");
    if (b->logical.empty()) error(n, "RESOLVE needs a LOGICAL image, '" + n.text + "' is not one");
    c.buffer = n.text;
    if (peekSameLine().valid()) {
      expectWord("SAMPLES");
      c.resolveSamples = uintSameLine("sample count");
    }
    expectEndOfLine();
    script_.commands.push_back(c);
  }

  // Ours: EXPECT img MEMORY BYTES [RESOLVED] [PLATFORM p] IDX x y [SIZE w h] EQ bytes...
  void expectMemory(Command& c, const Buffer& b) {
    c.kind = Command::Kind::ExpectMemory;
    if (b.logical.empty()) errorAfter("MEMORY BYTES needs a LOGICAL image, '" + b.name + "' is not one");
    expectWord("BYTES");
    Token w = nextSameLine("IDX");
    if (w.text == "RESOLVED") c.afterResolve = true, w = nextSameLine("IDX");
    if (w.text == "PLATFORM") {
      Token p = nextSameLine("platform name");
      if (!platforms::platformFromName(p.text)) error(p, "unknown platform '" + p.text + "' (reference, dx10, ps3, x360)");
      c.platform = p.text;
      w = nextSameLine("IDX");
    }
    if (w.text != "IDX") error(w, "expected IDX, got '" + w.text + "'");
    c.px = uintSameLine("x");
    c.py = uintSameLine("y");
    Token o = nextSameLine("SIZE or EQ");
    if (o.text == "SIZE") {
      c.pw = uintSameLine("width");
      c.ph = uintSameLine("height");
      o = nextSameLine("EQ");
    }
    if (o.text != "EQ") error(o, "expected EQ, got '" + o.text + "'");
    while (peekSameLine().valid()) {
      Token v = next();
      Value x = valueToken(v);
      if (!x.isInteger || x.i < 0 || x.i > 255) error(v, "expected a byte (0-255 or 0x00-0xFF), got '" + v.text + "'");
      c.values.push_back(x);
    }
    if (c.values.empty()) errorAfter("expected bytes after EQ");
  }

  // Ours: EXPECT img EQ_IMAGE (FILE path | GOLDEN name) [RMSE t] [MAX t] [FLIP t]
  void expectImage(Command& c) {
    c.kind = Command::Kind::ExpectImage;
    Token k = nextSameLine("FILE or GOLDEN");
    Token f = nextSameLine(k.text == "GOLDEN" ? "golden name" : "file name");
    fs::path dir = fs::path(name_).parent_path();
    if (k.text == "FILE") c.imageFile = (dir / f.text).string();
    else if (k.text == "GOLDEN") c.imageFile = (dir / "golden" / (f.text + ".png")).string();
    else error(k, "expected FILE or GOLDEN, got '" + k.text + "'");
    while (peekSameLine().valid()) {
      Token o = next();
      double v = numberSameLine("tolerance");
      if (o.text == "RMSE") c.imageRmse = v;
      else if (o.text == "MAX") c.imageMax = v;
      else if (o.text == "FLIP") c.imageFlip = v;
      else error(o, "unexpected '" + o.text + "' (RMSE, MAX or FLIP)");
    }
  }

  std::vector<Tolerance> tolerances() {
    std::vector<Tolerance> out;
    while (true) {
      Token o = peekSameLine();
      if (!o.valid()) break;
      std::string s = o.text;
      bool percent = !s.empty() && s.back() == '%';
      if (percent) s.pop_back();
      if (!isNumber(s)) break;
      next();
      out.push_back({std::strtod(s.c_str(), nullptr), percent});
    }
    if (out.empty()) errorAfter("expected a tolerance");
    if (out.size() > 4) errorAfter("at most 4 tolerances");
    return out;
  }

  void expect(const Token& t) {
    Command c;
    c.loc = {t.line, t.col};
    Token b = nextSameLine("buffer name");
    const Buffer* buf = script_.findBuffer(b.text);
    if (!buf) error(b, "unknown buffer '" + b.text + "'");
    c.buffer = b.text;
    Token w = nextSameLine("IDX, EQ_BUFFER or RMSE_BUFFER");
    if (w.text == "MEMORY" || w.text == "EQ_IMAGE") {
      if (w.text == "MEMORY") expectMemory(c, *buf);
      else expectImage(c);
      script_.commands.push_back(c);
      return;
    }
    if (w.text == "EQ_BUFFER" || w.text == "RMSE_BUFFER" || w.text == "EQ_HISTOGRAM_EMD_BUFFER") {
      c.kind = Command::Kind::ExpectBuffer;
      Token o = nextSameLine("buffer name");
      if (!script_.findBuffer(o.text)) error(o, "unknown buffer '" + o.text + "'");
      c.other = o.text;
      if (w.text != "EQ_BUFFER") {
        c.rmse = true;
        expectWord("TOLERANCE");
        c.rmseTolerance = numberSameLine("tolerance");
        c.emd = w.text == "EQ_HISTOGRAM_EMD_BUFFER";
      }
      expectEndOfLine();
      script_.commands.push_back(c);
      return;
    }
    if (w.text == "RELATIVE") {
      unsupported(w, "EXPECT RELATIVE");
      return skipLine();
    }
    if (w.text != "IDX") error(w, "expected IDX, EQ_BUFFER or RMSE_BUFFER, got '" + w.text + "'");
    Token x = nextSameLine("index");
    c.px = uintToken(x);
    Token o = nextSameLine("comparator");
    bool isProbe = false;
    if (Parser::isNumber(o.text)) {  // IDX x y: an image probe
      c.py = uintToken(o);
      isProbe = true;
      o = nextSameLine("SIZE or comparator");
      if (o.text == "SIZE") {
        c.pw = uintSameLine("width");
        c.ph = uintSameLine("height");
        o = nextSameLine("EQ_RGBA or EQ_RGB");
      }
    }
    if (o.text == "EQ_RGBA" || o.text == "EQ_RGB") {
      if (!isProbe) error(o, o.text + " needs IDX x y");
      c.kind = Command::Kind::ExpectProbe;
      c.rgba = o.text == "EQ_RGBA";
      for (int i = 0; i < (c.rgba ? 4 : 3); ++i) c.color[i] = numberSameLine("colour component");
      Token tol = peekSameLine();
      if (tol.valid()) {
        next();
        if (tol.text != "TOLERANCE") error(tol, "unexpected '" + tol.text + "'");
        c.tolerances = tolerances();
      }
      expectEndOfLine();
      script_.commands.push_back(c);
      return;
    }
    if (isProbe) error(o, "expected EQ_RGBA or EQ_RGB, got '" + o.text + "'");
    c.kind = Command::Kind::ExpectValues;
    if (o.text == "TOLERANCE") {
      c.tolerances = tolerances();
      o = nextSameLine("EQ");
      if (o.text != "EQ") error(o, "TOLERANCE needs EQ, got '" + o.text + "'");
      c.comparator = Comparator::FuzzyEq;
    } else {
      static const std::map<std::string, Comparator> kCmp = {{"EQ", Comparator::Eq}, {"NE", Comparator::Ne},
                                                             {"LT", Comparator::Lt}, {"LE", Comparator::Le},
                                                             {"GT", Comparator::Gt}, {"GE", Comparator::Ge}};
      auto it = kCmp.find(o.text);
      if (it == kCmp.end()) error(o, "unknown comparator '" + o.text + "' (EQ NE LT LE GT GE EQ_RGB EQ_RGBA)");
      c.comparator = it->second;
    }
    // Values may continue over following lines until the next command word.
    while (true) {
      Token v = peekSameLine();
      if (!v.valid()) break;
      next();
      c.values.push_back(valueToken(v));
    }
    if (c.values.empty()) errorAfter("expected values after " + o.text);
    script_.commands.push_back(c);
  }
};

}  // namespace

ParseResult parseScript(const std::string& text, const std::string& name) {
  ParseResult r;
  try {
    Parser p(text, name);
    r.script = p.run();
    r.ok = true;
  } catch (const ParseError& e) {
    r.error = name + ":" + std::to_string(e.loc.line) + ":" + std::to_string(e.loc.column) + ": error: " + e.message;
  }
  return r;
}

ParseResult parseScriptFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    ParseResult r;
    r.error = path + ": error: cannot read the file";
    return r;
  }
  std::stringstream ss;
  ss << in.rdbuf();
  // piglit's and VkRunner's format by its extension; everything else is AmberScript.
  if (isShaderTestPath(path)) return parseShaderTest(ss.str(), path);
  return parseScript(ss.str(), path);
}

}  // namespace parity::harness::script
