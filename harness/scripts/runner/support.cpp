#include "harness/scripts/runner/support.h"

#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

namespace parity::harness::script::runner {

std::string formatOfDataType(const ElementType& t) {
  const uint32_t bits = scalarSize(t.scalar) * 8;
  if (t.columns != 1 || t.rows > 4 || t.layout.stride != t.rows * bits / 8 || t.scalar == Scalar::Float64) return "";
  std::string name;
  for (uint32_t c = 0; c < t.rows; ++c) name += std::string(1, "RGBA"[c]) + std::to_string(bits);
  switch (t.scalar) {
    case Scalar::Float16: case Scalar::Float32: return name + "_SFLOAT";
    case Scalar::Int8: case Scalar::Int16: case Scalar::Int32: case Scalar::Int64: return name + "_SINT";
    default: return name + "_UINT";
  }
}

TexFormat textureFormat(const ElementType& t) {
  static const std::map<std::string, TexFormat> kMap = {
      {"R8G8B8A8_UNORM", {rhi::Format::RGBA8, false}},      {"B8G8R8A8_UNORM", {rhi::Format::RGBA8, true}},
      {"R8G8B8A8_SRGB", {rhi::Format::RGBA8_SRGB, false}},  {"B8G8R8A8_SRGB", {rhi::Format::RGBA8_SRGB, true}},
      {"R8G8B8A8_UINT", {rhi::Format::RGBA8_UINT, false}},  {"R8_UNORM", {rhi::Format::R8, false}},
      {"R16G16_UNORM", {rhi::Format::RG16_UNORM, false}},   {"R16G16_SNORM", {rhi::Format::RG16_SNORM, false}},
      {"R16G16_SFLOAT", {rhi::Format::RG16_FLOAT, false}},  {"R16G16_UINT", {rhi::Format::RG16_UINT, false}},
      {"R32_UINT", {rhi::Format::R32_UINT, false}},         {"R32_SFLOAT", {rhi::Format::R32F, false}},
      {"R16G16B16A16_SFLOAT", {rhi::Format::RGBA16F, false}}, {"R32G32_SFLOAT", {rhi::Format::RG32F, false}},
      {"R32G32B32A32_SFLOAT", {rhi::Format::RGBA32F, false}},
      {"R8G8_UINT", {rhi::Format::RG8_UINT, false}},        {"R8G8_SNORM", {rhi::Format::RG8_SNORM, false}},
      {"R16_SNORM", {rhi::Format::R16_SNORM, false}},       {"R8G8B8A8_SNORM", {rhi::Format::RGBA8_SNORM, false}},
      {"R16G16B16A16_SNORM", {rhi::Format::RGBA16_SNORM, false}},
      {"B10G11R11_UFLOAT_PACK32", {rhi::Format::B10G11R11_UFLOAT, false}},
      {"R32_SINT", {rhi::Format::R32_SINT, false}},         {"R32G32B32A32_UINT", {rhi::Format::RGBA32_UINT, false}},
      {"R32G32B32A32_SINT", {rhi::Format::RGBA32_SINT, false}},
      // The RHI's only stencil format is D24S8: 32-bit float depth with stencil runs as D24S8.
      {"D32_SFLOAT_S8_UINT", {rhi::Format::D24S8, false}},  {"D24_UNORM_S8_UINT", {rhi::Format::D24S8, false}},
      {"X8_D24_UNORM_PACK32", {rhi::Format::D24S8, false}}, {"D32_SFLOAT", {rhi::Format::D32F, false}},
      {"D16_UNORM", {rhi::Format::D16, false}},
      {"R8G8B8_UNORM", {rhi::Format::RGBA8, false, 0xFF}}, {"B8G8R8_UNORM", {rhi::Format::RGBA8, true, 0xFF}},
      {"R8G8B8_SNORM", {rhi::Format::RGBA8_SNORM, false, 0x7F}}, {"B8G8R8_SNORM", {rhi::Format::RGBA8_SNORM, true, 0x7F}}};
  const std::string name = t.isFormat ? t.name : formatOfDataType(t);
  auto it = kMap.find(name);
  if (it != kMap.end()) return it->second;
  if (!t.isFormat) throw Unsupported{"image with DATA_TYPE " + t.name + (name.empty() ? " (no image format has its layout)" : " (" + name + " is no RHI format)")};
  throw Unsupported{"FORMAT " + t.name + " as an image (no RHI format)"};
}

bool integerComponents(const ElementType& t) {
  for (const Field& f : t.layout.fields)
    if (f.scalar != t.layout.fields[0].scalar || (f.mode != Mode::Int && f.mode != Mode::Uint)) return false;
  return !t.layout.fields.empty();
}

rhi::VertexFormat integerVertexFormat(Scalar s, size_t n) {
  static const rhi::VertexFormat kUint[] = {rhi::VertexFormat::UInt, rhi::VertexFormat::UInt2, rhi::VertexFormat::UInt3,
                                             rhi::VertexFormat::UInt4};
  static const rhi::VertexFormat kInt[] = {rhi::VertexFormat::Int, rhi::VertexFormat::Int2, rhi::VertexFormat::Int3,
                                            rhi::VertexFormat::Int4};
  return (s == Scalar::Int32 ? kInt : kUint)[n - 1];
}

double readScalar(const uint8_t* p, Scalar s) {
  auto get = [&](auto x) {
    std::memcpy(&x, p, sizeof(x));
    return static_cast<double>(x);
  };
  switch (s) {
    case Scalar::Int8: return get(int8_t{});
    case Scalar::Int16: return get(int16_t{});
    case Scalar::Int32: return get(int32_t{});
    case Scalar::Int64: return get(int64_t{});
    case Scalar::Uint8: return get(uint8_t{});
    case Scalar::Uint16: return get(uint16_t{});
    case Scalar::Uint32: return get(uint32_t{});
    case Scalar::Uint64: return get(uint64_t{});
    case Scalar::Float16: {
      uint16_t h;
      std::memcpy(&h, p, 2);
      uint32_t e = (h >> 10) & 0x1F, m = h & 0x3FF;
      double v = e == 0 ? std::ldexp(m, -24) : e == 31 ? (m ? NAN : INFINITY) : std::ldexp(m | 0x400, int(e) - 25);
      return (h & 0x8000) ? -v : v;
    }
    case Scalar::Float32: return get(float{});
    default: return get(double{});
  }
}

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

rhi::ShaderStage rhiStage(Stage s) {
  switch (s) {
    case Stage::Vertex: return rhi::ShaderStage::Vertex;
    case Stage::Fragment: return rhi::ShaderStage::Fragment;
    case Stage::Compute: return rhi::ShaderStage::Compute;
    case Stage::Geometry: return rhi::ShaderStage::Geometry;
    case Stage::TessControl: return rhi::ShaderStage::TessControl;
    case Stage::TessEvaluation: return rhi::ShaderStage::TessEvaluation;
  }
  return rhi::ShaderStage::Vertex;
}

rhi::CompareOp compareOp(const std::string& s) {
  static const std::map<std::string, rhi::CompareOp> k = {
      {"never", rhi::CompareOp::Never}, {"less", rhi::CompareOp::Less}, {"equal", rhi::CompareOp::Equal},
      {"less_or_equal", rhi::CompareOp::LessEqual}, {"greater", rhi::CompareOp::Greater},
      {"not_equal", rhi::CompareOp::NotEqual}, {"greater_or_equal", rhi::CompareOp::GreaterEqual},
      {"always", rhi::CompareOp::Always}};
  auto it = k.find(s);
  if (it == k.end()) throw Failure{"unknown compare op '" + s + "'"};
  return it->second;
}

rhi::StencilOp stencilOp(const std::string& s) {
  static const std::map<std::string, rhi::StencilOp> k = {
      {"keep", rhi::StencilOp::Keep}, {"zero", rhi::StencilOp::Zero}, {"replace", rhi::StencilOp::Replace},
      {"increment_and_clamp", rhi::StencilOp::IncrementClamp}, {"decrement_and_clamp", rhi::StencilOp::DecrementClamp},
      {"invert", rhi::StencilOp::Invert}, {"increment_and_wrap", rhi::StencilOp::IncrementWrap},
      {"decrement_and_wrap", rhi::StencilOp::DecrementWrap}};
  auto it = k.find(s);
  if (it == k.end()) throw Failure{"unknown stencil op '" + s + "'"};
  return it->second;
}

StencilValues stencilValues(const Pipeline& p) {
  StencilValues out{p.front.reference, p.front.compareMask, p.front.writeMask, true};
  struct Use {
    bool reference = false, compareMask = false, writeMask = false;
  };
  auto use = [](const StencilFace& f) {
    Use u;
    if (!f.test) return u;
    const bool compares = f.compareOp != "always" && f.compareOp != "never";
    const bool replaces = f.failOp == "replace" || f.passOp == "replace" || f.depthFailOp == "replace";
    u.reference = compares || replaces;
    u.compareMask = compares;
    u.writeMask = f.failOp != "keep" || f.passOp != "keep" || f.depthFailOp != "keep";
    return u;
  };
  const Use front = use(p.front), back = use(p.back);
  auto pick = [&](uint32_t StencilFace::*value, bool Use::*used, uint32_t& into) {
    if (front.*used && back.*used && p.front.*value != p.back.*value) out.agree = false;
    into = front.*used || !(back.*used) ? p.front.*value : p.back.*value;
  };
  pick(&StencilFace::reference, &Use::reference, out.reference);
  pick(&StencilFace::compareMask, &Use::compareMask, out.compareMask);
  pick(&StencilFace::writeMask, &Use::writeMask, out.writeMask);
  return out;
}

rhi::BlendFactor blendFactor(const std::string& s) {
  static const std::map<std::string, rhi::BlendFactor> k = {
      {"zero", rhi::BlendFactor::Zero}, {"one", rhi::BlendFactor::One}, {"src_color", rhi::BlendFactor::SrcColor},
      {"one_minus_src_color", rhi::BlendFactor::OneMinusSrcColor}, {"dst_color", rhi::BlendFactor::DstColor},
      {"one_minus_dst_color", rhi::BlendFactor::OneMinusDstColor}, {"src_alpha", rhi::BlendFactor::SrcAlpha},
      {"one_minus_src_alpha", rhi::BlendFactor::OneMinusSrcAlpha}, {"dst_alpha", rhi::BlendFactor::DstAlpha},
      {"one_minus_dst_alpha", rhi::BlendFactor::OneMinusDstAlpha}, {"constant_color", rhi::BlendFactor::ConstantColor},
      {"one_minus_constant_color", rhi::BlendFactor::OneMinusConstantColor}};
  auto it = k.find(s);
  if (it == k.end()) throw Unsupported{"blend factor " + s};
  return it->second;
}

rhi::BlendOp blendOp(const std::string& s) {
  static const std::map<std::string, rhi::BlendOp> k = {
      {"add", rhi::BlendOp::Add}, {"subtract", rhi::BlendOp::Subtract},
      {"reverse_subtract", rhi::BlendOp::ReverseSubtract}, {"min", rhi::BlendOp::Min}, {"max", rhi::BlendOp::Max}};
  auto it = k.find(s);
  if (it == k.end()) throw Unsupported{"blend op " + s};
  return it->second;
}

rhi::AddressMode addressMode(const std::string& s) {
  if (s == "repeat") return rhi::AddressMode::Repeat;
  if (s == "mirrored_repeat") return rhi::AddressMode::MirroredRepeat;
  if (s == "clamp_to_edge") return rhi::AddressMode::ClampToEdge;
  if (s == "clamp_to_border") return rhi::AddressMode::ClampToBorder;
  throw Unsupported{"sampler address mode " + s};
}

rhi::BorderColor borderColor(const std::string& s) {
  static const std::map<std::string, rhi::BorderColor> k = {
      {"float_transparent_black", rhi::BorderColor::FloatTransparentBlack},
      {"float_opaque_black", rhi::BorderColor::FloatOpaqueBlack},
      {"float_opaque_white", rhi::BorderColor::FloatOpaqueWhite},
      {"int_transparent_black", rhi::BorderColor::IntTransparentBlack},
      {"int_opaque_black", rhi::BorderColor::IntOpaqueBlack},
      {"int_opaque_white", rhi::BorderColor::IntOpaqueWhite}};
  auto it = k.find(s);
  if (it == k.end()) throw Unsupported{"sampler border colour " + s};
  return it->second;
}

// `declarations` after the #version line and any #extension lines (which must precede
// declarations), then a #line that keeps the compiler's line numbers those of the script.
// `version`: the line for a source without one; `versionAdded`: the source's #version line was
// added to it (its lines start after it).
std::string withDeclarations(std::string src, const std::string& declarations, int sourceLine, const std::string& version,
                             bool versionAdded) {
  size_t v = src.find("#version");
  if (v == std::string::npos && !version.empty()) return withDeclarations(version + "\n" + src, declarations, sourceLine, "", true);
  if (v == std::string::npos) {
    // No #version at all (GLSL 1.10): after the last #extension line (comments may come before
    // them; an #extension after code is an error in any case).
    size_t end = 0;
    int lines = 0;
    for (size_t at = 0, line = 0; at < src.size(); ++line) {
      const size_t eol = src.find('\n', at), first = src.find_first_not_of(" \t", at);
      if (eol == std::string::npos) break;
      if (first != std::string::npos && src.compare(first, 10, "#extension") == 0) {
        end = eol + 1;
        lines = static_cast<int>(line) + 1;
      }
      at = eol + 1;
    }
    src.insert(end, declarations + "#line " + std::to_string(sourceLine + lines) + "\n");
    return src;
  }
  size_t eol = src.find('\n', v);
  for (size_t at = eol; !declarations.empty() && at != std::string::npos && at + 1 < src.size(); at = src.find('\n', at + 1)) {
    size_t first = src.find_first_not_of(" \t", at + 1);
    if (first != std::string::npos && src.compare(first, 10, "#extension") == 0) eol = src.find('\n', first);
  }
  int linesBefore = static_cast<int>(std::count(src.begin(), src.begin() + static_cast<long>(eol), '\n'));
  if (versionAdded) --linesBefore;
  if (eol != std::string::npos) src.insert(eol + 1, declarations + "#line " + std::to_string(sourceLine + linesBefore + 1) + "\n");
  return src;
}


}  // namespace parity::harness::script::runner
