// AmberScript declarations: SHADER, BUFFER, IMAGE, SAMPLER, STRUCT and VIRTUAL_FILE.
#include "harness/scripts/amber/statements.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "platforms/common/platform.h"

namespace fs = std::filesystem;

namespace parity::harness::script::amber {

// VIRTUAL_FILE path NEWLINE lines END: a file that SHADER ... VIRTUAL_FILE path (or FILE path)
// reads instead of the disk.
void DeclarationStatements::virtualFile(const Token& t) {
  Token path = nextSameLine("virtual file path");
  expectEndOfLine();
  if (virtualFiles_.count(path.text)) error(path, "duplicate VIRTUAL_FILE '" + path.text + "'");
  std::string content;
  if (!blockLines(&content)) error(t, "missing END for VIRTUAL_FILE '" + path.text + "'");
  virtualFiles_[path.text] = content;
}

// STRUCT name [STRIDE n] NEWLINE (type member [OFFSET n])* END
void DeclarationStatements::structDecl(const Token& t) {
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
void DeclarationStatements::structLayout(const std::string& name, bool std140, Layout* out, uint32_t* size, uint32_t* align) {
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

void DeclarationStatements::shader(const Token& t) {
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
  bool found = blockLines(&s.source, &s.sourceLine);
  if (!found) error(t, "missing END for SHADER '" + s.name + "'");
  script_.shaders.push_back(s);
}

void DeclarationStatements::buffer(const Token& t, bool isImage) {
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

void DeclarationStatements::sampler(const Token& t) {
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
    } else if (k == "MIN_LOD" || k == "MAX_LOD") {
      Token v = nextSameLine("value");
      (k == "MAX_LOD" ? s.maxLod : s.minLod) = numberToken(v);
    } else if (k == "COMPARE_OP") {
      Token v = nextSameLine("compare op");
      static const std::set<std::string> kOps = {"never", "less", "equal", "less_or_equal",
                                                 "greater", "not_equal", "greater_or_equal", "always"};
      s.compareOp = lower(v.text);
      if (!kOps.count(s.compareOp)) error(v, "unknown COMPARE_OP '" + v.text + "'");
    } else if (k == "COMPARE") {
      Token v = nextSameLine("on/off");
      if (lower(v.text) != "on" && lower(v.text) != "off") error(v, "COMPARE takes on or off, got '" + v.text + "'");
      s.compare = lower(v.text) == "on";
    } else if (k == "NORMALIZED_COORDS") {
    } else if (k == "UNNORMALIZED_COORDS") {
      unsupported(w, "SAMPLER " + k);
    } else error(w, "unexpected '" + k + "' in SAMPLER");
  }
  if (s.minLod > s.maxLod) error(t, "SAMPLER " + s.name + ": MIN_LOD above MAX_LOD");
  script_.samplers.push_back(s);
}

}  // namespace parity::harness::script::amber
