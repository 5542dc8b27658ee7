#include "harness/script_runner.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

#include <spirv-tools/optimizer.hpp>

#include "harness/flip.h"
#include "harness/opengl_glsl.h"
#include "harness/spirv_interface.h"
#include "platforms/platform_layer.h"
#include "platforms/x360/pixel_center.h"
#include "rhi/shader_compiler.h"
#include "rhi/shader_reflection.h"

namespace parity::harness::script {

const char* verdictName(Verdict v) {
  switch (v) {
    case Verdict::Pass: return "PASS";
    case Verdict::Fail: return "FAIL";
    default: return "SKIP";
  }
}

std::vector<std::string> allowedPlatforms(const Script& script) {
  std::vector<std::string> named;
  for (const Requirement& r : script.requirements)
    if (r.what == "platform" && std::find(named.begin(), named.end(), r.value) == named.end()) named.push_back(r.value);
  if (!named.empty()) return named;
  std::vector<std::string> all;
  for (auto id : {platforms::PlatformId::Reference, platforms::PlatformId::Dx10, platforms::PlatformId::Ps3,
                  platforms::PlatformId::X360})
    all.emplace_back(platforms::platformName(id));
  return all;
}

std::string skipReasonBeforeRun(const Script& script, const std::string& backend, const RunOptions& options) {
  for (const Requirement& r : script.requirements)
    if (r.what == "backend" && r.value != backend)
      return "REQUIRE backend " + r.value + " (line " + std::to_string(r.loc.line) + ")";
  std::vector<std::string> allowed = allowedPlatforms(script);
  if (std::find(allowed.begin(), allowed.end(), options.platform) == allowed.end()) {
    std::string list;
    for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
    return "REQUIRE platform " + list + "; not " + options.platform;
  }
  if (!script.unsupported.empty()) {
    std::string s = "unsupported: ";
    for (size_t i = 0; i < script.unsupported.size() && i < 3; ++i)
      s += (i ? ", " : "") + script.unsupported[i].feature + " (line " + std::to_string(script.unsupported[i].loc.line) + ")";
    if (script.unsupported.size() > 3) s += " and " + std::to_string(script.unsupported.size() - 3) + " more";
    return s;
  }
  return {};
}

namespace {

struct Unsupported {
  std::string what;
};
struct Failure {
  std::string what;
};

std::string lineOf(const Location& l) { return "line " + std::to_string(l.line); }

// SHADER_OPTIMIZATION: the named spirv-opt passes, in order, as Amber runs them on the module
// before the pipeline is made. Amber's documentation writes the flags with and without "--".
void optimizeSpirv(std::vector<uint32_t>& module, const std::vector<std::string>& passes, const std::string& shader) {
  spvtools::Optimizer optimizer(SPV_ENV_VULKAN_1_3);
  std::string messages;
  optimizer.SetMessageConsumer([&](spv_message_level_t, const char*, const spv_position_t&, const char* m) {
    messages += std::string(messages.empty() ? "" : "; ") + m;
  });
  for (const std::string& pass : passes) {
    const std::string flag = pass.rfind("--", 0) == 0 ? pass : "--" + pass;
    if (!optimizer.RegisterPassFromFlag(flag))
      throw Unsupported{"SHADER_OPTIMIZATION " + flag + " (not a pass of this SPIRV-Tools)"};
  }
  std::vector<uint32_t> optimized;
  if (!optimizer.Run(module.data(), module.size(), &optimized))
    throw Failure{"SHADER_OPTIMIZATION of shader '" + shader + "' failed: " + messages};
  module = std::move(optimized);
}

// --- formats ---
struct TexFormat {
  rhi::Format format = rhi::Format::Undefined;
  bool bgra = false;  // script bytes are B,G,R,A; the texture stores R,G,B,A
};

// The format Amber gives an image declared with a DATA_TYPE: one channel per vector component
// (int32 -> R32_SINT, vec4<float> -> R32G32B32A32_SFLOAT). Empty when the type's layout is no
// format's (matrices, padded vec3).
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
      {"D16_UNORM", {rhi::Format::D16, false}}};
  const std::string name = t.isFormat ? t.name : formatOfDataType(t);
  auto it = kMap.find(name);
  if (it != kMap.end()) return it->second;
  if (!t.isFormat) throw Unsupported{"image with DATA_TYPE " + t.name + (name.empty() ? " (no image format has its layout)" : " (" + name + " is no RHI format)")};
  throw Unsupported{"FORMAT " + t.name + " as an image (no RHI format)"};
}

// Whether every component of a vertex type is an integer (uint or int, not normalised) of one
// scalar type: what the RHI's integer vertex formats fetch.
bool integerComponents(const ElementType& t) {
  for (const Field& f : t.layout.fields)
    if (f.scalar != t.layout.fields[0].scalar || (f.mode != Mode::Int && f.mode != Mode::Uint)) return false;
  return !t.layout.fields.empty();
}

// The RHI's 32-bit integer vertex format of n components (uint or int, as the shader reads it).
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

bool isIntegerScalar(Scalar s) { return s != Scalar::Float16 && s != Scalar::Float32 && s != Scalar::Float64; }

double srgbToLinear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

// --- SPIR-V descriptor remapping: the RHI has one descriptor set; Amber scripts use many ---
using SetBinding = std::pair<uint32_t, uint32_t>;

std::set<SetBinding> spirvBindings(const std::vector<uint32_t>& spirv) {
  std::map<uint32_t, uint32_t> set, binding;
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0) break;
    if (op == 71 && n >= 4) {
      if (spirv[i + 2] == 34) set[spirv[i + 1]] = spirv[i + 3];
      if (spirv[i + 2] == 33) binding[spirv[i + 1]] = spirv[i + 3];
    }
    i += n;
  }
  std::set<SetBinding> out;
  for (auto& [id, b] : binding) out.insert({set.count(id) ? set[id] : 0, b});
  return out;
}

void remapSpirv(std::vector<uint32_t>& spirv, const std::map<SetBinding, uint32_t>& map) {
  std::map<uint32_t, uint32_t> set;
  std::map<uint32_t, size_t> setWord, bindingWord;
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0) break;
    if (op == 71 && n >= 4) {
      if (spirv[i + 2] == 34) setWord[spirv[i + 1]] = i + 3;
      if (spirv[i + 2] == 33) bindingWord[spirv[i + 1]] = i + 3;
    }
    i += n;
  }
  for (auto& [id, bw] : bindingWord) {
    uint32_t s = setWord.count(id) ? spirv[setWord[id]] : 0;
    auto it = map.find({s, spirv[bw]});
    if (it == map.end()) continue;
    spirv[bw] = it->second;
    if (setWord.count(id)) spirv[setWord[id]] = 0;
  }
}

// SPECIALIZE: the default value of each OpSpecConstant whose SpecId is given is replaced in the
// module itself, so both backends see constants with those values and neither API's
// specialization mechanism is needed (GL's glSpecializeShader takes no SPIR-V through
// SPIRV-Cross; on GL the cross-compiled GLSL keeps the defaults as its constants).
void specializeSpirv(std::vector<uint32_t>& spirv, const std::map<uint32_t, uint32_t>& values, const std::string& shader) {
  std::map<uint32_t, uint32_t> idOfSpecId;
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0 || i + n > spirv.size()) break;
    if (op == 71 && n >= 4 && spirv[i + 2] == 1) idOfSpecId[spirv[i + 3]] = spirv[i + 1];  // OpDecorate SpecId
    i += n;
  }
  std::set<uint32_t> done;
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0 || i + n > spirv.size()) break;
    bool specConstant = op >= 48 && op <= 52;  // OpSpecConstantTrue/False, OpSpecConstant(Composite/Op)
    for (const auto& [specId, bits] : values) {
      auto id = idOfSpecId.find(specId);
      if (!specConstant || id == idOfSpecId.end() || n < 3 || spirv[i + 2] != id->second) continue;
      if (op != 50 || n != 4)  // OpSpecConstant with one literal word: a 32-bit scalar
        throw Unsupported{"SPECIALIZE " + std::to_string(specId) + " of a constant that is not a 32-bit scalar"};
      spirv[i + 3] = bits;
      done.insert(specId);
    }
    i += n;
  }
  for (const auto& [specId, bits] : values)
    if (!done.count(specId))
      throw Failure{"SPECIALIZE " + std::to_string(specId) + ": shader '" + shader + "' has no specialization constant with that id"};
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

// --- rhi enum names ---
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

// Where OpenGL GLSL's uniform blocks go (rhi::ShaderCompileOptions::openGlSource, and
// linkOpenGlBlocks): a set no script uses, remapped to set 0 with the other bindings.
constexpr uint32_t kDefaultUniformSet = 15;
// Where OpenGL GLSL's sampler uniforms go, one binding per sampler name (linkOpenGlBlocks).
constexpr uint32_t kOpenGlSamplerSet = 14;
// Where the atomic counters of OpenGL binding N go: binding N of this set (linkOpenGlBlocks).
constexpr uint32_t kAtomicCounterSet = 13;
const char* kAtomicCounterBlockPrefix = "gl_AtomicCounterBlock_";
const char* kDefaultUniformBlock = "gl_DefaultUniformBlock";

// Its input is named as piglit's passthrough names it, so [vertex data] columns find it by name.
const char* kPassthroughVs = R"(#version 450
layout(location = 0) in vec4 piglit_vertex;
void main() { gl_Position = piglit_vertex; }
)";

class Runner {
 public:
  Runner(const Script& s, rhi::Device& d, const RunOptions& o) : script_(s), dev_(d), opts_(o) {}
  ~Runner() {
    for (auto& [n, r] : res_)  // the platform layer's targets belong to it
      if (r.logical) r.texture = {}, r.readTexture = {};
    for (auto& [k, p] : pipelines_) dev_.destroy(p.handle);
    for (auto& [k, p] : computePipelines_) dev_.destroy(p);
    for (auto h : shaders_) dev_.destroy(h);
    for (auto h : samplers_) dev_.destroy(h);
    for (auto h : tempBuffers_) dev_.destroy(h);
    for (auto& [k, v] : mipViews_) dev_.destroy(v);
    for (auto& [n, r] : res_)  // views before their parents
      if (r.def && !r.def->viewOf.empty() && r.texture) dev_.destroy(r.texture), r.texture = {};
    for (auto& [n, r] : res_) {
      if (r.buffer) dev_.destroy(r.buffer);
      if (r.texture) dev_.destroy(r.texture);
    }
  }

  RunResult run() {
    RunResult result;
    try {
      setupPlatform();
      for (const Shader& sh : script_.shaders) compiled_[sh.name] = compile(sh);  // errors surface even if unused
      linkOpenGlVaryings();
      createResources();
      linkOpenGlBlocks();
      applyUniformInitializers();
      for (const Command& c : script_.commands) execute(c, result);
      bool failed = false;
      for (const auto& e : result.expects)
        if (!e.pass) failed = true;
      if (failed) {
        result.verdict = Verdict::Fail;
        for (const auto& e : result.expects)
          if (!e.pass) {
            result.reason = e.message;
            break;
          }
      }
    } catch (const Unsupported& u) {
      result.verdict = Verdict::Skip;
      result.reason = "unsupported: " + u.what;
    } catch (const Failure& f) {
      result.verdict = Verdict::Fail;
      result.reason = f.what;
      for (const auto& e : result.expects)
        if (!e.pass) {  // report the first failure first
          result.reason = e.message + "; then " + f.what;
          break;
        }
    }
    return result;
  }

 private:
  struct Resource {
    const Buffer* def = nullptr;
    rhi::BufferHandle buffer;
    rhi::TextureHandle texture;
    TexFormat format;
    uint32_t width = 0, height = 0, samples = 1;
    uint32_t depth = 1;  // DIM_3D images: slices
    std::optional<std::vector<uint8_t>> cpu;  // contents given by COPY to a buffer with no GPU object
    bool logical = false;         // a LOGICAL image: GpuTargets owns the textures
    rhi::TextureHandle readTexture;  // LOGICAL: what shaders sample (after RESOLVE)
  };
  struct GfxPipeline {
    rhi::PipelineHandle handle;
  };

  const Script& script_;
  rhi::Device& dev_;
  RunOptions opts_;
  std::map<std::string, Resource> res_;
  std::map<std::string, GfxPipeline> pipelines_;
  std::map<std::string, rhi::ComputePipelineHandle> computePipelines_;
  std::map<std::string, std::map<SetBinding, uint32_t>> bindingMaps_;
  std::map<std::string, std::vector<rhi::ResourceBinding>> defaults_;  // by pipeline: see defaultBindings()
  rhi::BufferHandle zeroBuffer_;
  std::vector<rhi::ShaderHandle> shaders_;
  std::vector<rhi::SamplerHandle> samplers_;
  std::vector<rhi::BufferHandle> tempBuffers_;
  std::map<std::string, rhi::SamplerHandle> samplerByName_;
  std::map<std::pair<std::string, uint32_t>, rhi::TextureHandle> mipViews_;  // sampledTexture()
  std::map<std::string, std::vector<uint32_t>> compiled_;  // SPIR-V per shader name, before remapping
  struct ClearState {
    std::array<float, 4> color{0, 0, 0, 0};
    float depth = 1.0f;
    uint8_t stencil = 0;
  };
  std::map<std::string, ClearState> clear_;
  platforms::PlatformId platform_ = platforms::PlatformId::Reference;
  platforms::PlatformParams params_;
  std::unique_ptr<platforms::GpuTargets> targets_;
  rhi::ShaderCompileOptions compileOptions_;

  // The platform layer: parameters, the plan of every LOGICAL image, the shader defines and
  // include folders that let a script's GLSL `#include "platform.glsl"` (and any project shader).
  void setupPlatform() {
    auto id = platforms::platformFromName(opts_.platform);
    if (!id) throw Failure{"unknown platform '" + opts_.platform + "'"};
    platform_ = *id;
    for (const auto& [name, value] : script_.platformParams) {
      std::string why;
      if (!platforms::setParameter(params_, name, value, &why)) throw Failure{"SET PLATFORM_PARAM " + name + ": " + why};
    }
    std::vector<platforms::LogicalTarget> logical;
    uint32_t width = 0, height = 0;
    for (const Buffer& b : script_.buffers) {
      if (b.logical.empty()) continue;
      platforms::LogicalTarget t;
      t.name = b.name;
      for (auto f : {platforms::LogicalFormat::Rgba8Unorm, platforms::LogicalFormat::Rg16Unorm,
                     platforms::LogicalFormat::Rgba16Hdr, platforms::LogicalFormat::Depth24Stencil8})
        if (platforms::logicalFormatName(f) == b.logical) t.format = f;
      uint32_t w = b.width, h = b.height;
      for (const Pipeline& p : script_.pipelines)
        for (const Bind& bb : p.binds)
          if (bb.buffer == b.name && (bb.kind == BindKind::Color || bb.kind == BindKind::DepthStencil)) {
            if (t.pass.empty()) t.pass = p.name;
            if (!b.width) w = p.fbWidth, h = p.fbHeight;
          }
      if (!w || !h) throw Failure{"LOGICAL image '" + b.name + "' has no size (give WIDTH and HEIGHT or bind it as an attachment)"};
      if (width && (w != width || h != height))
        throw Unsupported{"LOGICAL images of different sizes (the platform plans one size per frame)"};
      width = w, height = h;
      logical.push_back(t);
    }
    platforms::TargetPlan plan = platforms::planTargets(platform_, logical, std::max(width, 1u), std::max(height, 1u), params_);
    compileOptions_ = platforms::platformShaderOptions(plan);
    compileOptions_.includeDirs.push_back(rhi::shaderDirectory());
    if (logical.empty()) return;
    targets_ = std::make_unique<platforms::GpuTargets>(dev_, plan);
    for (const platforms::PhysicalTarget& t : plan.targets) {
      Resource r;
      r.def = script_.findBuffer(t.logical.name);
      r.logical = true;
      r.texture = targets_->attachment(t.logical.name);
      r.readTexture = targets_->readTexture(t.logical.name);
      r.format.format = t.attachmentFormat;
      r.width = width, r.height = height;
      if (!r.texture || !r.readTexture) throw Failure{"cannot create the " + opts_.platform + " targets of LOGICAL image '" + t.logical.name + "'"};
      res_[t.logical.name] = r;
    }
  }

  // --- resources ---
  void createResources() {
    // Which buffers live in textures: those bound as attachments or images anywhere.
    std::map<std::string, std::pair<uint32_t, uint32_t>> textureSize;
    std::set<std::string> isTexture;
    for (const Pipeline& p : script_.pipelines)
      for (const Bind& b : p.binds) {
        bool attachment = b.kind == BindKind::Color || b.kind == BindKind::DepthStencil || b.kind == BindKind::Resolve;
        if (attachment || b.kind == BindKind::CombinedImageSampler || b.kind == BindKind::SampledImage ||
            b.kind == BindKind::StorageImage)
          isTexture.insert(b.buffer);
        // An attachment at BASE_MIP_LEVEL m is the framebuffer's size at that level.
        if (attachment && !textureSize.count(b.buffer))
          textureSize[b.buffer] = {p.fbWidth << b.baseMipLevel, p.fbHeight << b.baseMipLevel};
      }
    for (const Buffer& b : script_.buffers) {
      if (!b.viewOf.empty()) isTexture.insert(b.viewOf);
      if (b.textureUnit >= 0) isTexture.insert(b.name);
    }
    for (const Buffer& b : script_.buffers) {
      if (!b.logical.empty()) continue;  // created by setupPlatform()
      Resource r;
      r.def = &b;
      if (!b.viewOf.empty()) {
        const Resource& parent = res_.at(b.viewOf);
        r.format = textureFormat(b.type);
        r.width = parent.width, r.height = parent.height, r.samples = parent.samples, r.depth = parent.depth;
        rhi::TextureViewDesc vd;
        vd.parent = parent.texture;
        vd.format = r.format.format;
        vd.label = b.name;
        r.texture = dev_.createTextureView(vd);
        if (!r.texture) throw Failure{"cannot create view '" + b.name + "' of '" + b.viewOf + "'"};
        res_[b.name] = r;
        continue;
      }
      if (isTexture.count(b.name)) {
        r.format = textureFormat(b.type);
        if (b.isImage && b.dim == "DIM_2D" && textureSize.count(b.name)) {
          // As in Amber, an IMAGE bound as an attachment takes its pipeline's framebuffer size.
          r.width = textureSize[b.name].first, r.height = textureSize[b.name].second, r.samples = b.samples;
        } else if (b.isImage || b.width > 0) {  // IMAGE, or a BUFFER loaded from a PNG
          r.width = b.width, r.height = b.height, r.samples = b.samples, r.depth = b.depth;
        } else if (textureSize.count(b.name)) {
          r.width = textureSize[b.name].first, r.height = textureSize[b.name].second;
        } else {
          throw Unsupported{"BUFFER '" + b.name + "' sampled as an image without being rendered to"};
        }
        rhi::TextureDesc td;
        td.format = r.format.format;
        td.width = r.width, td.height = r.height, td.samples = r.samples;
        if (b.dim == "DIM_1D") td.type = rhi::TextureType::Tex1D;
        if (b.dim == "DIM_3D") td.type = rhi::TextureType::Tex3D, td.depth = r.depth;
        if (b.dim == "DIM_3D" && b.mipLevels > 1) throw Unsupported{"IMAGE DIM_3D with MIP_LEVELS"};
        td.mipLevels = b.mipLevels;
        td.usage = rhi::TextureUsage_Sampled | rhi::TextureUsage_RenderTarget;
        for (const Pipeline& p : script_.pipelines)
          for (const Bind& bb : p.binds)
            if (bb.buffer == b.name && bb.kind == BindKind::StorageImage) td.usage |= rhi::TextureUsage_Storage;
        if (r.samples > 1 && (td.usage & rhi::TextureUsage_Storage) && !dev_.info().caps.storageMultisample)
          throw Unsupported{"IMAGE '" + b.name + "' of " + std::to_string(r.samples) + " samples as a storage image (" +
                            dev_.info().renderer + " has no multisample storage images)"};
        td.label = b.name;
        std::vector<uint8_t> init;
        const rhi::FormatInfo& fi = rhi::formatInfo(td.format);
        size_t texels = size_t(r.width) * r.height * r.depth;
        if (rhi::isDepthFormat(td.format)) {
          if (td.format == rhi::Format::D24S8) {
            init.assign(texels * 4, 0xFF);  // words 0xFFFFFF00: depth 1.0, stencil 0
            for (size_t i = 0; i < texels; ++i) init[i * 4] = 0;
          } else if (td.format == rhi::Format::D16) {
            init.assign(texels * 2, 0xFF);  // 0xFFFF: depth 1.0
          } else {
            std::vector<float> ones(texels, 1.0f);
            init.assign(reinterpret_cast<uint8_t*>(ones.data()), reinterpret_cast<uint8_t*>(ones.data()) + texels * 4);
          }
        } else if (b.sized && b.bytes.size() == texels * fi.bytesPerTexel) {
          init = toTextureBytes(r, b.bytes);
        } else {
          init.assign(texels * fi.bytesPerTexel, 0);
        }
        if (r.samples == 1) td.initialData = init.data();
        r.texture = dev_.createTexture(td);
        if (!r.texture) throw Failure{"cannot create image '" + b.name + "' (" + fi.name + " " + std::to_string(r.width) + "x" +
                                      std::to_string(r.height) + " x" + std::to_string(r.samples) + ", " +
                                      std::to_string(b.mipLevels) + " mips)"};
        // Initial data fills mip 0; the other levels start as the attachments do (zero, or
        // depth 1.0), not undefined.
        for (uint32_t mip = 1; mip < b.mipLevels && r.samples == 1; ++mip) {
          const size_t mipTexels = size_t(std::max(r.width >> mip, 1u)) * std::max(r.height >> mip, 1u);
          std::vector<uint8_t> level(init.begin(), init.begin() + static_cast<long>(mipTexels * fi.bytesPerTexel));
          if (!rhi::isDepthFormat(td.format)) std::fill(level.begin(), level.end(), 0);
          dev_.writeTexture(r.texture, 0, mip, level.data());
        }
      } else if (b.sized && !b.bytes.empty()) {
        rhi::BufferDesc bd;
        bd.size = b.bytes.size();
        bd.initialData = b.bytes.data();
        bd.label = b.name;
        r.buffer = dev_.createBuffer(bd);
        if (!r.buffer) throw Failure{"cannot create buffer '" + b.name + "'"};
      }
      res_[b.name] = r;
    }
    for (const Sampler& s : script_.samplers) {
      rhi::SamplerDesc sd;
      sd.magFilter = s.linearMag ? rhi::Filter::Linear : rhi::Filter::Nearest;
      sd.minFilter = s.linearMin ? rhi::Filter::Linear : rhi::Filter::Nearest;
      sd.addressU = addressMode(s.addressMode[0]);
      sd.addressV = addressMode(s.addressMode[1]);
      sd.addressW = addressMode(s.addressMode[2]);
      sd.borderColor = borderColor(s.borderColor);
      // Amber's MIPMAP_MODE (default nearest) selects among the bound view's levels. MAX_LOD is
      // not an RHI sampler field: a script whose sampler would clamp below the levels it samples
      // is reported unsupported (checkMaxLod).
      sd.mipFilter = s.mipmapMode == "linear" ? rhi::MipFilter::Linear : rhi::MipFilter::Nearest;
      sd.label = s.name;
      rhi::SamplerHandle h = dev_.createSampler(sd);
      if (!h) throw Failure{"cannot create sampler '" + s.name + "'"};
      samplers_.push_back(h);
      samplerByName_[s.name] = h;
    }
  }

  std::vector<uint8_t> toTextureBytes(const Resource& r, std::vector<uint8_t> bytes) {
    if (r.format.bgra)
      for (size_t i = 0; i + 3 < bytes.size(); i += 4) std::swap(bytes[i], bytes[i + 2]);
    return bytes;
  }

  // Current contents of a script buffer in the script's own layout.
  std::vector<uint8_t> contents(const std::string& name) {
    Resource& r = res_.at(name);
    if (r.logical)
      throw Failure{"LOGICAL image '" + name + "' has platform-specific texels: read it in a shader or EXPECT " + name + " MEMORY BYTES"};
    if (r.texture) {
      if (r.samples > 1) throw Failure{"'" + name + "' is multisampled and cannot be read (bind a resolve target)"};
      rhi::ReadbackRegion region;
      if (rhi::isDepthFormat(r.format.format)) region.aspect = rhi::TextureAspect::Depth;
      std::vector<uint8_t> bytes;
      for (region.layer = 0; region.layer < r.depth; ++region.layer) {  // a 3D image slice by slice
        std::vector<uint8_t> slice = dev_.readTexture(r.texture, region);
        bytes.insert(bytes.end(), slice.begin(), slice.end());
      }
      return toTextureBytes(r, std::move(bytes));
    }
    if (r.buffer) return dev_.readBuffer(r.buffer, 0, r.def->bytes.size());
    if (r.cpu) return *r.cpu;
    return r.def->bytes;
  }

  // COPY a TO b: whole contents, in the script's layout.
  void copy(const Command& c) {
    Resource& src = res_.at(c.buffer);
    Resource& dst = res_.at(c.other);
    std::vector<uint8_t> bytes = contents(c.buffer);
    if (dst.texture) {
      if (dst.width != src.width || dst.height != src.height || dst.format.format != src.format.format)
        throw Unsupported{"COPY between images of different size or format"};
      if (dst.depth > 1) throw Unsupported{"COPY into a DIM_3D image"};
      dev_.writeTexture(dst.texture, 0, 0, toTextureBytes(dst, bytes).data());
    } else if (dst.buffer) {
      size_t n = std::min(bytes.size(), dst.def->bytes.size());
      dev_.writeBuffer(dst.buffer, 0, bytes.data(), n);
    } else {
      dst.cpu = bytes;
      dst.width = src.width, dst.height = src.height;
    }
  }

  rhi::BufferHandle gpuBuffer(const std::string& name, const Location& loc) {
    Resource& r = res_.at(name);
    if (!r.buffer) throw Failure{lineOf(loc) + ": buffer '" + name + "' has no contents (give SIZE or DATA)"};
    return r.buffer;
  }

  // --- shaders and pipelines ---
  std::map<SetBinding, uint32_t>& bindingMap(const Pipeline& p, const std::vector<std::vector<uint32_t>>& modules) {
    auto it = bindingMaps_.find(p.name);
    if (it != bindingMaps_.end()) return it->second;
    std::set<SetBinding> all;
    for (const auto& m : modules)
      for (auto sb : spirvBindings(m)) all.insert(sb);
    for (const Bind& b : bindsOf(p))
      if (b.kind == BindKind::Storage || b.kind == BindKind::Uniform || b.kind == BindKind::CombinedImageSampler ||
          b.kind == BindKind::StorageImage || b.kind == BindKind::SampledImage || b.kind == BindKind::Sampler ||
          b.kind == BindKind::UniformTexelBuffer || b.kind == BindKind::StorageTexelBuffer)
        all.insert({b.set, b.binding});
    std::map<SetBinding, uint32_t> map;
    bool identity = true;
    for (auto sb : all) identity &= sb.first == 0 && sb.second < rhi::kMaxBindings;
    uint32_t next = 0;
    for (auto sb : all) map[sb] = identity ? sb.second : next++;
    if (next > rhi::kMaxBindings) throw Unsupported{"more than " + std::to_string(rhi::kMaxBindings) + " bindings"};
    return bindingMaps_[p.name] = map;
  }

  std::vector<uint32_t> compile(const Shader& s) {
    if (s.format == "SPIRV-BIN") {
      if (s.source.size() % 4 != 0 || s.source.size() < 20) throw Failure{"shader '" + s.name + "': SPIR-V binary of " + std::to_string(s.source.size()) + " bytes"};
      std::vector<uint32_t> words(s.source.size() / 4);
      std::memcpy(words.data(), s.source.data(), s.source.size());
      return words;
    }
    if (s.format == "SPIRV-ASM") {
      rhi::CompiledShader c = rhi::assembleSpirv(s.source, script_.file, s.sourceLine, s.spirvMinor);
      if (!c.ok()) throw Failure{"shader '" + s.name + "' does not assemble: " + oneLine(c.error)};
      return c.spirv;
    }
    std::string src = s.passthrough ? kPassthroughVs : s.source;
    rhi::ShaderCompileOptions options = compileOptions_;
    std::string declarations;
    if (s.openGl && !s.passthrough) {
      OpenGlGlsl gl = prepareOpenGlGlsl(src, s.stage, s.glslVersion);
      src = gl.source;
      declarations = gl.declarations;
      options.openGlSource = true;
      options.defaultUniformSet = kDefaultUniformSet;
      options.defaultUniformBinding = static_cast<uint32_t>(s.stage);
    }
    if (!s.passthrough) {
      // Keep the compiler's line numbers those of the script: a #line after #version.
      size_t v = src.find("#version");
      if (v == std::string::npos) {
        src = "#version 450\n#line " + std::to_string(s.sourceLine) + "\n" + src;
      } else {
        // After the #version line, and after any #extension lines, which must precede declarations.
        size_t eol = src.find('\n', v);
        for (size_t at = eol; !declarations.empty() && at != std::string::npos && at + 1 < src.size(); at = src.find('\n', at + 1)) {
          size_t first = src.find_first_not_of(" \t", at + 1);
          if (first != std::string::npos && src.compare(first, 10, "#extension") == 0) eol = src.find('\n', first);
        }
        int linesBefore = static_cast<int>(std::count(src.begin(), src.begin() + static_cast<long>(eol), '\n'));
        if (s.openGl && s.source.find("#version") == std::string::npos) --linesBefore;  // the #version was added
        if (eol != std::string::npos)
          src.insert(eol + 1, declarations + "#line " + std::to_string(s.sourceLine + linesBefore + 1) + "\n");
      }
    }
    rhi::ShaderStage st = rhiStage(s.stage);
    rhi::CompiledShader c = rhi::compileGlslSource(src, script_.file, st, options);
    if (!c.ok()) {
      // An extension the compiler does not know is a limit of this build's glslang, not a broken shader.
      static const std::regex kUnknownExtension(R"(error: '#extension' : extension not supported: (\w+))");
      std::smatch m;
      if (std::regex_search(c.error, m, kUnknownExtension))
        throw Unsupported{"GLSL extension " + m[1].str() + " (unknown to this glslang)"};
      if (s.openGl)
        if (std::optional<std::string> limitation = glslangLimitation(s.source, s.sourceLine, c.error)) throw Unsupported{*limitation};
      // OpenGL GLSL that SPIR-V for Vulkan cannot hold: samplers in structs or constructors, which
      // glslang rejects or turns into a module the validator refuses.
      static const std::regex kInvalidModule(R"(generated SPIR-V is invalid: \[([\w-]+)\])");
      if (s.openGl && std::regex_search(c.error, m, kInvalidModule))
        throw Unsupported{"OpenGL GLSL without a Vulkan SPIR-V form (glslang's module breaks " + m[1].str() + ")"};
      if (s.openGl && c.error.find("'sampler/image' : cannot construct this type") != std::string::npos)
        throw Unsupported{"OpenGL GLSL without a Vulkan SPIR-V form (a sampler in a constructed struct)"};
      throw Failure{"shader '" + s.name + "' does not compile: " + oneLine(c.error)};
    }
    // glViewport sets every viewport, so an OpenGL shader may pick any of them; the RHI has one.
    if (s.openGl && s.stage != Stage::Fragment && outputsBuiltIn(c.spirv, kBuiltInViewportIndex))
      throw Unsupported{"gl_ViewportIndex written by the " + s.name + " shader (OpenGL's viewport array; the RHI has one viewport)"};
    return c.spirv;
  }

  static std::string oneLine(std::string e) {
    while (!e.empty() && e.back() == '\n') e.pop_back();
    for (char& ch : e)
      if (ch == '\n') ch = ' ';
    return e;
  }

  // OpenGL GLSL's uniform blocks, linked as OpenGL links them: by block name across the stages
  // (the loose uniforms of each stage are a block of their own), each in a buffer the runner
  // creates and `uniform` commands fill by member name. Each block moves to a binding of its own
  // in kDefaultUniformSet, so that blocks of different stages never meet at one binding.
  struct OpenGlBlock {
    std::string resource;      // res_ key
    std::string typeName;      // the block's name (ParityDefaultUniforms_SHADER for loose uniforms)
    bool loose = false;        // the loose uniforms of one shader
    std::string layoutShader;  // a shader whose module declares it (member offsets)
    uint32_t binding = 0;      // in kDefaultUniformSet
    std::optional<uint32_t> element;  // of an array of blocks (one OpenGlBlock each, keyed "Block[e]")
    std::vector<uint8_t> bytes;
  };
  std::map<std::string, OpenGlBlock> openGlBlocks_;                 // by block name
  std::map<std::string, std::vector<std::string>> openGlBlocksOf_;  // shader -> its blocks' keys
  // Sampler uniforms: each name at a binding of kOpenGlSamplerSet, reading the texture unit a
  // `uniform int NAME unit` command chose (OpenGL's default: unit 0).
  struct OpenGlSampler {
    uint32_t binding = 0, element = 0;
  };
  std::map<std::string, OpenGlSampler> openGlSamplers_;               // name ("s", "s[2]") -> where
  std::map<std::string, std::vector<std::string>> openGlSamplersOf_;  // shader -> its sampler names
  std::map<std::string, int64_t> samplerUnit_;                        // name -> texture unit
  // Atomic counters: the OpenGL atomic-counter buffer bindings each shader uses.
  std::map<std::string, std::vector<uint32_t>> openGlAtomicsOf_;

  // OpenGL matches one stage's outputs with the next stage's inputs by name (by location where both
  // give one); glslang's automatic locations number each stage's own declarations, which agree
  // only where both stages declare the same variables in the same order. Each input matched by
  // name takes the location of its producer's output.
  void linkOpenGlVaryings() {
    static const Stage kOrder[] = {Stage::Vertex, Stage::TessControl, Stage::TessEvaluation, Stage::Geometry, Stage::Fragment};
    const Shader* producer = nullptr;
    for (Stage stage : kOrder) {
      const Shader* consumer = nullptr;
      for (const Shader& s : script_.shaders)
        if (s.stage == stage) consumer = &s;
      if (!consumer) continue;
      if (producer && consumer->openGl && (producer->openGl || producer->passthrough)) {
        const std::set<std::string> locatedOutputs = producer->passthrough ? std::set<std::string>{} : explicitlyLocated(producer->source, true);
        const std::set<std::string> locatedInputs = explicitlyLocated(consumer->source, false);
        std::map<std::pair<std::string, bool>, InterfaceVariable> outputs;  // (name, patch)
        for (const InterfaceVariable& v : interfaceVariables(compiled_.at(producer->name)))
          if (v.output) outputs[{v.name, v.patch}] = v;
        std::vector<uint32_t>& spirv = compiled_.at(consumer->name);
        for (const InterfaceVariable& v : interfaceVariables(spirv)) {
          auto out = outputs.find({v.name, v.patch});
          if (v.output || out == outputs.end() || (locatedInputs.count(v.name) && locatedOutputs.count(v.name))) continue;
          spirv[v.locationWord] = out->second.location;
          if (v.componentWord) spirv[v.componentWord] = out->second.component;
        }
      }
      producer = consumer;
    }
  }

  void linkOpenGlBlocks() {
    for (const Shader& s : script_.shaders) {
      if (!s.openGl) continue;
      std::vector<uint32_t>& spirv = compiled_.at(s.name);
      // glslang's relaxed rules gather the atomic counters of OpenGL binding N into the storage
      // block gl_AtomicCounterBlock_N; it moves to binding N of kAtomicCounterSet (renamed: GLSL
      // reserves gl_ names, and the GL backend runs the module as GLSL).
      for (const UniformBlockVariable& v : storageBlocks(spirv)) {
        if (!v.setWord || !v.bindingWord || v.typeName.rfind(kAtomicCounterBlockPrefix, 0) != 0) continue;
        const uint32_t binding = static_cast<uint32_t>(std::stoul(v.typeName.substr(std::strlen(kAtomicCounterBlockPrefix))));
        renameStruct(spirv, v.typeName, "ParityAtomicCounters_" + std::to_string(binding));
        spirv[v.setWord] = kAtomicCounterSet;
        spirv[v.bindingWord] = binding;
        openGlAtomicsOf_[s.name].push_back(binding);
      }
      // Each stage's loose uniforms are a block of their own: named apart, or OpenGL would link
      // the stages' different blocks as one (the GL backend runs the module as GLSL).
      const std::string defaultBlock = "ParityDefaultUniforms_" + s.name;
      renameStruct(spirv, kDefaultUniformBlock, defaultBlock);
      for (const UniformBlockVariable& v : uniformBlocks(spirv)) {
        if (!v.setWord || !v.bindingWord) continue;
        const uint32_t binding = static_cast<uint32_t>(openGlBlocks_.size());  // unless the block is known
        for (uint32_t e = 0; e < v.elements; ++e) {
          std::string key = v.elements > 1 ? v.typeName + "[" + std::to_string(e) + "]" : v.typeName;
          OpenGlBlock& b = openGlBlocks_[key];
          if (b.resource.empty()) {
            b.resource = "uniform block " + key;
            b.typeName = v.typeName;
            b.loose = v.typeName == defaultBlock;
            b.layoutShader = s.name;
            b.binding = e == 0 ? binding : openGlBlocks_.at(v.typeName + "[0]").binding;
            if (v.elements > 1) b.element = e;
          }
          b.bytes.resize(std::max<size_t>({b.bytes.size(), v.size, 4}), 0);
          spirv[v.setWord] = kDefaultUniformSet;
          spirv[v.bindingWord] = b.binding;
          openGlBlocksOf_[s.name].push_back(key);
        }
      }
      for (const SamplerVariable& v : samplerVariables(spirv)) {
        if (!v.setWord || !v.bindingWord) continue;
        const uint32_t binding = static_cast<uint32_t>(openGlSamplers_.size());  // unless the sampler is known
        for (uint32_t e = 0; e < v.elements; ++e) {
          std::string name = v.elements > 1 ? v.name + "[" + std::to_string(e) + "]" : v.name;
          auto it = openGlSamplers_.emplace(name, OpenGlSampler{binding, e}).first;
          spirv[v.setWord] = kOpenGlSamplerSet;
          spirv[v.bindingWord] = it->second.binding;
          openGlSamplersOf_[s.name].push_back(name);
        }
      }
    }
    for (auto& [key, b] : openGlBlocks_) {
      rhi::BufferDesc bd;
      bd.size = b.bytes.size();
      bd.initialData = b.bytes.data();
      bd.label = b.resource;
      Resource r;
      r.buffer = dev_.createBuffer(bd);
      if (!r.buffer) throw Failure{"cannot create the buffer of " + b.resource};
      res_[b.resource] = r;
    }
  }

  // glslang drops the initialisers of block members (`uniform vec4 c = vec4(1.0);`): the literal
  // ones are written into the blocks here.
  void applyUniformInitializers() {
    for (const Shader& s : script_.shaders) {
      if (!s.openGl || !openGlBlocksOf_.count(s.name)) continue;
      for (const UniformInitialValue& v : uniformInitializers(s.source)) {
        Command c;
        c.loc = {s.sourceLine, 1};
        c.uniform = v.path;
        c.values = v.values;
        setUniform(c);
      }
    }
  }

  // The pipeline's binds and the uniform blocks of its OpenGL-GLSL shaders.
  std::vector<Bind> bindsOf(const Pipeline& p) const {
    std::vector<Bind> all = p.binds;
    std::set<std::string> added;
    auto listed = [](const auto& byShader, const std::string& shader) {
      auto it = byShader.find(shader);
      return it == byShader.end() ? typename std::decay_t<decltype(byShader)>::mapped_type{} : it->second;
    };
    for (const std::string& n : p.shaders) {
      for (const std::string& key : listed(openGlBlocksOf_, n)) {
        if (!added.insert(key).second) continue;
        const OpenGlBlock& block = openGlBlocks_.at(key);
        Bind b;
        b.kind = BindKind::Uniform;
        b.buffer = block.resource;
        b.set = kDefaultUniformSet, b.binding = block.binding;
        b.arrayElement = block.element.value_or(0);
        all.push_back(b);
      }
      for (uint32_t binding : listed(openGlAtomicsOf_, n)) {
        if (!added.insert("atomic counters " + std::to_string(binding)).second) continue;
        Bind b;
        b.kind = BindKind::Storage;
        b.set = kAtomicCounterSet, b.binding = binding;
        for (const Buffer& buffer : script_.buffers)
          if (buffer.atomicCounterBinding == static_cast<int>(binding)) b.buffer = buffer.name;
        if (b.buffer.empty())
          throw Failure{"a shader uses atomic counters at binding " + std::to_string(binding) + ", which no `atomic counters` command made"};
        all.push_back(b);
      }
      for (const std::string& name : listed(openGlSamplersOf_, n)) {
        if (!added.insert("sampler " + name).second) continue;
        auto unit = samplerUnit_.find(name);
        const int64_t u = unit == samplerUnit_.end() ? 0 : unit->second;
        Bind b;
        b.kind = BindKind::CombinedImageSampler;
        b.set = kOpenGlSamplerSet, b.binding = openGlSamplers_.at(name).binding;
        b.arrayElement = openGlSamplers_.at(name).element;
        for (const Buffer& image : script_.buffers)
          if (image.textureUnit == u) b.buffer = image.name;
        for (const Sampler& sampler : script_.samplers)
          if (sampler.textureUnit == u) b.sampler = sampler.name;
        if (b.buffer.empty())
          throw Failure{"sampler '" + name + "' reads texture unit " + std::to_string(u) + ", which no texture command filled"};
        all.push_back(b);
      }
    }
    return all;
  }

  // `uniform TYPE NAME values`: written wherever a block holds NAME (a member of a block may be
  // named "Block.member"); a name no block holds was optimised away, as OpenGL drivers do.
  void setUniform(const Command& c) {
    // A sampler uniform holds its texture unit; an array's name alone is its element 0.
    for (const std::string& name : {c.uniform, c.uniform + "[0]"})
      if (openGlSamplers_.count(name)) {
        samplerUnit_[name] = c.values.empty() ? 0 : c.values[0].i;
        return;
      }
    for (auto& [key, b] : openGlBlocks_) {
      if (b.element && *b.element != c.arrayElement) continue;  // piglit's `ubo array index`
      std::string path = c.uniform;
      if (!b.loose && path.rfind(b.typeName + ".", 0) == 0) path = path.substr(b.typeName.size() + 1);
      auto slot = findUniform(compiled_.at(b.layoutShader), b.typeName, path);
      if (!slot) continue;
      const uint32_t perElement = slot->rows * slot->columns;
      if (c.values.size() > size_t(perElement) * slot->elements)
        throw Failure{lineOf(c.loc) + ": " + std::to_string(c.values.size()) + " values for uniform '" + c.uniform + "'"};
      const uint32_t scalarBytes = scalarSize(slot->scalar);
      for (size_t i = 0; i < c.values.size(); ++i) {
        uint32_t element = static_cast<uint32_t>(i / perElement), k = static_cast<uint32_t>(i % perElement);
        uint32_t column = k / slot->rows, row = k % slot->rows;
        size_t at = slot->offset + size_t(element) * slot->arrayStride + size_t(column) * slot->matrixStride + size_t(row) * scalarBytes;
        if (at + scalarBytes > b.bytes.size()) throw Failure{lineOf(c.loc) + ": uniform '" + c.uniform + "' lies outside its block"};
        storeValue(b.bytes, at, slot->scalar, c.values[i]);
      }
      dev_.writeBuffer(res_.at(b.resource).buffer, 0, b.bytes.data(), b.bytes.size());
    }
  }

  // A SPIR-V extension that Vulkan 1.3 has not made core needs the device extension that brings
  // it: SPV_<VENDOR>_<name> comes with VK_<VENDOR>_<name> or VK_<VENDOR>_shader_<name>.
  void requireSpirvExtension(const std::string& extension) {
    static const std::set<std::string> kCore = {
        "SPV_KHR_shader_draw_parameters", "SPV_KHR_16bit_storage", "SPV_KHR_8bit_storage", "SPV_KHR_variable_pointers",
        "SPV_KHR_storage_buffer_storage_class", "SPV_KHR_device_group", "SPV_KHR_multiview", "SPV_KHR_float_controls",
        "SPV_KHR_vulkan_memory_model", "SPV_KHR_physical_storage_buffer", "SPV_EXT_physical_storage_buffer",
        "SPV_KHR_terminate_invocation", "SPV_EXT_demote_to_helper_invocation", "SPV_KHR_integer_dot_product",
        "SPV_KHR_non_semantic_info", "SPV_EXT_descriptor_indexing", "SPV_EXT_shader_viewport_index_layer",
        "SPV_KHR_no_integer_wrap_decoration"};
    if (kCore.count(extension) || extension.rfind("SPV_", 0) != 0) return;
    size_t vendorEnd = extension.find('_', 4);
    if (vendorEnd == std::string::npos) return;
    const std::string vendor = extension.substr(4, vendorEnd - 4), name = extension.substr(vendorEnd + 1);
    const std::vector<std::string>& offered = dev_.info().extensions;
    for (const std::string& candidate : {"VK_" + vendor + "_" + name, "VK_" + vendor + "_shader_" + name})
      if (std::find(offered.begin(), offered.end(), candidate) != offered.end()) return;
    throw Unsupported{"SPIR-V extension " + extension + " (no VK_" + vendor + "_[shader_]" + name + " on " + dev_.info().backend + " " +
                      dev_.info().renderer + ")"};
  }

  std::vector<rhi::ShaderHandle> makeShaders(const Pipeline& p) {
    std::vector<std::vector<uint32_t>> modules;
    std::vector<const Shader*> defs;
    for (const std::string& n : p.shaders) {
      const Shader* s = script_.findShader(n);
      defs.push_back(s);
      modules.push_back(compiled_.at(n));
      auto passes = p.optimizations.find(n);
      if (passes != p.optimizations.end()) optimizeSpirv(modules.back(), passes->second, n);
    }
    for (const auto& m : modules) {
      for (const std::string& extension : spirvExtensions(m)) requireSpirvExtension(extension);
      if (usesSubgroupOperations(m) && !dev_.info().caps.subgroups)
        throw Unsupported{"subgroup operations (no GL_KHR_shader_subgroup on " + dev_.info().renderer + ")"};
    }
    for (const auto& m : modules)
      for (const DescriptorArray& a : descriptorArrays(m)) {
        if (a.nested || a.elements == 0 || a.elements > rhi::kMaxArrayElements)
          throw Unsupported{"descriptor array '" + a.name + "' " +
                            (a.nested ? std::string("of arrays") : a.elements == 0 ? std::string("without a constant size")
                                                                                   : "of " + std::to_string(a.elements) + " elements") +
                            " (the RHI binds one-dimensional arrays of 1.." + std::to_string(rhi::kMaxArrayElements) + ")"};
        if (a.samplers && !dev_.info().caps.separateSamplerArrays)
          throw Unsupported{"array of separate samplers '" + a.name + "' (no such GLSL on " + dev_.info().backend + ")"};
      }
    auto& map = bindingMap(p, modules);
    std::map<uint32_t, std::set<uint32_t>> boundElements;  // RHI binding -> elements the script binds
    for (const Bind& b : bindsOf(p))
      if (b.kind != BindKind::Color && b.kind != BindKind::DepthStencil && b.kind != BindKind::Resolve &&
          b.kind != BindKind::PushConstant && map.count({b.set, b.binding}))
        boundElements[map.at({b.set, b.binding})].insert(b.arrayElement);
    std::vector<rhi::ShaderHandle> out;
    for (size_t i = 0; i < defs.size(); ++i) {
      remapSpirv(modules[i], map);
      defaultBindings(p, modules[i], rhiStage(defs[i]->stage), boundElements);
      auto spec = p.specializations.find(defs[i]->name);
      if (spec != p.specializations.end()) specializeSpirv(modules[i], spec->second, defs[i]->name);
      rhi::ShaderDesc sd;
      sd.stage = rhiStage(defs[i]->stage);
      sd.spirv = modules[i];
      auto ep = p.entryPoints.find(defs[i]->name);
      if (ep != p.entryPoints.end()) sd.entryPoint = ep->second;
      sd.label = defs[i]->name;
      rhi::ShaderHandle h = dev_.createShader(sd);
      if (!h) throw Failure{"cannot create shader '" + defs[i]->name + "'"};
      shaders_.push_back(h);
      out.push_back(h);
    }
    return out;
  }

  // A binding a shader declares and the script leaves unbound is left unwritten by Amber: a shader
  // that runs does not read it. The RHI needs every binding, so it gets a zeroed resource of its
  // kind (pipeline defaults_, bound before the script's binds). An array the script binds only
  // some elements of is a SKIP: what the others read is the peer runner's accident.
  void defaultBindings(const Pipeline& p, const std::vector<uint32_t>& spirv, rhi::ShaderStage stage,
                       const std::map<uint32_t, std::set<uint32_t>>& boundElements) {
    rhi::ShaderReflection reflection;
    std::string error;
    if (!rhi::reflectSpirv(spirv, stage, &reflection, &error)) return;  // createShader reports it
    for (const rhi::ShaderResource& r : reflection.resources) {
      auto bound = boundElements.find(r.binding);
      if (bound != boundElements.end()) {
        for (uint32_t e = 0; e < r.arraySize; ++e)
          if (!bound->second.count(e))
            throw Unsupported{"pipeline '" + p.name + "' binds elements of descriptor array '" + r.name + "' of " +
                              std::to_string(r.arraySize) + " but not element " + std::to_string(e)};
        continue;
      }
      for (uint32_t e = 0; e < r.arraySize; ++e) {
        rhi::ResourceBinding d;
        d.binding = r.binding;
        d.arrayElement = e;
        d.kind = r.kind;
        switch (r.kind) {
          case rhi::BindingKind::UniformBuffer:
          case rhi::BindingKind::StorageBuffer:
            d.buffer = zeroBuffer();
            break;
          case rhi::BindingKind::UniformTexelBuffer:
          case rhi::BindingKind::StorageTexelBuffer:
            d.buffer = zeroBuffer();
            d.texelFormat = r.integer ? rhi::Format::R32_UINT : rhi::Format::R32F;
            break;
          case rhi::BindingKind::SeparateSampler:
            break;  // the null sampler: the RHI's default
          default:
            throw Unsupported{"pipeline '" + p.name + "' binds nothing at the texture '" + r.name +
                              "' a shader declares (the runner's zeroed defaults are buffers and samplers)"};
        }
        auto& defaults = defaults_[p.name];
        if (std::none_of(defaults.begin(), defaults.end(), [&](const rhi::ResourceBinding& o) {
              return o.binding == d.binding && o.arrayElement == d.arrayElement;
            }))
          defaults.push_back(d);
      }
    }
  }

  rhi::BufferHandle zeroBuffer() {
    if (!zeroBuffer_) {
      std::vector<uint8_t> zeros(16384, 0);  // within every uniform buffer range limit
      zeroBuffer_ = tempBuffer(zeros.data(), zeros.size(), "unbound binding (zeroed)");
    }
    return zeroBuffer_;
  }

  struct VertexSetup {
    std::vector<std::pair<rhi::BufferHandle, uint32_t>> slots;  // buffer, offset
    rhi::PipelineDesc desc;
  };

  // Fills the vertex input of `desc` from the pipeline's VERTEX_DATA (or the generated
  // position-only buffer of DRAW_RECT/DRAW_GRID when `rectBuffer`).
  void vertexInput(const Pipeline& p, rhi::BufferHandle rectBuffer, rhi::PipelineDesc& desc,
                   std::vector<std::pair<rhi::BufferHandle, size_t>>& slots) {
    const Shader* vs = nullptr;
    for (const std::string& n : p.shaders)
      if (script_.findShader(n)->stage == Stage::Vertex) vs = script_.findShader(n);
    if (rectBuffer) {
      // piglit's `draw rect` feeds piglit_vertex and piglit_texcoord (0..1 over the rectangle),
      // wherever the compiler placed them; every other vertex shader reads location 0.
      uint32_t position = 0;
      std::optional<uint32_t> texcoord;
      if (vs && vs->openGl && !vs->passthrough) {
        const std::vector<uint32_t>& spirv = compiled_.at(vs->name);
        position = inputLocation(spirv, "piglit_vertex").value_or(inputLocation(spirv, "parity_Vertex").value_or(0));
        texcoord = inputLocation(compiled_.at(vs->name), "piglit_texcoord");
      }
      desc.attributeCount = texcoord ? 2 : 1;
      desc.attributes[0] = {position, rhi::VertexFormat::Float2, 0, 0};
      if (texcoord) desc.attributes[1] = {*texcoord, rhi::VertexFormat::Float2, 8, 0};
      desc.vertexBuffers[0] = {16, false};
      slots.push_back({rectBuffer, 0});
      return;
    }
    if (p.vertexData.size() > rhi::kMaxVertexBuffers) throw Unsupported{"more than 4 VERTEX_DATA buffers"};
    std::vector<VertexData> inputs;
    for (VertexData v : p.vertexData) {
      // Attributes by name (shader_test): the compiler's location; one the shader does not read is left out.
      if (!v.attribute.empty()) {
        std::optional<uint32_t> location = vs ? inputLocation(compiled_.at(vs->name), v.attribute) : std::nullopt;
        if (!location) continue;
        v.location = *location;
      }
      inputs.push_back(v);
    }
    for (size_t i = 0; i < inputs.size(); ++i) {
      const VertexData& v = inputs[i];
      const Buffer* b = script_.findBuffer(v.buffer);
      ElementType t = b->type;
      if (!v.format.empty()) {
        std::string why;
        if (!parseFormat(v.format, &t, &why)) throw Unsupported{"VERTEX_DATA FORMAT " + v.format};
      }
      rhi::VertexFormat vf;
      size_t n = t.layout.fields.size();
      Scalar s = t.layout.fields[0].scalar;
      Mode m = t.layout.fields[0].mode;
      if (s == Scalar::Float32 && n >= 1 && n <= 4) vf = static_cast<rhi::VertexFormat>(static_cast<int>(rhi::VertexFormat::Float) + n - 1);
      else if (s == Scalar::Uint8 && m == Mode::Unorm && n == 4 && t.layout.fields[0].channel == 'R') vf = rhi::VertexFormat::UByte4Norm;
      else if ((s == Scalar::Uint32 || s == Scalar::Int32) && n >= 1 && n <= 4 && integerComponents(t)) vf = integerVertexFormat(s, n);
      else if (n <= 4 && scalarSize(s) < 4 && integerComponents(t)) {
        // 8- and 16-bit integers (R8G8_UINT, int16 vertex data): widened to 32 bits on the CPU,
        // sign-extended where signed, as the fetch would; the shader reads the same values.
        const bool isSigned = s == Scalar::Int8 || s == Scalar::Int16;
        uint32_t stride = v.stride ? v.stride : t.layout.stride;
        std::vector<uint8_t> raw = contents(v.buffer);
        std::vector<int32_t> out;
        for (size_t at = v.offset; stride && at + t.layout.stride <= raw.size(); at += stride)
          for (const Field& f : t.layout.fields) out.push_back(static_cast<int32_t>(readScalar(raw.data() + at + f.offset, f.scalar)));
        if (out.empty()) throw Failure{lineOf(v.loc) + ": VERTEX_DATA '" + v.buffer + "' holds no vertex"};
        desc.attributes[i] = {v.location, integerVertexFormat(isSigned ? Scalar::Int32 : Scalar::Uint32, n), 0,
                              static_cast<uint32_t>(i)};
        desc.vertexBuffers[i] = {static_cast<uint32_t>(n * 4), v.perInstance};
        slots.push_back({tempBuffer(out.data(), out.size() * sizeof(int32_t), "widened vertices"), 0});
        continue;
      } else if (s == Scalar::Float64) throw Unsupported{"vertex attribute of 64-bit components (" + t.name + "; the RHI fetches 32-bit ones)"};
      else if (n <= 4 && (m == Mode::Unorm || m == Mode::Snorm || m == Mode::Float)) {
        // A format the RHI cannot fetch (R8G8_SNORM, R8_UNORM, half floats, ...): converted to
        // float components on the CPU, as the fetch would (snorm: max(v / 127, -1)).
        uint32_t stride = v.stride ? v.stride : t.layout.stride;
        std::vector<uint8_t> raw = contents(v.buffer);
        std::vector<float> out;
        for (size_t at = v.offset; stride && at + t.layout.stride <= raw.size(); at += stride)
          for (const Field& f : t.layout.fields) {
            double x = readScalar(raw.data() + at + f.offset, f.scalar);
            double bits = scalarSize(f.scalar) * 8.0;
            if (f.mode == Mode::Unorm) x /= std::pow(2.0, bits) - 1;
            if (f.mode == Mode::Snorm) x = std::max(-1.0, x / (std::pow(2.0, bits - 1) - 1));
            out.push_back(static_cast<float>(x));
          }
        if (out.empty()) throw Failure{lineOf(v.loc) + ": VERTEX_DATA '" + v.buffer + "' holds no vertex"};
        desc.attributes[i] = {v.location, static_cast<rhi::VertexFormat>(static_cast<int>(rhi::VertexFormat::Float) + n - 1), 0,
                              static_cast<uint32_t>(i)};
        desc.vertexBuffers[i] = {static_cast<uint32_t>(n * 4), v.perInstance};
        slots.push_back({tempBuffer(out.data(), out.size() * sizeof(float), "converted vertices"), 0});
        continue;
      } else throw Unsupported{"vertex format " + t.name};
      desc.attributes[i] = {v.location, vf, 0, static_cast<uint32_t>(i)};
      desc.vertexBuffers[i] = {v.stride ? v.stride : t.layout.stride, v.perInstance};
      slots.push_back({gpuBuffer(v.buffer, v.loc), v.offset});
    }
    desc.attributeCount = static_cast<uint32_t>(inputs.size());
  }

  struct Attachments {
    rhi::PassDesc pass;
    std::vector<rhi::Format> colorFormats;
    rhi::Format depthFormat = rhi::Format::Undefined;
    uint32_t samples = 1;
  };

  Attachments attachments(const Pipeline& p, rhi::LoadOp load, const ClearState& cs) {
    Attachments a;
    uint32_t count = 0;
    for (const Bind& b : p.binds)
      if (b.kind == BindKind::Color) count = std::max(count, b.location + 1);
    if (count > rhi::kMaxColorTargets) throw Unsupported{"more than 4 colour attachments"};
    a.colorFormats.assign(count, rhi::Format::Undefined);
    for (const Bind& b : p.binds) {
      if (b.kind == BindKind::Color) {
        Resource& r = res_.at(b.buffer);
        if (rhi::isDepthFormat(r.format.format)) throw Failure{lineOf(b.loc) + ": '" + b.buffer + "' has a depth format"};
        const uint32_t mipWidth = std::max(r.width >> b.baseMipLevel, 1u), mipHeight = std::max(r.height >> b.baseMipLevel, 1u);
        if (mipWidth != p.fbWidth || mipHeight != p.fbHeight)
          throw Unsupported{"attachment '" + b.buffer + "' of " + std::to_string(mipWidth) + "x" + std::to_string(mipHeight) +
                            (b.baseMipLevel ? " at mip " + std::to_string(b.baseMipLevel) : std::string()) + " in a " +
                            std::to_string(p.fbWidth) + "x" + std::to_string(p.fbHeight) + " framebuffer"};
        auto& c = a.pass.colors[b.location];
        c.texture = r.texture;
        c.mip = b.baseMipLevel;
        c.load = load;
        c.clearColor = cs.color;
        a.colorFormats[b.location] = r.format.format;
        a.samples = r.samples;
      } else if (b.kind == BindKind::DepthStencil) {
        Resource& r = res_.at(b.buffer);
        if (!rhi::isDepthFormat(r.format.format)) throw Failure{lineOf(b.loc) + ": '" + b.buffer + "' is not a depth format"};
        a.pass.depthStencil.texture = r.texture;
        a.pass.depthStencil.load = load;
        a.pass.depthStencil.clearDepth = cs.depth;
        a.pass.depthStencil.clearStencil = cs.stencil;
        a.depthFormat = r.format.format;
      }
    }
    for (const Bind& b : p.binds)
      if (b.kind == BindKind::Resolve) {
        if (count == 0) throw Failure{lineOf(b.loc) + ": resolve target without a colour attachment"};
        a.pass.colors[0].resolveTarget = res_.at(b.buffer).texture;
      }
    for (uint32_t i = 0; i < count; ++i)
      if (a.colorFormats[i] == rhi::Format::Undefined) throw Unsupported{"gaps between colour LOCATIONs"};
    return a;
  }

  // Pipeline state the device cannot give is a SKIP naming the construct.
  void requireFeature(bool needed, const std::string& feature, const std::string& construct) const {
    const std::vector<std::string>& offered = dev_.info().features;
    if (needed && std::find(offered.begin(), offered.end(), feature) == offered.end())
      throw Unsupported{construct + " (the device lacks " + feature + ")"};
  }

  rhi::PipelineHandle graphicsPipeline(const Pipeline& p, rhi::PrimitiveTopology topology, bool rect,
                                       const Attachments& att, std::vector<std::pair<rhi::BufferHandle, size_t>>& slots,
                                       rhi::BufferHandle rectBuffer, uint32_t patchPoints = 0) {
    rhi::PipelineDesc d;
    vertexInput(p, rectBuffer, d, slots);
    if (!patchPoints) patchPoints = p.patchControlPoints;
    std::string key = p.name + "/" + std::to_string(int(topology)) + (rect ? "/rect" : "") + "/" + std::to_string(patchPoints);
    auto it = pipelines_.find(key);
    if (it != pipelines_.end()) return it->second.handle;
    std::vector<rhi::ShaderHandle> sh = makeShaders(p);
    for (size_t i = 0; i < p.shaders.size(); ++i) {
      Stage st = script_.findShader(p.shaders[i])->stage;
      if (st == Stage::Vertex) d.vertexShader = sh[i];
      if (st == Stage::Fragment) d.fragmentShader = sh[i];
      if (st == Stage::Geometry) d.geometryShader = sh[i];
      if (st == Stage::TessControl) d.tessControlShader = sh[i];
      if (st == Stage::TessEvaluation) d.tessEvaluationShader = sh[i];
    }
    d.patchControlPoints = patchPoints;
    if (!d.vertexShader || !d.fragmentShader) throw Failure{"pipeline '" + p.name + "' needs a vertex and a fragment shader"};
    d.topology = topology;
    d.raster.cull = p.cullMode == "front" ? rhi::CullMode::Front : p.cullMode == "back" ? rhi::CullMode::Back : rhi::CullMode::None;
    d.raster.frontFace = p.frontFace == "clockwise" ? rhi::FrontFace::Clockwise : rhi::FrontFace::CounterClockwise;
    d.raster.polygonMode = p.polygonMode == "line"    ? rhi::PolygonMode::Line
                           : p.polygonMode == "point" ? rhi::PolygonMode::Point
                                                      : rhi::PolygonMode::Fill;
    d.raster.depthClampEnabled = p.depthClamp;
    d.raster.depthBias = {p.depthBiasConstant, p.depthBiasSlope, p.depthBiasClamp};
    requireFeature(d.raster.polygonMode != rhi::PolygonMode::Fill, "fillModeNonSolid", "POLYGON_MODE " + p.polygonMode);
    requireFeature(p.depthClamp, "depthClamp", "DEPTH CLAMP on");
    requireFeature(p.depthBiasClamp != 0, "depthBiasClamp", "DEPTH BIAS clamp");
    requireFeature(topology >= rhi::PrimitiveTopology::LinesWithAdjacency, "geometryShader", "adjacency topologies");
    if (p.depthTest) {
      d.depthStencil.depthCompare = compareOp(p.depthCompare);
      d.depthStencil.depthWrite = p.depthWrite;
    }
    if (p.front.test || p.back.test) {
      if (p.front.reference != p.back.reference || p.front.compareMask != p.back.compareMask ||
          p.front.writeMask != p.back.writeMask)
        throw Unsupported{"different stencil reference or masks per face"};
      d.depthStencil.stencilEnabled = true;
      auto face = [](const StencilFace& f) {
        rhi::StencilFaceState s;
        if (!f.test) return s;
        s.compare = compareOp(f.compareOp);
        s.fail = stencilOp(f.failOp);
        s.pass = stencilOp(f.passOp);
        s.depthFail = stencilOp(f.depthFailOp);
        return s;
      };
      d.depthStencil.front = face(p.front);
      d.depthStencil.back = face(p.back);
      d.depthStencil.stencilReadMask = static_cast<uint8_t>(p.front.compareMask);
      d.depthStencil.stencilWriteMask = static_cast<uint8_t>(p.front.writeMask);
    }
    d.colorTargetCount = static_cast<uint32_t>(att.colorFormats.size());
    for (size_t i = 0; i < att.colorFormats.size(); ++i) {
      d.colorTargets[i].format = att.colorFormats[i];
      if (p.blend.enabled) {
        auto& b = d.colorTargets[i].blend;
        b.enabled = true;
        b.srcColor = blendFactor(p.blend.srcColor);
        b.dstColor = blendFactor(p.blend.dstColor);
        b.colorOp = blendOp(p.blend.colorOp);
        b.srcAlpha = blendFactor(p.blend.srcAlpha);
        b.dstAlpha = blendFactor(p.blend.dstAlpha);
        b.alphaOp = blendOp(p.blend.alphaOp);
      }
    }
    d.depthStencilFormat = att.depthFormat;
    d.samples = att.samples;
    d.label = p.name;
    rhi::PipelineHandle h = dev_.createPipeline(d);
    if (!h) throw Failure{"cannot create pipeline '" + p.name + "' (see the validation message above)"};
    pipelines_[key] = {h};
    return h;
  }

  // Contents of the pipeline's push_constant buffer, read before a pass begins (reads are
  // transfers, which the RHI does not allow inside passes).
  std::vector<uint8_t> pushConstantBytes(const Pipeline& p) {
    for (const Bind& b : p.binds)
      if (b.kind == BindKind::PushConstant) return contents(b.buffer);
    return {};
  }

  // What a combined_image_sampler or sampled_image binding samples: the texture, or from
  // BASE_MIP_LEVEL m a view of levels m and up (created once per image and level).
  rhi::TextureHandle sampledTexture(const Bind& b) {
    Resource& r = res_.at(b.buffer);
    if (r.logical) return r.readTexture;
    if (b.baseMipLevel == 0) return r.texture;
    rhi::TextureHandle& view = mipViews_[{b.buffer, b.baseMipLevel}];
    if (!view) {
      rhi::TextureViewDesc vd;
      vd.parent = r.texture;
      vd.baseMip = b.baseMipLevel;
      vd.label = b.buffer + " from mip " + std::to_string(b.baseMipLevel);
      view = dev_.createTextureView(vd);
      if (!view) throw Failure{lineOf(b.loc) + ": cannot bind '" + b.buffer + "' from BASE_MIP_LEVEL " + std::to_string(b.baseMipLevel)};
    }
    return view;
  }

  // Amber samplers clamp the level of detail to MAX_LOD (default 1.0), which the RHI's samplers do
  // not: a sampler whose MAX_LOD is below the highest level it can reach would sample levels
  // Amber never reads, so such a script is unsupported rather than silently different.
  void checkMaxLod(const Pipeline& p) {
    for (const Bind& s : p.binds) {
      if (s.kind != BindKind::CombinedImageSampler && s.kind != BindKind::Sampler) continue;
      const Sampler* sampler = script_.findSampler(s.kind == BindKind::Sampler ? s.buffer : s.sampler);
      if (!sampler) continue;
      for (const Bind& t : p.binds) {
        if (s.kind == BindKind::CombinedImageSampler ? &t != &s : t.kind != BindKind::SampledImage) continue;
        const Buffer* image = script_.findBuffer(t.buffer);
        if (!image || image->mipLevels <= t.baseMipLevel + 1) continue;
        const double highest = image->mipLevels - t.baseMipLevel - 1;
        if (sampler->maxLod < highest)
          throw Unsupported{"SAMPLER '" + sampler->name + "' MAX_LOD " + fmt(sampler->maxLod) + " below the " +
                            fmt(highest + 1) + " mip levels of '" + t.buffer + "' it samples"};
      }
    }
  }

  void bindResources(const Pipeline& p, const std::vector<uint8_t>& pushBytes) {
    checkMaxLod(p);
    const auto& map = bindingMaps_.at(p.name);
    std::vector<rhi::ResourceBinding> rb = defaults_[p.name];
    for (const Bind& b : bindsOf(p)) {
      rhi::ResourceBinding r;
      auto it = map.find({b.set, b.binding});
      if (it != map.end()) r.binding = it->second;
      r.arrayElement = b.arrayElement;
      switch (b.kind) {
        case BindKind::Storage:
        case BindKind::Uniform:
          r.kind = b.kind == BindKind::Storage ? rhi::BindingKind::StorageBuffer : rhi::BindingKind::UniformBuffer;
          r.buffer = gpuBuffer(b.buffer, b.loc);
          r.offset = static_cast<size_t>(b.offset);
          r.size = static_cast<size_t>(b.range);
          break;
        case BindKind::CombinedImageSampler:
          r.kind = rhi::BindingKind::SampledTexture;
          r.texture = sampledTexture(b);
          if (!b.sampler.empty()) r.sampler = samplerByName_.at(b.sampler);
          break;
        case BindKind::StorageImage:
          r.kind = rhi::BindingKind::StorageTexture;
          r.texture = res_.at(b.buffer).texture;
          r.mip = b.baseMipLevel;
          break;
        case BindKind::SampledImage:
          r.kind = rhi::BindingKind::SeparateTexture;
          r.texture = sampledTexture(b);
          break;
        case BindKind::UniformTexelBuffer:
        case BindKind::StorageTexelBuffer: {
          r.kind = b.kind == BindKind::UniformTexelBuffer ? rhi::BindingKind::UniformTexelBuffer
                                                          : rhi::BindingKind::StorageTexelBuffer;
          r.buffer = gpuBuffer(b.buffer, b.loc);
          r.offset = static_cast<size_t>(b.offset);
          r.size = static_cast<size_t>(b.range);
          // The buffer's FORMAT (or format-named DATA_TYPE) is the texels' format.
          const Buffer* def = res_.at(b.buffer).def;
          if (!def || !def->type.isFormat) throw Unsupported{"texel buffer '" + b.buffer + "' without a FORMAT"};
          TexFormat tf = textureFormat(def->type);
          if (tf.bgra || !rhi::isTexelBufferFormat(tf.format))
            throw Unsupported{"texel buffer '" + b.buffer + "' of FORMAT " + def->type.name + " (not a texel buffer format of the RHI)"};
          r.texelFormat = tf.format;
          break;
        }
        case BindKind::Sampler:
          r.kind = rhi::BindingKind::SeparateSampler;
          r.sampler = samplerByName_.at(b.buffer);
          break;
        case BindKind::PushConstant: {
          if (pushBytes.size() > rhi::kMaxPushConstantBytes) throw Unsupported{"push constants over 128 bytes"};
          // The RHI pushes whole words; a shorter buffer (one int8, one int16) is padded with zeros.
          std::vector<uint8_t> words(pushBytes);
          words.resize((words.size() + 3) / 4 * 4, 0);
          dev_.pushConstants(words.data(), static_cast<uint32_t>(words.size()));
          continue;
        }
        default: continue;
      }
      rb.push_back(r);
    }
    if (!rb.empty()) dev_.setBindings(rb);
  }

  rhi::BufferHandle tempBuffer(const void* data, size_t size, const char* label) {
    rhi::BufferDesc bd;
    bd.size = size;
    bd.initialData = data;
    bd.label = label;
    rhi::BufferHandle h = dev_.createBuffer(bd);
    if (!h) throw Failure{std::string("cannot create ") + label};
    tempBuffers_.push_back(h);
    return h;
  }

  void draw(const Command& c, const Pipeline& p) {
    ClearState& cs = clear_[p.name];
    Attachments att = attachments(p, rhi::LoadOp::Load, cs);
    std::vector<std::pair<rhi::BufferHandle, size_t>> slots;
    rhi::PipelineHandle ph;
    uint32_t vertexCount = 0, instanceCount = 1, firstVertex = 0, firstInstance = 0;
    bool indexed = false;
    rhi::BufferHandle indexBuffer;
    rhi::IndexType indexType = rhi::IndexType::UInt32;
    uint32_t indexOffsetBytes = 0;
    if (c.kind == Command::Kind::DrawRect || c.kind == Command::Kind::DrawGrid) {
      // As in Amber, the rectangle's vertices replace the pipeline's one VERTEX_DATA for this draw;
      // Amber refuses the draw on a pipeline with more than one.
      if (p.vertexData.size() > 1)
        throw Failure{lineOf(c.loc) + ": " + (c.kind == Command::Kind::DrawRect ? "DRAW_RECT" : "DRAW_GRID") +
                      " on pipeline '" + p.name + "' with more than one VERTEX_DATA"};
      // Amber: pixels to NDC, (0, 0) the top-left = NDC (-1, -1) = framebuffer row 0.
      // x360 screen-space draws: D3D9 pixel centres (PIX_CENTER = 0, HALFPIXELOFFSET FALSE) are
      // emulated as the host does, by moving window positions +0.5 px (X5).
      float centre = platform_ == platforms::PlatformId::X360
                         ? platforms::x360::hostWindowOffset(platforms::x360::pixelCenterFor(params_.halfPixelOffset, params_))
                         : 0.0f;
      float fw = static_cast<float>(p.fbWidth), fh = static_cast<float>(p.fbHeight);
      float x = (c.x + centre) / fw * 2.0f - 1.0f, y = (c.y + centre) / fh * 2.0f - 1.0f, w = c.w / fw * 2.0f, h = c.h / fh * 2.0f;
      if (c.ndc) x = c.x, y = c.y, w = c.w, h = c.h;
      std::vector<float> v;
      rhi::PrimitiveTopology topo;
      if (c.kind == Command::Kind::DrawRect && c.patch) {
        // piglit's `draw rect patch`: one patch of the corners in piglit_draw_rect's order.
        v = {x, y, x + w, y, x, y + h, x + w, y + h};
        topo = rhi::PrimitiveTopology::Patches;
      } else if (c.kind == Command::Kind::DrawRect) {
        v = {x, y + h, x, y, x + w, y + h, x + w, y};
        topo = rhi::PrimitiveTopology::TriangleStrip;
      } else {
        topo = rhi::PrimitiveTopology::Triangles;
        float cw = w / static_cast<float>(c.cellsX), ch = h / static_cast<float>(c.cellsY);
        for (uint32_t j = 0; j < c.cellsY; ++j)
          for (uint32_t i = 0; i < c.cellsX; ++i) {
            float x0 = x + cw * static_cast<float>(i), y0 = y + ch * static_cast<float>(j), x1 = x0 + cw, y1 = y0 + ch;
            // Two triangles split along the top-left/bottom-right diagonal, both starting at the
            // cell's top-left corner (the provoking vertex of flat inputs).
            float q[12] = {x0, y0, x1, y0, x1, y1, x0, y0, x1, y1, x0, y1};
            v.insert(v.end(), q, q + 12);
          }
      }
      // Each vertex: its position and its texture coordinate (0..1 across the rectangle).
      std::vector<float> interleaved;
      for (size_t i = 0; i + 1 < v.size(); i += 2)
        interleaved.insert(interleaved.end(), {v[i], v[i + 1], w != 0 ? (v[i] - x) / w : 0.0f, h != 0 ? (v[i + 1] - y) / h : 0.0f});
      rhi::BufferHandle vb = tempBuffer(interleaved.data(), interleaved.size() * sizeof(float), "rect vertices");
      ph = graphicsPipeline(p, topo, true, att, slots, vb, c.patch ? 4 : 0);
      vertexCount = static_cast<uint32_t>(v.size() / 2);
    } else {
      static const std::map<std::string, rhi::PrimitiveTopology> kTopo = {
          {"TRIANGLE_LIST", rhi::PrimitiveTopology::Triangles}, {"TRIANGLE_STRIP", rhi::PrimitiveTopology::TriangleStrip},
          {"TRIANGLE_FAN", rhi::PrimitiveTopology::Triangles}, {"LINE_LIST", rhi::PrimitiveTopology::Lines},
          {"POINT_LIST", rhi::PrimitiveTopology::Points}, {"LINE_STRIP", rhi::PrimitiveTopology::LineStrip},
          {"PATCH_LIST", rhi::PrimitiveTopology::Patches},
          {"LINE_LIST_WITH_ADJACENCY", rhi::PrimitiveTopology::LinesWithAdjacency},
          {"LINE_STRIP_WITH_ADJACENCY", rhi::PrimitiveTopology::LineStripWithAdjacency},
          {"TRIANGLE_LIST_WITH_ADJACENCY", rhi::PrimitiveTopology::TrianglesWithAdjacency},
          {"TRIANGLE_STRIP_WITH_ADJACENCY", rhi::PrimitiveTopology::TriangleStripWithAdjacency}};
      auto t = kTopo.find(c.topology);
      if (t == kTopo.end()) throw Unsupported{"DRAW_ARRAY AS " + c.topology};
      bool fan = c.topology == "TRIANGLE_FAN";
      ph = graphicsPipeline(p, t->second, false, att, slots, {});
      instanceCount = c.instanceCount;
      firstInstance = c.instanceStart;
      // Vertex count: COUNT, or every element of the first vertex buffer (or index buffer).
      std::vector<uint32_t> indices;  // when converted on the CPU (uint8 indices, fans)
      if (c.indexed) {
        if (p.indexData.empty()) throw Failure{lineOf(c.loc) + ": DRAW_ARRAY INDEXED on a pipeline without INDEX_DATA"};
        const Buffer* ib = script_.findBuffer(p.indexData);
        Scalar s = ib->type.layout.fields[0].scalar;
        size_t n = ib->bytes.size() / scalarSize(s);
        uint32_t count = c.countGiven ? c.count : static_cast<uint32_t>(n - std::min<size_t>(n, c.start));
        if (s == Scalar::Uint8 || fan) {
          std::vector<uint8_t> raw = contents(p.indexData);
          std::vector<uint32_t> all;
          for (size_t i = 0; i < n; ++i) all.push_back(static_cast<uint32_t>(readScalar(raw.data() + i * scalarSize(s), s)));
          std::vector<uint32_t> sel(all.begin() + std::min<size_t>(c.start, n), all.begin() + std::min<size_t>(c.start + count, n));
          indices = sel;
        } else {
          indexBuffer = gpuBuffer(p.indexData, c.loc);
          indexType = s == Scalar::Uint16 ? rhi::IndexType::UInt16 : rhi::IndexType::UInt32;
          if (s != Scalar::Uint16 && s != Scalar::Uint32) throw Unsupported{"INDEX_DATA of " + ib->type.name};
          indexOffsetBytes = c.start * scalarSize(s);
          vertexCount = count;
        }
        indexed = true;
      } else {
        uint32_t n = 0;
        if (!p.vertexData.empty()) {
          const Buffer* vb = script_.findBuffer(p.vertexData[0].buffer);
          uint32_t stride = p.vertexData[0].stride ? p.vertexData[0].stride : vb->type.layout.stride;
          n = static_cast<uint32_t>(vb->bytes.size() / std::max(1u, stride));
        }
        uint32_t count = c.countGiven ? c.count : n - std::min(n, c.start);
        if (fan) {
          for (uint32_t i = 0; i < count; ++i) indices.push_back(c.start + i);
        } else {
          vertexCount = count;
          firstVertex = c.start;
        }
      }
      if (fan || !indices.empty() || (indexed && !indexBuffer)) {
        std::vector<uint32_t> list;
        if (fan) {
          for (size_t i = 1; i + 1 < indices.size(); ++i) list.insert(list.end(), {indices[0], indices[i], indices[i + 1]});
        } else {
          list = indices;
        }
        if (list.empty()) list.push_back(0), vertexCount = 0;
        else vertexCount = static_cast<uint32_t>(list.size());
        indexBuffer = tempBuffer(list.data(), list.size() * 4, "converted indices");
        indexType = rhi::IndexType::UInt32;
        indexOffsetBytes = 0;
        indexed = true;
      }
    }
    std::vector<uint8_t> pushBytes = pushConstantBytes(p);
    dev_.beginPass(att.pass);
    dev_.setPipeline(ph);
    if (p.viewport) dev_.setViewport({(*p.viewport)[0], (*p.viewport)[1], (*p.viewport)[2], (*p.viewport)[3], p.viewportDepth[0], p.viewportDepth[1]});
    if (p.front.test || p.back.test) dev_.setStencilReference(static_cast<uint8_t>(p.front.reference));
    if (p.blend.enabled) dev_.setBlendConstant(p.blend.constant);
    bindResources(p, pushBytes);
    for (size_t i = 0; i < slots.size(); ++i) dev_.setVertexBuffer(static_cast<uint32_t>(i), slots[i].first, slots[i].second);
    if (indexed) {
      dev_.setIndexBuffer(indexBuffer, indexType, indexOffsetBytes);
      if (vertexCount) dev_.drawIndexed(vertexCount, instanceCount, 0, c.baseVertex, firstInstance);
    } else if (vertexCount) {
      dev_.draw(vertexCount, instanceCount, firstVertex, firstInstance);
    }
    dev_.endPass();
  }

  void compute(const Command& c, const Pipeline& p) {
    auto it = computePipelines_.find(p.name);
    rhi::ComputePipelineHandle h;
    if (it == computePipelines_.end()) {
      std::vector<rhi::ShaderHandle> sh = makeShaders(p);
      if (sh.size() != 1) throw Failure{"compute pipeline '" + p.name + "' needs one compute shader"};
      rhi::ComputePipelineDesc d;
      d.computeShader = sh[0];
      d.label = p.name;
      h = dev_.createComputePipeline(d);
      if (!h) throw Failure{"cannot create compute pipeline '" + p.name + "'"};
      computePipelines_[p.name] = h;
    } else {
      h = it->second;
    }
    dev_.setComputePipeline(h);
    bindResources(p, pushConstantBytes(p));
    dev_.dispatch(c.groups[0], c.groups[1], c.groups[2]);
  }

  void clearPass(const Pipeline& p) {
    Attachments att = attachments(p, rhi::LoadOp::Clear, clear_[p.name]);
    dev_.beginPass(att.pass);
    dev_.endPass();
  }

  // --- expectations ---
  ExpectResult probe(const Command& c) {
    ExpectResult e;
    e.line = c.loc.line;
    Resource& r = res_.at(c.buffer);
    std::ostringstream what;
    what << "line " << c.loc.line << ": EXPECT " << c.buffer << " IDX " << c.px << " " << c.py << " SIZE " << c.pw << " " << c.ph;
    if (r.logical)
      throw Failure{what.str() + ": LOGICAL image texels are platform-specific; read it in a shader or use MEMORY BYTES"};
    if (!r.texture && !(r.cpu && r.width > 0)) throw Failure{what.str() + ": '" + c.buffer + "' is not an image or framebuffer"};
    if (c.px + c.pw > r.width || c.py + c.ph > r.height)
      throw Failure{what.str() + ": outside the " + std::to_string(r.width) + "x" + std::to_string(r.height) + " image"};
    std::vector<uint8_t> px = contents(c.buffer);
    const Layout& L = r.def->type.layout;
    double tol[4];
    bool pct[4];
    for (int i = 0; i < 4; ++i) {
      if (c.tolerances.empty()) tol[i] = 0.002, pct[i] = false;
      else {
        const Tolerance& t = c.tolerances[c.tolerances.size() == 4 ? i : 0];
        tol[i] = t.percent ? t.value : t.value / 255.0;
        pct[i] = t.percent;
      }
    }
    uint32_t bad = 0;
    std::string first;
    for (uint32_t y = c.py; y < c.py + c.ph; ++y)
      for (uint32_t x = c.px; x < c.px + c.pw; ++x) {
        const uint8_t* t = px.data() + (size_t(y) * r.width + x) * L.stride;
        double actual[4] = {0, 0, 0, 1};
        bool has[4] = {false, false, false, false};
        for (const Field& f : L.fields) {
          int ch = f.channel == 'R' ? 0 : f.channel == 'G' ? 1 : f.channel == 'B' ? 2 : f.channel == 'A' ? 3 : 0;
          double v = readScalar(t + f.offset, f.scalar);
          if (f.mode == Mode::Unorm || f.mode == Mode::Srgb) v /= std::ldexp(1.0, int(scalarSize(f.scalar) * 8)) - 1;
          if (f.mode == Mode::Snorm) v /= std::ldexp(1.0, int(scalarSize(f.scalar) * 8 - 1)) - 1;
          if (f.mode == Mode::Srgb && ch != 3) v = srgbToLinear(v);
          actual[ch] = v;
          has[ch] = true;
        }
        bool ok = true;
        for (int i = 0; i < (c.rgba ? 4 : 3); ++i) {
          if (!has[i]) continue;
          double expected = c.color[i] / 255.0, diff = std::fabs(expected - actual[i]);
          if (pct[i] ? diff > tol[i] / 100.0 * std::fabs(actual[i]) : diff > tol[i]) ok = false;
        }
        if (ok) continue;
        if (bad++ == 0) {
          std::ostringstream s;
          bool scale = L.fields[0].mode == Mode::Unorm || L.fields[0].mode == Mode::Srgb;
          s << "first at (" << x << ", " << y << "): expected (";
          for (int i = 0; i < (c.rgba ? 4 : 3); ++i) s << (i ? ", " : "") << fmt(c.color[i]);
          s << "), got (";
          for (int i = 0; i < (c.rgba ? 4 : 3); ++i) s << (i ? ", " : "") << fmt(scale ? std::round(actual[i] * 255.0 * 1000) / 1000 : actual[i] * 255.0);
          s << ")";
          first = s.str();
        }
      }
    e.pass = bad == 0;
    e.message = what.str() + (bad ? ": " + std::to_string(bad) + " of " + std::to_string(c.pw * c.ph) + " pixels differ, " + first : ": ok");
    return e;
  }

  ExpectResult values(const Command& c) {
    ExpectResult e;
    e.line = c.loc.line;
    const Buffer* b = script_.findBuffer(c.buffer);
    const Layout& L = c.valueTypeGiven ? c.valueType.layout : b->type.layout;
    std::vector<uint8_t> bytes = contents(c.buffer);
    std::string what = "line " + std::to_string(c.loc.line) + ": EXPECT " + c.buffer + " IDX " + std::to_string(c.px);
    // A given value type reads its elements from byte px on; else px indexes the buffer's layout.
    size_t base = c.valueTypeGiven ? c.px : 0;
    size_t elem = c.valueTypeGiven ? 0 : c.px / L.stride, field = c.valueTypeGiven ? 0 : L.fields.size();
    for (size_t f = 0; f < L.fields.size() && !c.valueTypeGiven; ++f)
      if (L.fields[f].offset == c.px % L.stride) field = f;
    if (field == L.fields.size()) throw Failure{what + ": byte offset " + std::to_string(c.px) + " is not the start of a component"};
    for (size_t i = 0; i < c.values.size(); ++i) {
      const Field& f = L.fields[field];
      size_t off = base + elem * L.stride + f.offset;
      if (off + scalarSize(f.scalar) > bytes.size())
        throw Failure{what + ": value " + std::to_string(i) + " is past the end of the buffer (" + std::to_string(bytes.size()) + " bytes)"};
      double actual = readScalar(bytes.data() + off, f.scalar);
      const Value& v = c.values[i];
      double expected = v.d;
      bool ok = true;
      bool integer = isIntegerScalar(f.scalar);
      switch (c.comparator) {
        case Comparator::Eq: ok = integer ? actual == expected : std::fabs(actual - expected) <= 1e-6 * std::max(1.0, std::fabs(expected)); break;
        case Comparator::Ne: ok = integer ? actual != expected : std::fabs(actual - expected) > 1e-6 * std::max(1.0, std::fabs(expected)); break;
        case Comparator::Lt: ok = actual < expected; break;
        case Comparator::Le: ok = actual <= expected; break;
        case Comparator::Gt: ok = actual > expected; break;
        case Comparator::Ge: ok = actual >= expected; break;
        case Comparator::FuzzyEq: {
          const Tolerance& t = c.tolerances[0];
          double d = std::fabs(actual - expected);
          ok = t.percent ? d <= t.value / 100.0 * std::fabs(expected) : d <= t.value;
          break;
        }
      }
      if (!ok) {
        static const char* kOps[] = {"==", "!=", "<", "<=", ">", ">=", "~="};
        e.pass = false;
        e.message = what + ": value " + std::to_string(i) + " (byte " + std::to_string(off) + "): expected " +
                    kOps[int(c.comparator)] + " " + fmt(expected) + ", got " + fmt(actual);
        return e;
      }
      if (++field == L.fields.size()) field = 0, ++elem;
    }
    e.pass = true;
    e.message = what + ": ok";
    return e;
  }

  ExpectResult buffers(const Command& c) {
    ExpectResult e;
    e.line = c.loc.line;
    const Buffer* a = script_.findBuffer(c.buffer);
    const Buffer* b = script_.findBuffer(c.other);
    std::string what = "line " + std::to_string(c.loc.line) + ": EXPECT " + c.buffer + (c.emd ? " EQ_HISTOGRAM_EMD_BUFFER " : c.rmse ? " RMSE_BUFFER " : " EQ_BUFFER ") + c.other;
    std::vector<uint8_t> x = contents(c.buffer), y = contents(c.other);
    const Layout &La = a->type.layout, &Lb = b->type.layout;
    size_t na = x.size() / La.stride, nb = y.size() / Lb.stride;
    if (La.fields.size() != Lb.fields.size() || La.fields[0].scalar != Lb.fields[0].scalar)
      throw Failure{what + ": the buffers have different types (" + a->type.name + ", " + b->type.name + ")"};
    if (na != nb) {
      e.message = what + ": " + std::to_string(na) + " elements vs " + std::to_string(nb);
      return e;
    }
    double sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < na; ++i)
      for (size_t f = 0; f < La.fields.size(); ++f) {
        double va = readScalar(x.data() + i * La.stride + La.fields[f].offset, La.fields[f].scalar);
        double vb = readScalar(y.data() + i * Lb.stride + Lb.fields[f].offset, Lb.fields[f].scalar);
        if (!c.rmse && !c.emd && va != vb) {
          e.message = what + ": element " + std::to_string(i) + " component " + std::to_string(f) + ": " + fmt(va) + " vs " + fmt(vb);
          return e;
        }
        sum += (va - vb) * (va - vb);
        ++n;
      }
    if (c.emd) {
      // Amber's EQ_HISTOGRAM_EMD_BUFFER: per channel, 256-bin histograms normalised by the
      // element count; EMD = sum |cumulative difference| / 256; the largest channel's EMD is
      // compared with the tolerance. 8-bit unorm only.
      if (La.fields[0].scalar != Scalar::Uint8) throw Unsupported{"EQ_HISTOGRAM_EMD_BUFFER on " + a->type.name};
      double worst = 0;
      for (size_t f = 0; f < La.fields.size(); ++f) {
        std::vector<double> ha(256, 0), hb(256, 0);
        for (size_t i = 0; i < na; ++i) {
          ha[x[i * La.stride + La.fields[f].offset]] += 1.0 / double(na);
          hb[y[i * Lb.stride + Lb.fields[f].offset]] += 1.0 / double(nb);
        }
        double cum = 0, emd = 0;
        for (int k = 0; k < 256; ++k) {
          cum += ha[k] - hb[k];
          emd += std::fabs(cum);
        }
        worst = std::max(worst, emd / 256.0);
      }
      e.pass = worst <= c.rmseTolerance;
      e.message = what + ": histogram EMD " + fmt(worst) + (e.pass ? " <= " : " > ") + fmt(c.rmseTolerance);
      return e;
    }
    if (c.rmse) {
      double rmse = n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
      // Allowance for the float rounding of the inputs (1.1f - 1.0f is 0.10000002).
      e.pass = rmse <= c.rmseTolerance + 1e-6;
      e.message = what + ": RMSE " + fmt(rmse) + (e.pass ? " <= " : " > ") + fmt(c.rmseTolerance);
      return e;
    }
    e.pass = true;
    e.message = what + ": ok";
    return e;
  }

  // Ours: the console memory bytes of a LOGICAL image (platforms::GpuTargets::consoleBytes), per
  // pixel in the console's byte order; the expected bytes are one pixel's (every pixel of the
  // rectangle must hold them) or every pixel's, row by row.
  ExpectResult memory(const Command& c) {
    ExpectResult e;
    e.line = c.loc.line;
    Resource& r = res_.at(c.buffer);
    std::ostringstream what;
    what << "line " << c.loc.line << ": EXPECT " << c.buffer << " MEMORY BYTES" << (c.afterResolve ? " RESOLVED" : "") << " IDX "
         << c.px << " " << c.py << " SIZE " << c.pw << " " << c.ph << " on " << opts_.platform;
    if (c.px + c.pw > r.width || c.py + c.ph > r.height)
      throw Failure{what.str() + ": outside the " + std::to_string(r.width) + "x" + std::to_string(r.height) + " image"};
    std::vector<uint8_t> bytes = targets_->consoleBytes(c.buffer, c.afterResolve);
    size_t pixels = size_t(r.width) * r.height;
    size_t bpp = pixels ? bytes.size() / pixels : 0;
    bool perPixel = c.values.size() == bpp * c.pw * c.ph && c.values.size() != bpp;
    if (bpp == 0 || (c.values.size() != bpp && !perPixel))
      throw Failure{what.str() + ": " + std::to_string(c.values.size()) + " bytes given, a pixel holds " + std::to_string(bpp)};
    auto hex = [](const uint8_t* b, size_t n) {
      std::string s;
      char buf[8];
      for (size_t i = 0; i < n; ++i) std::snprintf(buf, sizeof(buf), "%s%02X", i ? " " : "", b[i]), s += buf;
      return s;
    };
    uint32_t bad = 0;
    std::string first;
    for (uint32_t y = c.py; y < c.py + c.ph; ++y)
      for (uint32_t x = c.px; x < c.px + c.pw; ++x) {
        const uint8_t* got = bytes.data() + (size_t(y) * r.width + x) * bpp;
        size_t k = perPixel ? (size_t(y - c.py) * c.pw + (x - c.px)) * bpp : 0;
        std::vector<uint8_t> want(bpp);
        for (size_t i = 0; i < bpp; ++i) want[i] = static_cast<uint8_t>(c.values[k + i].i);
        if (std::memcmp(got, want.data(), bpp) == 0) continue;
        if (bad++ == 0)
          first = "first at (" + std::to_string(x) + ", " + std::to_string(y) + "): expected " + hex(want.data(), bpp) + ", got " + hex(got, bpp);
      }
    e.pass = bad == 0;
    e.message = what.str() + (bad ? ": " + std::to_string(bad) + " of " + std::to_string(c.pw * c.ph) + " pixels differ, " + first : ": ok");
    return e;
  }

  // Ours: an RGBA8 image against a PNG: RMSE over all channels (0-255 units), the largest
  // channel difference, and (FLIP t) the mean LDR-FLIP error (harness/flip.h, 0..1).
  ExpectResult image(const Command& c) {
    ExpectResult e;
    e.line = c.loc.line;
    std::string what = "line " + std::to_string(c.loc.line) + ": EXPECT " + c.buffer + " EQ_IMAGE " + c.imageFile;
    Resource& r = res_.at(c.buffer);
    const Layout& L = r.def->type.layout;
    if (L.stride != 4 || L.fields.size() != 4 || L.fields[0].scalar != Scalar::Uint8)
      throw Failure{what + ": EQ_IMAGE compares 8-bit RGBA images, '" + c.buffer + "' is " + r.def->type.name};
    std::vector<uint8_t> want;
    uint32_t w = 0, h = 0;
    std::string why;
    if (!loadPng(c.imageFile, &want, &w, &h, &why)) throw Failure{what + ": " + why};
    if (w != r.width || h != r.height) {
      e.message = what + ": reference is " + std::to_string(w) + "x" + std::to_string(h) + ", image is " +
                  std::to_string(r.width) + "x" + std::to_string(r.height);
      return e;
    }
    std::vector<uint8_t> got = contents(c.buffer);  // R, G, B, A by channel name after toTextureBytes
    std::vector<uint8_t> rgba(got.size());
    for (size_t i = 0; i + 3 < got.size(); i += 4)
      for (const Field& f : L.fields) {
        int ch = f.channel == 'R' ? 0 : f.channel == 'G' ? 1 : f.channel == 'B' ? 2 : 3;
        rgba[i + size_t(ch)] = got[i + f.offset];
      }
    double sum = 0, worst = 0;
    for (size_t i = 0; i < rgba.size() && i < want.size(); ++i) {
      double d = std::fabs(double(rgba[i]) - double(want[i]));
      sum += d * d;
      worst = std::max(worst, d);
    }
    double rmse = rgba.empty() ? 0 : std::sqrt(sum / double(rgba.size()));
    // FLIP alone judges by FLIP; RMSE/MAX given with it still apply.
    bool flipOnly = c.imageFlip && !c.imageRmse && !c.imageMax;
    double rmseLimit = flipOnly ? 255 : c.imageRmse.value_or(0);
    double maxLimit = flipOnly ? 255 : c.imageMax.value_or(c.imageRmse ? 255 : 0);
    e.pass = rmse <= rmseLimit + 1e-9 && worst <= maxLimit;
    e.message = what + ": RMSE " + fmt(rmse) + " (limit " + fmt(rmseLimit) + "), max " + fmt(worst) + " (limit " + fmt(maxLimit) + ")";
    if (c.imageFlip) {
      OIIO::ImageSpec spec(int(w), int(h), 4, OIIO::TypeDesc::UINT8);
      OIIO::ImageBuf reference(spec, want.data()), test(spec, rgba.data());
      FlipResult flip = computeLdrFlip(reference, test);
      if (!flip.ok) throw Failure{what + ": FLIP: " + flip.error};
      e.pass = e.pass && flip.mean <= *c.imageFlip + 1e-12;
      e.message += ", FLIP mean " + fmt(flip.mean) + " (limit " + fmt(*c.imageFlip) + ")";
    }
    return e;
  }

  void execute(const Command& c, RunResult& result) {
    const Pipeline* p = c.pipeline.empty() ? nullptr : script_.findPipeline(c.pipeline);
    switch (c.kind) {
      case Command::Kind::ClearColor:
        for (int i = 0; i < 4; ++i) clear_[p->name].color[i] = static_cast<float>(c.color[i] / 255.0);
        break;
      case Command::Kind::ClearDepth: clear_[p->name].depth = static_cast<float>(c.color[0]); break;
      case Command::Kind::ClearStencil: clear_[p->name].stencil = static_cast<uint8_t>(c.color[0]); break;
      case Command::Kind::Clear: clearPass(*p); break;
      case Command::Kind::DrawRect:
      case Command::Kind::DrawGrid:
      case Command::Kind::DrawArray: draw(c, *p); break;
      case Command::Kind::Compute: compute(c, *p); break;
      case Command::Kind::ExpectProbe: result.expects.push_back(probe(c)); break;
      case Command::Kind::ExpectValues: result.expects.push_back(values(c)); break;
      case Command::Kind::ExpectBuffer: result.expects.push_back(buffers(c)); break;
      case Command::Kind::Copy: copy(c); break;
      case Command::Kind::Resolve:
        if (!targets_->resolve(c.buffer, c.resolveSamples))
          throw Failure{lineOf(c.loc) + ": RESOLVE " + c.buffer + " failed on " + opts_.platform + ": " + targets_->error()};
        break;
      case Command::Kind::ExpectMemory:
        if (c.platform.empty() || c.platform == opts_.platform) result.expects.push_back(memory(c));
        break;
      case Command::Kind::ExpectImage: result.expects.push_back(image(c)); break;
      case Command::Kind::SetUniform: setUniform(c); break;
      case Command::Kind::WriteBuffer: {
        rhi::BufferHandle b = gpuBuffer(c.buffer, c.loc);
        if (c.px + c.bytes.size() > res_.at(c.buffer).def->bytes.size()) throw Failure{lineOf(c.loc) + ": write past the end of '" + c.buffer + "'"};
        dev_.writeBuffer(b, c.px, c.bytes.data(), c.bytes.size());
        break;
      }
    }
  }
};

}  // namespace

std::string ScriptCase::id() const { return script + "/" + backend + "/" + platform; }

bool isExpectFail(const std::string& path) {
  const std::string suffix = ".expect_fail.amber";
  return path.size() >= suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::vector<std::string> collectScripts(const std::vector<std::string>& paths, std::string* error) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  for (const std::string& p : paths) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<std::string> found;
      for (auto it = fs::recursive_directory_iterator(p, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
        if (it->is_regular_file() && (it->path().extension() == ".amber" || it->path().extension() == ".shader_test"))
          found.push_back(it->path().string());
      std::sort(found.begin(), found.end());
      out.insert(out.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(p, ec)) {
      out.push_back(p);
    } else {
      *error = p + ": no such file or folder";
      return {};
    }
  }
  return out;
}

std::vector<ScriptCase> listScriptCases(const std::vector<std::string>& paths, const std::vector<std::string>& backends,
                                        const std::vector<std::string>& platforms, std::string* error) {
  std::vector<ScriptCase> out;
  std::vector<std::string> files = collectScripts(paths, error);
  if (!error->empty()) return {};
  for (const std::string& f : files) {
    ParseResult parsed = parseScriptFile(f);
    std::vector<std::string> allowed = parsed.ok ? allowedPlatforms(parsed.script) : std::vector<std::string>{"reference"};
    for (const std::string& b : backends)
      for (const std::string& p : allowed)
        if (platforms.empty() || std::find(platforms.begin(), platforms.end(), p) != platforms.end())
          out.push_back({f, b, p, isExpectFail(f)});
  }
  return out;
}

RunResult applyExpectFail(RunResult r, bool expectFail) {
  if (!expectFail) return r;
  if (r.verdict == Verdict::Fail) {
    r.verdict = Verdict::Pass;
    r.reason = "failed as expected: " + r.reason;
  } else if (r.verdict == Verdict::Pass) {
    r.verdict = Verdict::Fail;
    r.reason = "expected to fail (*.expect_fail.amber) but passed";
  }
  return r;
}

RunResult runScriptCase(const ScriptCase& c) {
  RunResult r;
  ParseResult parsed = parseScriptFile(c.script);
  RunOptions ro;
  ro.platform = c.platform;
  if (!parsed.ok) return applyExpectFail({Verdict::Fail, parsed.error, {}}, c.expectFail);
  if (std::string why = skipReasonBeforeRun(parsed.script, c.backend, ro); !why.empty()) return {Verdict::Skip, why, {}};
  rhi::DeviceDesc desc;
  desc.backend = c.backend;
  std::vector<std::string> validation;
  desc.onValidationError = [&validation](const std::string& id, const std::string& msg) { validation.push_back(id + ": " + msg); };
  std::string whyNot;
  std::unique_ptr<rhi::Device> dev = rhi::createDevice(desc, &whyNot);
  if (!dev) return {Verdict::Skip, "backend " + c.backend + " unavailable: " + whyNot, {}};
  r = runScript(parsed.script, *dev, ro);
  if (!validation.empty() && r.verdict == Verdict::Pass) {
    r.verdict = Verdict::Fail;
    r.reason = "RHI validation: " + validation.front();
  } else if (!validation.empty() && r.verdict == Verdict::Fail) {
    r.reason += " (RHI validation: " + validation.front() + ")";
  }
  return applyExpectFail(r, c.expectFail);
}

std::string deviceRequirementMissing(const Script& script, const rhi::DeviceInfo& info) {
  // Emulated by the runner: uint8 indices are widened on the CPU.
  static const std::set<std::string> kEmulated = {"indexTypeUint8", "VK_EXT_index_type_uint8"};
  for (const Requirement& r : script.requirements) {
    if (r.what != "device_feature" && r.what != "device_extension") continue;
    // Amber qualifies features by their structure ("Float16Int8Features.shaderFloat16"); the
    // member names are unique across the structures.
    std::string name = r.what == "device_feature" ? r.value.substr(r.value.rfind('.') + 1) : r.value;
    const std::vector<std::string>& offered = r.what == "device_feature" ? info.features : info.extensions;
    if (kEmulated.count(name) || std::find(offered.begin(), offered.end(), name) != offered.end()) continue;
    return std::string(r.what == "device_feature" ? "DEVICE_FEATURE " : "DEVICE_EXTENSION ") + r.value + " (line " +
           std::to_string(r.loc.line) + ") not offered by " + info.backend + " on " + info.renderer;
  }
  return {};
}

RunResult runScript(const Script& script, rhi::Device& device, const RunOptions& options) {
  std::string why = skipReasonBeforeRun(script, device.info().backend, options);
  if (!why.empty()) return {Verdict::Skip, why, {}};
  const rhi::Capabilities& caps = device.info().caps;
  for (const Requirement& r : script.requirements) {
    if (r.what != "capability") continue;
    bool ok = r.value == "compute" ? caps.compute
              : r.value == "texture_views" ? caps.textureViews
              : r.value == "timestamps" ? caps.timestamps
              : r.value == "independent_blend" ? caps.independentBlend
              : r.value == "msaa4" ? caps.maxSamples >= 4
                                   : false;
    if (!ok) return {Verdict::Skip, "REQUIRE capability " + r.value + " not offered by this backend", {}};
  }
  if (std::string why = deviceRequirementMissing(script, device.info()); !why.empty()) return {Verdict::Skip, why, {}};
  Runner runner(script, device, options);
  return runner.run();
}

}  // namespace parity::harness::script
