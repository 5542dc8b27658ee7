#include "harness/scripts/script.h"

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

#include "harness/io/image_io.h"
#include "harness/scripts/shader_test_parser.h"
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

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

namespace {

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
bool Script::hasArbPrograms() const {
  return std::any_of(shaders.begin(), shaders.end(), [](const Shader& s) { return s.format == "ARB"; });
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

namespace {

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

void applyHexFloatBits(const std::string& word, Scalar s, Value* v) {
  if (word.size() < 3 || word[0] != '0' || (word[1] != 'x' && word[1] != 'X') || !v->isInteger) return;
  const uint64_t bits = static_cast<uint64_t>(v->i);
  if (s == Scalar::Float32) {
    float f;
    const uint32_t u = static_cast<uint32_t>(bits);
    std::memcpy(&f, &u, sizeof f);
    v->d = f;
  } else if (s == Scalar::Float64) {
    std::memcpy(&v->d, &bits, sizeof bits);
  } else {
    return;
  }
  v->isInteger = false;
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
