#include "rhi/validation.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "rhi/shader_reflection.h"

namespace parity::rhi {

namespace {

using R = ValidationRuleId;

constexpr uint32_t kMaxTextureSize = 16384;
constexpr uint32_t kMaxTextureLayers = 2048;
constexpr uint32_t kMaxTexture3DSize = 2048;  // GL 4.5's minimum MAX_3D_TEXTURE_SIZE
constexpr uint32_t kMaxDispatchGroups = 65535;
constexpr uint32_t kMaxVertexLocations = 16;
constexpr size_t kBufferBindingAlignment = 256;   // the largest alignment Vulkan lets a device ask for
constexpr size_t kMaxUniformBufferRange = 65536;  // uniform block size offered by llvmpipe and lavapipe

const char* const kRuleNames[] = {
#define PARITY_RHI_VALIDATION_NAME(id, description) #id,
    PARITY_RHI_VALIDATION_RULES(PARITY_RHI_VALIDATION_NAME)
#undef PARITY_RHI_VALIDATION_NAME
};
static_assert(sizeof(kRuleNames) / sizeof(kRuleNames[0]) == static_cast<size_t>(R::Count));

uint32_t mipSize(uint32_t size, uint32_t mip) { return std::max(1u, mip < 32 ? size >> mip : 0u); }

uint32_t vertexFormatSize(VertexFormat f) {
  switch (f) {
    case VertexFormat::Float:
      return 4;
    case VertexFormat::Float2:
      return 8;
    case VertexFormat::Float3:
      return 12;
    case VertexFormat::Float4:
      return 16;
    case VertexFormat::UByte4Norm:
      return 4;
    case VertexFormat::UInt:
      return 4;
    case VertexFormat::UInt2:
      return 8;
    case VertexFormat::UInt4:
      return 16;
    case VertexFormat::UInt3:
      return 12;
    case VertexFormat::Int:
      return 4;
    case VertexFormat::Int2:
      return 8;
    case VertexFormat::Int3:
      return 12;
    case VertexFormat::Int4:
      return 16;
    case VertexFormat::Double:
      return 8;
    case VertexFormat::Double2:
      return 16;
    case VertexFormat::Double3:
      return 24;
    case VertexFormat::Double4:
      return 32;
  }
  return 0;
}

// Locations an attribute of this format takes: dvec3 and dvec4 take two (Vulkan and OpenGL).
uint32_t vertexFormatLocations(VertexFormat f) { return f == VertexFormat::Double3 || f == VertexFormat::Double4 ? 2 : 1; }

const char* stageName(ShaderStage s) {
  switch (s) {
    case ShaderStage::Vertex:
      return "vertex";
    case ShaderStage::Fragment:
      return "fragment";
    case ShaderStage::Compute:
      return "compute";
    case ShaderStage::Geometry:
      return "geometry";
    case ShaderStage::TessControl:
      return "tessellation control";
    case ShaderStage::TessEvaluation:
      return "tessellation evaluation";
  }
  return "unknown";
}

const char* kindName(BindingKind k) {
  switch (k) {
    case BindingKind::UniformBuffer:
      return "UniformBuffer";
    case BindingKind::StorageBuffer:
      return "StorageBuffer";
    case BindingKind::SampledTexture:
      return "SampledTexture";
    case BindingKind::StorageTexture:
      return "StorageTexture";
    case BindingKind::SeparateTexture:
      return "SeparateTexture";
    case BindingKind::SeparateSampler:
      return "SeparateSampler";
    case BindingKind::UniformTexelBuffer:
      return "UniformTexelBuffer";
    case BindingKind::StorageTexelBuffer:
      return "StorageTexelBuffer";
  }
  return "unknown";
}

bool validFormat(Format f) {
  return f != Format::Undefined && static_cast<uint32_t>(f) < static_cast<uint32_t>(Format::Count);
}
const char* fmt(Format f) { return validFormat(f) ? formatInfo(f).name : "Undefined"; }

std::string quoted(const std::string& kind, const std::string& label, uint32_t id) {
  if (!label.empty()) return kind + " '" + label + "'";
  if (id == 0) return "unlabelled " + kind;
  std::ostringstream s;
  s << kind << " #" << (id & 0xFFFFF);
  return s.str();
}

// Execution models of OpEntryPoint for the three stages.
uint32_t executionModel(ShaderStage s) {
  switch (s) {
    case ShaderStage::Vertex:
      return 0;
    case ShaderStage::Fragment:
      return 4;
    case ShaderStage::Compute:
      return 5;
    case ShaderStage::Geometry:
      return 3;
    case ShaderStage::TessControl:
      return 1;
    case ShaderStage::TessEvaluation:
      return 2;
  }
  return 0xFFFFFFFF;
}

// 0: found; 1: not a SPIR-V module; 2: no matching entry point.
int findEntryPoint(const std::vector<uint32_t>& words, ShaderStage stage, const std::string& name) {
  if (words.size() < 5 || words[0] != 0x07230203u) return 1;
  size_t i = 5;
  while (i < words.size()) {
    uint32_t count = words[i] >> 16, op = words[i] & 0xFFFF;
    if (count == 0 || i + count > words.size()) return 1;
    if (op == 15 /* OpEntryPoint */ && count >= 4 && words[i + 1] == executionModel(stage)) {
      std::string entry;
      for (size_t w = i + 3; w < i + count; ++w) {
        bool end = false;
        for (int b = 0; b < 4; ++b) {
          char c = static_cast<char>((words[w] >> (8 * b)) & 0xFF);
          if (c == 0) {
            end = true;
            break;
          }
          entry.push_back(c);
        }
        if (end) break;
      }
      if (entry == name) return 0;
    }
    i += count;
  }
  return 2;
}

struct BufferRec {
  BufferDesc desc;
};

struct TextureRec {
  // For views: format, layers and mipLevels of the view; width/height at the view's first mip;
  // type, samples and usage from the parent.
  TextureDesc desc;
  bool isView = false;
  uint32_t root = 0;       // id of the texture owning the memory (itself unless a view)
  uint32_t baseLayer = 0;  // first layer and mip of the root this texture covers
  uint32_t baseMip = 0;
  uint32_t liveViews = 0;  // roots: views not destroyed yet
  bool swizzled = false;   // views: a component mapping other than the identity (sampling only)
};

struct ShaderRec {
  ShaderStage stage;
  ShaderReflection reflection;
  std::string label;
};

struct PipelineRec {
  PipelineDesc desc;
  std::vector<ShaderResource> resources;  // union of both stages, sorted by binding
  uint32_t pushConstantSize = 0;
  std::vector<SeparatePair> separatePairs;  // union of both stages
};

struct ComputePipelineRec {
  std::vector<ShaderResource> resources;
  uint32_t pushConstantSize = 0;
  std::string label;
  std::vector<SeparatePair> separatePairs;
};

bool usesBorder(const SamplerDesc& d) {
  return d.addressU == AddressMode::ClampToBorder || d.addressV == AddressMode::ClampToBorder ||
         d.addressW == AddressMode::ClampToBorder;
}
bool intBorder(BorderColor c) {
  return c == BorderColor::IntTransparentBlack || c == BorderColor::IntOpaqueBlack || c == BorderColor::IntOpaqueWhite;
}

struct AttachmentRef {
  uint32_t root = 0, layer = 0, mip = 0;  // in the root texture
};

enum class PassState { None, Active, Dropped };

class ValidatingDevice final : public Device {
 public:
  ValidatingDevice(std::unique_ptr<Device> backend, ValidationCallback onError)
      : backend_(std::move(backend)), onError_(std::move(onError)) {}

  const DeviceInfo& info() const override { return backend_->info(); }

  // ------------------------------------------------------------------------------------------
  // Resources
  // ------------------------------------------------------------------------------------------
  BufferHandle createBuffer(const BufferDesc& desc) override {
    if (desc.size == 0)
      return fail<BufferHandle>(R::E_BUFFER_SIZE_ZERO, quoted("buffer", desc.label, 0) + ": size is 0");
    if (desc.usage == 0 || (desc.usage & ~uint32_t(BufferUsage_All)))
      return fail<BufferHandle>(R::E_BUFFER_USAGE, quoted("buffer", desc.label, 0) + ": usage flags empty or unknown");
    BufferHandle h = backend_->createBuffer(desc);
    if (h) {
      BufferRec rec{desc};
      rec.desc.initialData = nullptr;
      buffers_[h.id] = std::move(rec);
    }
    return h;
  }

  TextureHandle createTexture(const TextureDesc& desc) override {
    std::string name = quoted("texture", desc.label, 0);
    if (!validFormat(desc.format))
      return fail<TextureHandle>(R::E_TEXTURE_FORMAT_UNDEFINED, name + ": format is Undefined");
    if (desc.width == 0 || desc.height == 0 || desc.depth == 0 || desc.layers == 0 || desc.mipLevels == 0) {
      std::ostringstream s;
      s << name << ": " << desc.width << "x" << desc.height << "x" << desc.depth << ", " << desc.layers << " layers, "
        << desc.mipLevels << " mips";
      return fail<TextureHandle>(R::E_TEXTURE_SIZE_ZERO, s.str());
    }
    if (desc.width > kMaxTextureSize || desc.height > kMaxTextureSize || desc.layers > kMaxTextureLayers) {
      std::ostringstream s;
      s << name << ": " << desc.width << "x" << desc.height << " with " << desc.layers
        << " layers (limits: 16384x16384, 2048 layers)";
      return fail<TextureHandle>(R::E_TEXTURE_SIZE_TOO_LARGE, s.str());
    }
    if (desc.type == TextureType::Tex2D && desc.layers != 1)
      return fail<TextureHandle>(R::E_TEXTURE_LAYERS, name + ": Tex2D with " + std::to_string(desc.layers) + " layers");
    if (desc.type == TextureType::Cube && (desc.layers != 6 || desc.width != desc.height)) {
      std::ostringstream s;
      s << name << ": Cube " << desc.width << "x" << desc.height << " with " << desc.layers << " layers";
      return fail<TextureHandle>(R::E_TEXTURE_CUBE_LAYERS, s.str());
    }
    if (const char* why = dimensionProblem(desc)) return fail<TextureHandle>(R::E_TEXTURE_DIMENSION, name + ": " + why);
    uint32_t fullChain = 1;
    for (uint32_t m = std::max({desc.width, desc.height, desc.depth}); m > 1; m >>= 1) ++fullChain;
    if (desc.mipLevels > fullChain) {
      std::ostringstream s;
      s << name << ": " << desc.mipLevels << " mips, a " << desc.width << "x" << desc.height << " texture has at most "
        << fullChain;
      return fail<TextureHandle>(R::E_TEXTURE_MIP_COUNT, s.str());
    }
    if ((desc.samples != 1 && desc.samples != 4) || desc.samples > info().caps.maxSamples) {
      std::ostringstream s;
      s << name << ": " << desc.samples << " samples (1 or 4 allowed, device maximum " << info().caps.maxSamples << ")";
      return fail<TextureHandle>(R::E_TEXTURE_MSAA_SAMPLES, s.str());
    }
    if (desc.usage == 0 ||
        (desc.usage & ~uint32_t(TextureUsage_Sampled | TextureUsage_RenderTarget | TextureUsage_Storage)))
      return fail<TextureHandle>(R::E_TEXTURE_USAGE, name + ": usage flags empty or unknown");
    if (desc.samples > 1) {
      const char* why = nullptr;
      if (desc.type != TextureType::Tex2D)
        why = "it is not Tex2D";
      else if (desc.mipLevels != 1)
        why = "it has mips";
      else if ((desc.usage & TextureUsage_Storage) && !info().caps.storageMultisample)
        why = "it has Storage usage (the device has no Capabilities::storageMultisample)";
      else if (desc.initialData)
        why = "it has initial data";
      if (why) return fail<TextureHandle>(R::E_TEXTURE_MSAA_INVALID, name + ": multisampled but " + why);
    }
    if ((desc.usage & TextureUsage_Storage) &&
        (isDepthFormat(desc.format) || formatInfo(desc.format).kind == FormatKind::Srgb))
      return fail<TextureHandle>(R::E_TEXTURE_USAGE,
                                 name + ": Storage usage on format " + fmt(desc.format) + " (not storable)");
    TextureHandle h = backend_->createTexture(desc);
    if (h) {
      TextureRec rec;
      rec.desc = desc;
      rec.desc.initialData = nullptr;
      rec.root = h.id;
      textures_[h.id] = std::move(rec);
    }
    return h;
  }

  // Null when the texture's extent fits its type.
  static const char* dimensionProblem(const TextureDesc& d) {
    if (d.type == TextureType::Tex1D && d.height != 1) return "Tex1D with height != 1";
    if (d.type == TextureType::Tex3D && d.layers != 1) return "Tex3D with layers != 1";
    if (d.type == TextureType::Tex3D && std::max({d.width, d.height, d.depth}) > kMaxTexture3DSize)
      return "Tex3D with a side above 2048";
    if (d.type != TextureType::Tex3D && d.depth != 1) return "depth != 1 on a texture that is not Tex3D";
    return nullptr;
  }

  // Layers a transfer or attachment may address at `mip`: a Tex3D's slices, else array layers.
  static uint32_t layersAt(const TextureDesc& d, uint32_t mip) {
    return d.type == TextureType::Tex3D ? std::max(1u, d.depth >> mip) : d.layers;
  }

  TextureHandle createTextureView(const TextureViewDesc& desc) override {
    std::string name = quoted("texture view", desc.label, 0);
    const TextureRec* parent = texture(desc.parent);
    if (!parent)
      return fail<TextureHandle>(R::E_VIEW_PARENT_INVALID,
                                 name + ": parent is " + (desc.parent ? "destroyed" : "null"));
    std::string parentName = textureName(desc.parent);
    if (parent->isView)
      return fail<TextureHandle>(R::E_VIEW_PARENT_INVALID, name + ": parent " + parentName + " is itself a view");
    Format pf = parent->desc.format;
    Format vf = desc.format == Format::Undefined ? pf : desc.format;
    if (!validFormat(vf)) return fail<TextureHandle>(R::E_VIEW_SIZE_CLASS, name + ": unknown format");
    if ((isDepthFormat(pf) || isDepthFormat(vf)) && vf != pf)
      return fail<TextureHandle>(R::E_VIEW_DEPTH, name + ": " + fmt(vf) + " view of " + parentName + " (" + fmt(pf) +
                                                      "); depth formats cannot be reinterpreted");
    if (formatInfo(vf).bytesPerTexel != formatInfo(pf).bytesPerTexel) {
      std::ostringstream s;
      s << name << ": " << fmt(vf) << " (" << formatInfo(vf).bytesPerTexel << " bytes) view of " << parentName << " ("
        << fmt(pf) << ", " << formatInfo(pf).bytesPerTexel << " bytes)";
      return fail<TextureHandle>(R::E_VIEW_SIZE_CLASS, s.str());
    }
    const TextureDesc& pd = parent->desc;
    uint32_t layerCount =
        desc.layerCount ? desc.layerCount : (desc.baseLayer < pd.layers ? pd.layers - desc.baseLayer : 0);
    uint32_t mipCount = desc.mipCount ? desc.mipCount : (desc.baseMip < pd.mipLevels ? pd.mipLevels - desc.baseMip : 0);
    if (desc.baseLayer >= pd.layers || layerCount == 0 || uint64_t(desc.baseLayer) + layerCount > pd.layers ||
        desc.baseMip >= pd.mipLevels || mipCount == 0 || uint64_t(desc.baseMip) + mipCount > pd.mipLevels) {
      std::ostringstream s;
      s << name << ": layers [" << desc.baseLayer << ", +" << desc.layerCount << "), mips [" << desc.baseMip << ", +"
        << desc.mipCount << ") outside " << parentName << " (" << pd.layers << " layers, " << pd.mipLevels << " mips)";
      return fail<TextureHandle>(R::E_VIEW_RANGE, s.str());
    }
    for (Swizzle c : {desc.swizzle.r, desc.swizzle.g, desc.swizzle.b, desc.swizzle.a})
      if (c > Swizzle::Alpha)
        return fail<TextureHandle>(R::E_VIEW_SWIZZLE, name + ": swizzle value " + std::to_string(int(c)) + " names no component");
    TextureHandle h = backend_->createTextureView(desc);
    if (h) {
      TextureRec rec;
      rec.desc = pd;
      rec.desc.format = vf;
      rec.desc.layers = layerCount;
      rec.desc.mipLevels = mipCount;
      rec.desc.width = mipSize(pd.width, desc.baseMip);
      rec.desc.height = mipSize(pd.height, desc.baseMip);
      rec.desc.label = desc.label;
      rec.isView = true;
      rec.swizzled = !desc.swizzle.isIdentity();
      rec.root = desc.parent.id;
      rec.baseLayer = desc.baseLayer;
      rec.baseMip = desc.baseMip;
      textures_[desc.parent.id].liveViews++;
      textures_[h.id] = std::move(rec);
    }
    return h;
  }

  SamplerHandle createSampler(const SamplerDesc& desc) override {
    const std::string name = quoted("sampler", desc.label, 0);
    if (!std::isfinite(desc.minLod) || !std::isfinite(desc.maxLod) || !std::isfinite(desc.mipLodBias))
      return fail<SamplerHandle>(R::E_SAMPLER_LOD, name + ": a level-of-detail clamp or bias that is not finite");
    if (desc.minLod > desc.maxLod)
      return fail<SamplerHandle>(R::E_SAMPLER_LOD, name + ": minLod " + std::to_string(desc.minLod) + " above maxLod " +
                                                       std::to_string(desc.maxLod));
    if (std::fabs(desc.mipLodBias) > info().caps.maxSamplerLodBias)
      return fail<SamplerHandle>(R::E_SAMPLER_LOD, name + ": mipLodBias " + std::to_string(desc.mipLodBias) +
                                                       " beyond the device's " + std::to_string(info().caps.maxSamplerLodBias));
    SamplerHandle h = backend_->createSampler(desc);
    if (h) samplers_[h.id] = desc;
    return h;
  }

  ShaderHandle createShader(const ShaderDesc& desc) override {
    std::string name = quoted(std::string(stageName(desc.stage)) + " shader", desc.label, 0);
    if (desc.spirv.empty()) return fail<ShaderHandle>(R::E_SHADER_SPIRV_EMPTY, name + ": no SPIR-V");
    int entry = findEntryPoint(desc.spirv, desc.stage, desc.entryPoint);
    if (entry == 1) return fail<ShaderHandle>(R::E_SHADER_REFLECTION, name + ": not a SPIR-V module");
    if (entry == 2)
      return fail<ShaderHandle>(R::E_SHADER_ENTRY_POINT, name + ": no " + stageName(desc.stage) +
                                                             " entry point named '" + desc.entryPoint + "'");
    ShaderRec rec{desc.stage, {}, desc.label};
    std::string error;
    if (!reflectSpirv(desc.spirv, desc.stage, &rec.reflection, &error))
      return fail<ShaderHandle>(R::E_SHADER_REFLECTION, name + ": " + error);
    for (const ShaderResource& r : rec.reflection.resources)
      if (r.binding >= kMaxBindings)
        return fail<ShaderHandle>(R::E_SHADER_REFLECTION,
                                  name + ": binding " + std::to_string(r.binding) + " (" + r.name + ") >= 16");
    for (const ShaderResource& r : rec.reflection.resources)
      if (r.kind == BindingKind::SeparateSampler && r.arraySize > 1 && !backend_->info().caps.separateSamplerArrays)
        return fail<ShaderHandle>(R::E_SHADER_SAMPLER_ARRAY, name + ": '" + r.name + "' is an array of " +
                                                                 std::to_string(r.arraySize) + " separate samplers, which " +
                                                                 backend_->info().backend + " cannot run");
    if (rec.reflection.pushConstantSize > kMaxPushConstantBytes)
      return fail<ShaderHandle>(R::E_SHADER_REFLECTION, name + ": push-constant block of " +
                                                            std::to_string(rec.reflection.pushConstantSize) +
                                                            " bytes (at most 128)");
    ShaderHandle h = backend_->createShader(desc);
    if (h) shaders_[h.id] = std::move(rec);
    return h;
  }

  PipelineHandle createPipeline(const PipelineDesc& desc) override {
    std::string name = quoted("pipeline", desc.label, 0);
    if (!desc.vertexShader || !desc.fragmentShader)
      return fail<PipelineHandle>(R::E_PIPELINE_SHADER_MISSING,
                                  name + ": " + (!desc.vertexShader ? "vertex" : "fragment") + " shader is null");
    const ShaderRec* vs = shader(desc.vertexShader);
    const ShaderRec* fs = shader(desc.fragmentShader);
    if (!vs) return fail<PipelineHandle>(R::E_HANDLE_INVALID, name + ": vertex shader was destroyed");
    if (!fs) return fail<PipelineHandle>(R::E_HANDLE_INVALID, name + ": fragment shader was destroyed");
    if (vs->stage != ShaderStage::Vertex)
      return fail<PipelineHandle>(
          R::E_PIPELINE_SHADER_STAGE,
          name + ": vertex shader " + shaderName(desc.vertexShader) + " is a " + stageName(vs->stage) + " shader");
    if (fs->stage != ShaderStage::Fragment)
      return fail<PipelineHandle>(
          R::E_PIPELINE_SHADER_STAGE,
          name + ": fragment shader " + shaderName(desc.fragmentShader) + " is a " + stageName(fs->stage) + " shader");
    // The optional stages: each of its own kind; tessellation comes as a pair drawn as patches.
    struct Optional {
      ShaderHandle handle;
      ShaderStage stage;
    };
    std::vector<std::pair<ShaderHandle, const ShaderRec*>> stages{{desc.vertexShader, vs}};
    for (const Optional& o : {Optional{desc.tessControlShader, ShaderStage::TessControl},
                              Optional{desc.tessEvaluationShader, ShaderStage::TessEvaluation},
                              Optional{desc.geometryShader, ShaderStage::Geometry}}) {
      if (!o.handle) continue;
      const ShaderRec* rec = shader(o.handle);
      if (!rec) return fail<PipelineHandle>(R::E_HANDLE_INVALID, name + ": " + stageName(o.stage) + " shader was destroyed");
      if (rec->stage != o.stage)
        return fail<PipelineHandle>(R::E_PIPELINE_SHADER_STAGE, name + ": " + stageName(o.stage) + " shader " +
                                                                    shaderName(o.handle) + " is a " + stageName(rec->stage) + " shader");
      stages.push_back({o.handle, rec});
    }
    stages.push_back({desc.fragmentShader, fs});
    const bool tessellation = desc.tessControlShader || desc.tessEvaluationShader;
    if (tessellation && (!desc.tessControlShader || !desc.tessEvaluationShader || desc.topology != PrimitiveTopology::Patches ||
                         desc.patchControlPoints < 1 || desc.patchControlPoints > 32))
      return fail<PipelineHandle>(R::E_PIPELINE_SHADER_STAGE,
                                  name + ": tessellation needs both its shaders, Patches topology and 1..32 patchControlPoints");
    if (!tessellation && desc.topology == PrimitiveTopology::Patches)
      return fail<PipelineHandle>(R::E_PIPELINE_SHADER_STAGE, name + ": Patches topology without tessellation shaders");
    const RasterState& raster = desc.raster;
    if (desc.topology > PrimitiveTopology::TriangleStripWithAdjacency || raster.polygonMode > PolygonMode::Point)
      return fail<PipelineHandle>(R::E_PIPELINE_RASTER_STATE, name + ": topology " + std::to_string(int(desc.topology)) +
                                                                  " or polygon mode " + std::to_string(int(raster.polygonMode)) +
                                                                  " of no known value");
    const DepthBias& bias = raster.depthBias;
    if (!std::isfinite(bias.constantFactor) || !std::isfinite(bias.slopeFactor) || !std::isfinite(bias.clamp))
      return fail<PipelineHandle>(R::E_PIPELINE_RASTER_STATE, name + ": depth bias factor or clamp not finite");
    const bool adjacency = desc.topology >= PrimitiveTopology::LinesWithAdjacency;
    for (const auto& [needed, feature] : {std::pair{raster.polygonMode != PolygonMode::Fill, "fillModeNonSolid"},
                                          std::pair{raster.depthClampEnabled, "depthClamp"},
                                          std::pair{raster.provokingVertex == ProvokingVertex::Last, "provokingVertexLast"},
                                          std::pair{bias.clamp != 0, "depthBiasClamp"},
                                          std::pair{adjacency, "geometryShader"}})
      if (needed && std::find(info().features.begin(), info().features.end(), feature) == info().features.end())
        return fail<PipelineHandle>(R::E_PIPELINE_DEVICE_FEATURE,
                                    name + ": the device lacks " + feature + ", which this pipeline's state needs");
    PipelineRec rec;
    rec.desc = desc;
    std::vector<const ShaderReflection*> reflections;
    for (const auto& [handle, stage] : stages) {
      reflections.push_back(&stage->reflection);
      rec.pushConstantSize = std::max(rec.pushConstantSize, stage->reflection.pushConstantSize);
      for (const ShaderResource& r : stage->reflection.resources) {
        auto it = std::find_if(rec.resources.begin(), rec.resources.end(),
                               [&](const ShaderResource& o) { return o.binding == r.binding; });
        if (it == rec.resources.end()) {
          rec.resources.push_back(r);
        } else if (it->kind != r.kind) {
          return fail<PipelineHandle>(R::E_PIPELINE_BINDING_CONFLICT,
                                      name + ": binding " + std::to_string(r.binding) + " is " + kindName(it->kind) +
                                          " in one stage but " + kindName(r.kind) + " in " + shaderName(handle));
        } else if (it->arraySize != r.arraySize) {
          return fail<PipelineHandle>(R::E_PIPELINE_ARRAY_SIZE,
                                      name + ": binding " + std::to_string(r.binding) + " is an array of " +
                                          std::to_string(it->arraySize) + " in one stage but of " +
                                          std::to_string(r.arraySize) + " in " + shaderName(handle));
        }
      }
    }
    std::sort(rec.resources.begin(), rec.resources.end(),
              [](const ShaderResource& a, const ShaderResource& b) { return a.binding < b.binding; });
    rec.separatePairs = mergeSeparatePairs(reflections);
    if (rec.separatePairs.size() > kMaxSeparatePairs)
      return fail<PipelineHandle>(R::E_PIPELINE_SEPARATE_PAIRS,
                                  name + ": the shaders combine " + std::to_string(rec.separatePairs.size()) +
                                      " separate texture/sampler pairs (at most " +
                                      std::to_string(kMaxSeparatePairs) + ")");

    if (desc.colorTargetCount > kMaxColorTargets)
      return fail<PipelineHandle>(R::E_PIPELINE_COLOR_TARGET_COUNT,
                                  name + ": " + std::to_string(desc.colorTargetCount) + " colour targets (at most 4)");
    bool anyColor = false;
    for (uint32_t i = 0; i < desc.colorTargetCount; ++i) {
      const ColorTargetState& t = desc.colorTargets[i];
      if (t.format == Format::Undefined) continue;
      anyColor = true;
      if (!validFormat(t.format) || isDepthFormat(t.format))
        return fail<PipelineHandle>(R::E_PIPELINE_FORMAT,
                                    name + ": colour target " + std::to_string(i) + " has format " + fmt(t.format));
      if (t.blend.enabled && isIntegerFormat(t.format))
        return fail<PipelineHandle>(R::E_PIPELINE_BLEND, name + ": blending on colour target " + std::to_string(i) +
                                                             " of integer format " + fmt(t.format));
    }
    if (desc.depthStencilFormat != Format::Undefined && !isDepthFormat(desc.depthStencilFormat))
      return fail<PipelineHandle>(R::E_PIPELINE_FORMAT, name + ": depthStencilFormat " + fmt(desc.depthStencilFormat) +
                                                            " is not a depth format");
    if (!anyColor && desc.depthStencilFormat == Format::Undefined)
      return fail<PipelineHandle>(R::E_PIPELINE_COLOR_TARGET_COUNT,
                                  name + ": no colour target and no depth-stencil format");
    const DepthStencilState& ds = desc.depthStencil;
    bool depthUsed = ds.depthCompare != CompareOp::Always || ds.depthWrite;
    if ((depthUsed || ds.stencilEnabled) && desc.depthStencilFormat == Format::Undefined)
      return fail<PipelineHandle>(R::E_PIPELINE_DEPTH_STATE,
                                  name + ": depth or stencil state enabled without a depthStencilFormat");
    if (ds.stencilEnabled && !hasStencil(desc.depthStencilFormat))
      return fail<PipelineHandle>(R::E_PIPELINE_DEPTH_STATE, name + ": stencil enabled but depthStencilFormat " +
                                                                 fmt(desc.depthStencilFormat) + " has no stencil");
    if ((desc.samples != 1 && desc.samples != 4) || desc.samples > info().caps.maxSamples)
      return fail<PipelineHandle>(R::E_PIPELINE_SAMPLES, name + ": " + std::to_string(desc.samples) + " samples");

    if (desc.attributeCount > kMaxVertexAttributes)
      return fail<PipelineHandle>(R::E_PIPELINE_ATTRIBUTE,
                                  name + ": " + std::to_string(desc.attributeCount) + " attributes (at most " +
                                      std::to_string(kMaxVertexAttributes) + ")");
    std::vector<uint32_t> locations;
    for (uint32_t i = 0; i < desc.attributeCount; ++i) {
      const VertexAttribute& a = desc.attributes[i];
      std::string an = name + ": attribute " + std::to_string(i) + " (location " + std::to_string(a.location) + ")";
      if (a.location >= kMaxVertexLocations)
        return fail<PipelineHandle>(R::E_PIPELINE_ATTRIBUTE, an + ": location >= 16");
      for (uint32_t l = a.location; l < a.location + vertexFormatLocations(a.format); ++l) {
        if (std::find(locations.begin(), locations.end(), l) != locations.end())
          return fail<PipelineHandle>(R::E_PIPELINE_ATTRIBUTE, an + ": location " + std::to_string(l) + " used twice");
        locations.push_back(l);
      }
      if (a.bufferSlot >= kMaxVertexBuffers)
        return fail<PipelineHandle>(R::E_PIPELINE_ATTRIBUTE,
                                    an + ": buffer slot " + std::to_string(a.bufferSlot) + " >= 4");
      if (vertexFormatSize(a.format) == 0)
        return fail<PipelineHandle>(R::E_PIPELINE_ATTRIBUTE, an + ": unknown format");
    }
    for (uint32_t i = 0; i < desc.attributeCount; ++i)
      if (desc.attributes[i].format >= VertexFormat::Double && !info().caps.doubleVertexFormats)
        return fail<PipelineHandle>(R::E_PIPELINE_DEVICE_FEATURE, name + ": attribute " + std::to_string(i) +
                                                                      ": the device has no 64-bit vertex formats "
                                                                      "(Capabilities::doubleVertexFormats)");
    for (uint32_t loc : vs->reflection.inputLocations)
      if (std::find(locations.begin(), locations.end(), loc) == locations.end())
        return fail<PipelineHandle>(R::E_PIPELINE_ATTRIBUTE, name + ": vertex shader " + shaderName(desc.vertexShader) +
                                                                 " reads location " + std::to_string(loc) +
                                                                 " but no attribute supplies it");

    PipelineHandle h = backend_->createPipeline(desc);
    if (h) pipelines_[h.id] = std::move(rec);
    return h;
  }

  ComputePipelineHandle createComputePipeline(const ComputePipelineDesc& desc) override {
    std::string name = quoted("compute pipeline", desc.label, 0);
    if (!desc.computeShader)
      return fail<ComputePipelineHandle>(R::E_PIPELINE_SHADER_MISSING, name + ": compute shader is null");
    const ShaderRec* cs = shader(desc.computeShader);
    if (!cs) return fail<ComputePipelineHandle>(R::E_HANDLE_INVALID, name + ": compute shader was destroyed");
    if (cs->stage != ShaderStage::Compute)
      return fail<ComputePipelineHandle>(R::E_PIPELINE_SHADER_STAGE, name + ": " + shaderName(desc.computeShader) +
                                                                         " is a " + stageName(cs->stage) + " shader");
    const Capabilities& caps = info().caps;
    const uint32_t required = desc.requiredSubgroupSize;
    if ((required || desc.fullSubgroups || desc.varyingSubgroupSize) && !caps.subgroupSizeControl)
      return fail<ComputePipelineHandle>(R::E_PIPELINE_SUBGROUP_SIZE, name + ": subgroup size control, which " + info().renderer + " on " +
                                                                           info().backend + " lacks");
    if (required && ((required & (required - 1)) || required < caps.minSubgroupSize || required > caps.maxSubgroupSize))
      return fail<ComputePipelineHandle>(R::E_PIPELINE_SUBGROUP_SIZE, name + ": requiredSubgroupSize " + std::to_string(required) +
                                                                           " is not a power of two in [" + std::to_string(caps.minSubgroupSize) +
                                                                           ", " + std::to_string(caps.maxSubgroupSize) + "]");
    const uint32_t fullSize = required ? required : caps.maxSubgroupSize;
    if (desc.fullSubgroups && fullSize && cs->reflection.localSize[0] % fullSize)
      return fail<ComputePipelineHandle>(R::E_PIPELINE_SUBGROUP_SIZE, name + ": fullSubgroups with local size x " +
                                                                           std::to_string(cs->reflection.localSize[0]) +
                                                                           ", not a multiple of the subgroup size " + std::to_string(fullSize));
    ComputePipelineHandle h = backend_->createComputePipeline(desc);
    if (h)
      computePipelines_[h.id] =
          ComputePipelineRec{cs->reflection.resources, cs->reflection.pushConstantSize, desc.label,
                             cs->reflection.separatePairs};
    return h;
  }

  void destroy(BufferHandle h) override {
    if (!h) return;
    if (!buffers_.count(h.id)) return (void)report(R::E_HANDLE_INVALID, "destroy: buffer handle already destroyed");
    buffers_.erase(h.id);
    backend_->destroy(h);
  }
  void destroy(TextureHandle h) override {
    if (!h) return;
    auto it = textures_.find(h.id);
    if (it == textures_.end()) return (void)report(R::E_HANDLE_INVALID, "destroy: texture handle already destroyed");
    if (it->second.liveViews > 0)
      return (void)report(R::E_TEXTURE_DESTROY_WITH_VIEWS, "destroy: " + textureName(h) + " still has " +
                                                               std::to_string(it->second.liveViews) + " live view(s)");
    if (it->second.isView) {
      auto parent = textures_.find(it->second.root);
      if (parent != textures_.end() && parent->second.liveViews > 0) parent->second.liveViews--;
    }
    textures_.erase(it);
    backend_->destroy(h);
  }
  void destroy(SamplerHandle h) override {
    if (!h) return;
    if (!samplers_.erase(h.id)) return (void)report(R::E_HANDLE_INVALID, "destroy: sampler handle already destroyed");
    backend_->destroy(h);
  }
  void destroy(ShaderHandle h) override {
    if (!h) return;
    if (!shaders_.erase(h.id)) return (void)report(R::E_HANDLE_INVALID, "destroy: shader handle already destroyed");
    backend_->destroy(h);
  }
  void destroy(PipelineHandle h) override {
    if (!h) return;
    if (!pipelines_.erase(h.id)) return (void)report(R::E_HANDLE_INVALID, "destroy: pipeline handle already destroyed");
    backend_->destroy(h);
  }
  void destroy(ComputePipelineHandle h) override {
    if (!h) return;
    if (!computePipelines_.erase(h.id))
      return (void)report(R::E_HANDLE_INVALID, "destroy: compute pipeline handle already destroyed");
    backend_->destroy(h);
  }

  const BufferDesc* describe(BufferHandle h) const override { return backend_->describe(h); }
  const TextureDesc* describe(TextureHandle h) const override { return backend_->describe(h); }

  // ------------------------------------------------------------------------------------------
  // Transfers
  // ------------------------------------------------------------------------------------------
  void writeBuffer(BufferHandle h, size_t offset, const void* data, size_t size) override {
    if (!transferAllowed("writeBuffer")) return;
    const BufferRec* b = liveBuffer(h, "writeBuffer");
    if (!b) return;
    if (!data || size == 0)
      return (void)report(R::E_TRANSFER_EMPTY, "writeBuffer to " + bufferName(h) + ": null data or size 0");
    if (offset > b->desc.size || size > b->desc.size - offset)
      return (void)report(R::E_WRITE_OUT_OF_RANGE, "writeBuffer to " + bufferName(h) + ": " + range(offset, size) +
                                                       " past its size " + std::to_string(b->desc.size));
    backend_->writeBuffer(h, offset, data, size);
  }

  void writeTexture(TextureHandle h, uint32_t layer, uint32_t mip, const void* data) override {
    if (!transferAllowed("writeTexture")) return;
    const TextureRec* t = liveTexture(h, "writeTexture");
    if (!t) return;
    if (!data) return (void)report(R::E_TRANSFER_EMPTY, "writeTexture to " + textureName(h) + ": null data");
    if (t->desc.samples > 1) return (void)report(R::E_TRANSFER_MSAA, "writeTexture to multisampled " + textureName(h));
    if (!subresourceOk(*t, layer, mip, "writeTexture", h)) return;
    backend_->writeTexture(h, layer, mip, data);
  }

  std::vector<uint8_t> readBuffer(BufferHandle h, size_t offset, size_t size) override {
    if (!transferAllowed("readBuffer")) return {};
    const BufferRec* b = liveBuffer(h, "readBuffer");
    if (!b) return {};
    if (size == 0) {
      report(R::E_TRANSFER_EMPTY, "readBuffer of " + bufferName(h) + ": size 0");
      return {};
    }
    if (offset > b->desc.size || size > b->desc.size - offset) {
      report(R::E_READ_OUT_OF_RANGE, "readBuffer of " + bufferName(h) + ": " + range(offset, size) + " past its size " +
                                         std::to_string(b->desc.size));
      return {};
    }
    return backend_->readBuffer(h, offset, size);
  }

  std::vector<uint8_t> readTexture(TextureHandle h, const ReadbackRegion& region) override {
    if (!transferAllowed("readTexture")) return {};
    const TextureRec* t = liveTexture(h, "readTexture");
    if (!t) return {};
    if (t->desc.samples > 1) {
      report(R::E_READBACK_MSAA, "readTexture of multisampled " + textureName(h) + ": resolve it first");
      return {};
    }
    Format f = t->desc.format;
    const char* aspectProblem = nullptr;
    if (region.aspect == TextureAspect::Color && isDepthFormat(f)) aspectProblem = "Color aspect of a depth format";
    if (region.aspect == TextureAspect::Depth && !isDepthFormat(f)) aspectProblem = "Depth aspect of a colour format";
    if (region.aspect == TextureAspect::Stencil && !hasStencil(f))
      aspectProblem = "Stencil aspect of a format without stencil";
    if (static_cast<uint32_t>(region.aspect) > static_cast<uint32_t>(TextureAspect::Stencil))
      aspectProblem = "unknown aspect";
    if (aspectProblem) {
      report(R::E_READBACK_ASPECT,
             std::string("readTexture of ") + textureName(h) + " (" + fmt(f) + "): " + aspectProblem);
      return {};
    }
    if (!subresourceOk(*t, region.layer, region.mip, "readTexture", h)) return {};
    return backend_->readTexture(h, region);
  }

  void copyTexture(TextureHandle src, TextureHandle dst, const ReadbackRegion& srcRegion,
                   const ReadbackRegion& dstRegion) override {
    if (!transferAllowed("copyTexture")) return;
    const TextureRec* s = liveTexture(src, "copyTexture source");
    if (!s) return;
    const TextureRec* d = liveTexture(dst, "copyTexture destination");
    if (!d) return;
    std::string what = "copyTexture " + textureName(src) + " -> " + textureName(dst);
    if (s->desc.samples > 1 || d->desc.samples > 1)
      return (void)report(R::E_TRANSFER_MSAA, what + ": multisampled textures cannot be copied");
    Format sf = s->desc.format, df = d->desc.format;
    if ((isDepthFormat(sf) || isDepthFormat(df)) && sf != df)
      return (void)report(R::E_COPY_DEPTH, what + ": " + fmt(sf) + " -> " + fmt(df));
    if (formatInfo(sf).bytesPerTexel != formatInfo(df).bytesPerTexel)
      return (void)report(R::E_COPY_SIZE_CLASS, what + ": " + fmt(sf) + " -> " + fmt(df));
    if (!subresourceOk(*s, srcRegion.layer, srcRegion.mip, "copyTexture source", src)) return;
    if (!subresourceOk(*d, dstRegion.layer, dstRegion.mip, "copyTexture destination", dst)) return;
    uint32_t sw = mipSize(s->desc.width, srcRegion.mip), sh = mipSize(s->desc.height, srcRegion.mip);
    uint32_t dw = mipSize(d->desc.width, dstRegion.mip), dh = mipSize(d->desc.height, dstRegion.mip);
    if (sw != dw || sh != dh) {
      std::ostringstream m;
      m << what << ": " << sw << "x" << sh << " -> " << dw << "x" << dh;
      return (void)report(R::E_COPY_SIZE_MISMATCH, m.str());
    }
    AttachmentRef a = rootRef(*s, srcRegion.layer, srcRegion.mip), b = rootRef(*d, dstRegion.layer, dstRegion.mip);
    if (a.root == b.root && a.layer == b.layer && a.mip == b.mip)
      return (void)report(R::E_COPY_OVERLAP, what + ": source and destination are the same layer and mip");
    backend_->copyTexture(src, dst, srcRegion, dstRegion);
  }

  void copyBuffer(BufferHandle src, size_t srcOffset, BufferHandle dst, size_t dstOffset, size_t size) override {
    if (!transferAllowed("copyBuffer")) return;
    const BufferRec* s = liveBuffer(src, "copyBuffer source");
    if (!s) return;
    const BufferRec* d = liveBuffer(dst, "copyBuffer destination");
    if (!d) return;
    std::string what = "copyBuffer " + bufferName(src) + " -> " + bufferName(dst);
    if (size == 0) return (void)report(R::E_TRANSFER_EMPTY, what + ": size 0");
    if (srcOffset > s->desc.size || size > s->desc.size - srcOffset)
      return (void)report(R::E_COPY_OUT_OF_RANGE, what + ": source " + range(srcOffset, size) + " past its size " +
                                                      std::to_string(s->desc.size));
    if (dstOffset > d->desc.size || size > d->desc.size - dstOffset)
      return (void)report(R::E_COPY_OUT_OF_RANGE, what + ": destination " + range(dstOffset, size) + " past its size " +
                                                      std::to_string(d->desc.size));
    if (src == dst && srcOffset < dstOffset + size && dstOffset < srcOffset + size)
      return (void)report(R::E_COPY_OVERLAP,
                          what + ": ranges " + range(srcOffset, size) + " and " + range(dstOffset, size) + " overlap");
    backend_->copyBuffer(src, srcOffset, dst, dstOffset, size);
  }

  // ------------------------------------------------------------------------------------------
  // Passes
  // ------------------------------------------------------------------------------------------
  void beginPass(const PassDesc& desc) override {
    if (pass_ != PassState::None)
      return (void)report(R::E_PASS_NESTED,
                          "beginPass " + passName(desc.label) + " inside pass " + passName(pass_label_));
    pass_label_ = desc.label;
    if (!validatePass(desc)) {
      pass_ = PassState::Dropped;
      return;
    }
    pass_ = PassState::Active;
    pipeline_ = {};
    backend_->beginPass(desc);
  }

  void endPass() override {
    if (pass_ == PassState::None) return (void)report(R::E_PASS_NOT_BEGUN, "endPass without beginPass");
    bool forward = pass_ == PassState::Active;
    pass_ = PassState::None;
    pipeline_ = {};
    pass_color_.fill(Format::Undefined);
    pass_depth_ = Format::Undefined;
    pass_refs_.clear();
    if (forward) backend_->endPass();
  }

  void setPipeline(PipelineHandle h) override {
    if (!inPassCommand("setPipeline")) return;
    if (!pipeline(h))
      return (void)report(R::E_HANDLE_INVALID,
                          "setPipeline: pipeline handle is " + std::string(h ? "destroyed" : "null"));
    pipeline_ = h;
    backend_->setPipeline(h);
  }

  void setViewport(const Viewport& vp) override {
    if (!inPassCommand("setViewport")) return;
    bool finite = std::isfinite(vp.x) && std::isfinite(vp.y) && std::isfinite(vp.width) && std::isfinite(vp.height) &&
                  std::isfinite(vp.minDepth) && std::isfinite(vp.maxDepth);
    if (!finite || vp.width < 0 || vp.height < 0 || vp.minDepth < 0 || vp.minDepth > 1 || vp.maxDepth < 0 ||
        vp.maxDepth > 1) {
      std::ostringstream s;
      s << "setViewport in pass " << passName(pass_label_) << ": (" << vp.x << ", " << vp.y << ", " << vp.width << "x"
        << vp.height << ", depth " << vp.minDepth << ".." << vp.maxDepth << ")";
      return (void)report(R::E_VIEWPORT_INVALID, s.str());
    }
    backend_->setViewport(vp);
  }

  void setScissor(const Rect& r) override {
    if (!inPassCommand("setScissor")) return;
    if (r.x < 0 || r.y < 0) {
      std::ostringstream s;
      s << "setScissor in pass " << passName(pass_label_) << ": origin (" << r.x << ", " << r.y << ") is negative";
      return (void)report(R::E_SCISSOR_INVALID, s.str());
    }
    backend_->setScissor(r);
  }

  void setStencilReference(uint8_t ref) override {
    if (pass_ == PassState::Dropped) return;
    backend_->setStencilReference(ref);
  }
  void setBlendConstant(const std::array<float, 4>& c) override {
    if (pass_ == PassState::Dropped) return;
    backend_->setBlendConstant(c);
  }

  void setVertexBuffer(uint32_t slot, BufferHandle h, size_t offset) override {
    if (pass_ == PassState::Dropped) return;
    if (slot >= kMaxVertexBuffers)
      return (void)report(R::E_VERTEX_BUFFER_SLOT, "setVertexBuffer: slot " + std::to_string(slot) + " >= 4");
    const BufferRec* b = liveBuffer(h, "setVertexBuffer");
    if (!b) return;
    if (!(b->desc.usage & BufferUsage_Vertex))
      return (void)report(R::E_BUFFER_USAGE, "setVertexBuffer: " + bufferName(h) + " lacks BufferUsage_Vertex");
    if (offset >= b->desc.size)
      return (void)report(R::E_BUFFER_OFFSET, "setVertexBuffer: offset " + std::to_string(offset) +
                                                  " past the end of " + bufferName(h) + " (" +
                                                  std::to_string(b->desc.size) + " bytes)");
    vertexBuffers_[slot] = VertexBinding{h, offset};
    backend_->setVertexBuffer(slot, h, offset);
  }

  void setIndexBuffer(BufferHandle h, IndexType type, size_t offset) override {
    if (pass_ == PassState::Dropped) return;
    const BufferRec* b = liveBuffer(h, "setIndexBuffer");
    if (!b) return;
    if (!(b->desc.usage & BufferUsage_Index))
      return (void)report(R::E_BUFFER_USAGE, "setIndexBuffer: " + bufferName(h) + " lacks BufferUsage_Index");
    size_t indexSize = type == IndexType::UInt16 ? 2 : 4;
    if (offset >= b->desc.size || offset % indexSize != 0)
      return (void)report(R::E_BUFFER_OFFSET, "setIndexBuffer: offset " + std::to_string(offset) + " in " +
                                                  bufferName(h) + " (" + std::to_string(b->desc.size) +
                                                  " bytes) is past the end or not a multiple of the index size");
    indexBuffer_ = IndexBinding{h, offset, type};
    backend_->setIndexBuffer(h, type, offset);
  }

  void draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) override {
    if (!inPassCommand("draw")) return;
    const PipelineRec* p = drawPipeline("draw");
    if (!p) return;
    if (!vertexInputsOk(*p, "draw", vertexCount, instanceCount, firstVertex, firstInstance, true)) return;
    if (!bindingsOk(p->resources, p->separatePairs, p->pushConstantSize, "draw with " + pipelineName(pipeline_))) return;
    backend_->draw(vertexCount, instanceCount, firstVertex, firstInstance);
  }

  void drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                   uint32_t firstInstance) override {
    if (!inPassCommand("drawIndexed")) return;
    const PipelineRec* p = drawPipeline("drawIndexed");
    if (!p) return;
    if (!vertexInputsOk(*p, "drawIndexed", 0, instanceCount, 0, firstInstance, false)) return;
    if (!indexBuffer_)
      return (void)report(R::E_INDEX_BUFFER_MISSING,
                          "drawIndexed with " + pipelineName(pipeline_) + ": no index buffer set");
    const BufferRec* ib = buffer(indexBuffer_->buffer);
    if (!ib) return (void)report(R::E_HANDLE_INVALID, "drawIndexed: the index buffer was destroyed");
    uint64_t indexSize = indexBuffer_->type == IndexType::UInt16 ? 2 : 4;
    uint64_t end = indexBuffer_->offset + (uint64_t(firstIndex) + indexCount) * indexSize;
    if (indexCount > 0 && end > ib->desc.size) {
      std::ostringstream s;
      s << "drawIndexed: indices [" << firstIndex << ", " << firstIndex + uint64_t(indexCount) << ") end at byte "
        << end << " of " << bufferName(indexBuffer_->buffer) << " (" << ib->desc.size << " bytes)";
      return (void)report(R::E_DRAW_INDEX_RANGE, s.str());
    }
    if (!bindingsOk(p->resources, p->separatePairs, p->pushConstantSize, "drawIndexed with " + pipelineName(pipeline_))) return;
    backend_->drawIndexed(indexCount, instanceCount, firstIndex, vertexOffset, firstInstance);
  }

  // ------------------------------------------------------------------------------------------
  // Compute
  // ------------------------------------------------------------------------------------------
  void setComputePipeline(ComputePipelineHandle h) override {
    if (pass_ != PassState::None)
      return (void)report(R::E_DISPATCH_IN_PASS, "setComputePipeline inside pass " + passName(pass_label_));
    if (!computePipeline(h))
      return (void)report(R::E_HANDLE_INVALID,
                          "setComputePipeline: compute pipeline handle is " + std::string(h ? "destroyed" : "null"));
    computePipeline_ = h;
    backend_->setComputePipeline(h);
  }

  void dispatch(uint32_t x, uint32_t y, uint32_t z) override {
    if (pass_ != PassState::None)
      return (void)report(R::E_DISPATCH_IN_PASS, "dispatch inside pass " + passName(pass_label_));
    if (!computePipeline_) return (void)report(R::E_DISPATCH_NO_PIPELINE, "dispatch without setComputePipeline");
    const ComputePipelineRec* p = computePipeline(computePipeline_);
    if (!p) return (void)report(R::E_HANDLE_INVALID, "dispatch: the compute pipeline was destroyed");
    std::string what = "dispatch with " + quoted("compute pipeline", p->label, computePipeline_.id);
    if (x > kMaxDispatchGroups || y > kMaxDispatchGroups || z > kMaxDispatchGroups) {
      std::ostringstream s;
      s << what << ": " << x << "x" << y << "x" << z << " groups (at most 65535 per dimension)";
      return (void)report(R::E_DISPATCH_SIZE, s.str());
    }
    if (!bindingsOk(p->resources, p->separatePairs, p->pushConstantSize, what)) return;
    backend_->dispatch(x, y, z);
  }

  // ------------------------------------------------------------------------------------------
  // Bindings and push constants
  // ------------------------------------------------------------------------------------------
  void setBindings(std::span<const ResourceBinding> bindings) override {
    if (pass_ == PassState::Dropped) return;
    std::array<uint32_t, kMaxBindings> seen{};  // per binding, a bit per array element
    for (const ResourceBinding& b : bindings) {
      std::string what = "setBindings: binding " + std::to_string(b.binding);
      if (b.binding >= kMaxBindings) return (void)report(R::E_BINDING_INDEX, what + " >= 16");
      if (b.arrayElement >= kMaxArrayElements)
        return (void)report(R::E_BINDING_ARRAY_ELEMENT, what + ": arrayElement " + std::to_string(b.arrayElement) + " >= 16");
      if (b.arrayElement) what += "[" + std::to_string(b.arrayElement) + "]";
      if (seen[b.binding] & (1u << b.arrayElement)) return (void)report(R::E_BINDING_INDEX, what + " given twice");
      seen[b.binding] |= 1u << b.arrayElement;
      switch (b.kind) {
        case BindingKind::UniformBuffer:
        case BindingKind::StorageBuffer:
        case BindingKind::UniformTexelBuffer:
        case BindingKind::StorageTexelBuffer: {
          const BufferRec* buf = buffer(b.buffer);
          if (!buf)
            return (void)report(R::E_HANDLE_INVALID, what + " (" + kindName(b.kind) + "): buffer handle is " +
                                                         (b.buffer ? "destroyed" : "null"));
          const bool texel = b.kind == BindingKind::UniformTexelBuffer || b.kind == BindingKind::StorageTexelBuffer;
          uint32_t need = b.kind == BindingKind::UniformBuffer || b.kind == BindingKind::UniformTexelBuffer
                              ? BufferUsage_Uniform
                              : BufferUsage_Storage;
          if (!(buf->desc.usage & need))
            return (void)report(R::E_BUFFER_USAGE,
                                what + ": " + bufferName(b.buffer) + " lacks " +
                                    (need == BufferUsage_Uniform ? "BufferUsage_Uniform" : "BufferUsage_Storage"));
          size_t size = buf->desc.size;
          if (b.offset >= size || b.size > size - b.offset || b.offset % kBufferBindingAlignment != 0)
            return (void)report(R::E_BINDING_RANGE, what + ": " + range(b.offset, b.size) + " of " +
                                                        bufferName(b.buffer) + " (" + std::to_string(size) +
                                                        " bytes; offsets must be multiples of 256)");
          size_t bound = b.size ? b.size : size - b.offset;
          if (texel && !isTexelBufferFormat(b.texelFormat))
            return (void)report(R::E_BINDING_TEXEL_FORMAT, what + ": texelFormat " + fmt(b.texelFormat) +
                                                               " cannot be a texel buffer's format");
          if (texel && bound % formatInfo(b.texelFormat).bytesPerTexel != 0)
            return (void)report(R::E_BINDING_TEXEL_FORMAT,
                                what + ": " + std::to_string(bound) + " bytes of " + bufferName(b.buffer) +
                                    " are not a whole number of " + fmt(b.texelFormat) + " texels");
          if (b.kind == BindingKind::UniformBuffer && bound > kMaxUniformBufferRange)
            return (void)report(R::E_BINDING_RANGE, what + ": " + std::to_string(bound) + " bytes of " +
                                                        bufferName(b.buffer) +
                                                        " as a uniform buffer (at most 65536; give a size)");
          break;
        }
        case BindingKind::SampledTexture:
        case BindingKind::StorageTexture: {
          const TextureRec* t = texture(b.texture);
          if (!t)
            return (void)report(R::E_HANDLE_INVALID, what + " (" + kindName(b.kind) + "): texture handle is " +
                                                         (b.texture ? "destroyed" : "null"));
          bool storage = b.kind == BindingKind::StorageTexture;
          uint32_t need = storage ? TextureUsage_Storage : TextureUsage_Sampled;
          if (!(t->desc.usage & need))
            return (void)report(R::E_TEXTURE_USAGE, what + ": " + textureName(b.texture) + " lacks " +
                                                        (storage ? "TextureUsage_Storage" : "TextureUsage_Sampled"));
          if (storage && t->swizzled)
            return (void)report(R::E_VIEW_SWIZZLE, what + ": " + textureName(b.texture) +
                                                       " has a swizzle; a storage texture reads and writes the texels as stored");
          if (storage && b.mip >= t->desc.mipLevels)
            return (void)report(R::E_BINDING_RANGE, what + ": mip " + std::to_string(b.mip) + " of " +
                                                        textureName(b.texture) + " (" +
                                                        std::to_string(t->desc.mipLevels) + " mips)");
          if (!storage && b.sampler && !samplers_.count(b.sampler.id))
            return (void)report(R::E_HANDLE_INVALID, what + ": sampler handle is destroyed");
          break;
        }
        case BindingKind::SeparateTexture: {
          const TextureRec* t = texture(b.texture);
          if (!t)
            return (void)report(R::E_HANDLE_INVALID, what + " (" + kindName(b.kind) + "): texture handle is " +
                                                         (b.texture ? "destroyed" : "null"));
          if (!(t->desc.usage & TextureUsage_Sampled))
            return (void)report(R::E_TEXTURE_USAGE, what + ": " + textureName(b.texture) + " lacks TextureUsage_Sampled");
          break;
        }
        case BindingKind::SeparateSampler:
          if (b.sampler && !samplers_.count(b.sampler.id))  // null: the default sampler
            return (void)report(R::E_HANDLE_INVALID, what + ": sampler handle is destroyed");
          break;
        default:
          return (void)report(R::E_BINDING_KIND, what + ": unknown kind");
      }
    }
    for (const ResourceBinding& b : bindings) bindings_[b.binding][b.arrayElement] = b;
    backend_->setBindings(bindings);
  }

  void pushConstants(const void* data, uint32_t size) override {
    if (pass_ == PassState::Dropped) return;
    if (!data || size == 0 || size > kMaxPushConstantBytes || size % 4 != 0)
      return (void)report(R::E_PUSH_CONSTANT_SIZE, "pushConstants: " + std::to_string(size) + " bytes" +
                                                       (data ? "" : " from null data") + " (1..128, a multiple of 4)");
    pushedBytes_ = std::max(pushedBytes_, size);
    backend_->pushConstants(data, size);
  }

  // What an ARB assembly program reads: the backend's own state, nothing to check here.
  void setProgramParameter(ShaderStage stage, bool local, uint32_t index, const std::array<float, 4>& value) override {
    backend_->setProgramParameter(stage, local, index, value);
  }
  void setTransformMatrices(const std::array<float, 16>& modelView, const std::array<float, 16>& projection) override {
    backend_->setTransformMatrices(modelView, projection);
  }
  void setCurrentAttribute(CurrentAttribute attribute, uint32_t index, const std::array<float, 4>& value) override {
    backend_->setCurrentAttribute(attribute, index, value);
  }

  // ------------------------------------------------------------------------------------------
  // Timing and submission
  // ------------------------------------------------------------------------------------------
  TimestampId writeTimestamp() override {
    if (pass_ != PassState::None) {
      report(R::E_TIMESTAMP_IN_PASS, "writeTimestamp inside pass " + passName(pass_label_));
      return kInvalidTimestamp;
    }
    TimestampId id = backend_->writeTimestamp();
    pendingTimestamps_.insert(id);
    return id;
  }

  std::optional<uint64_t> timestampNs(TimestampId id) override {
    if (id == kInvalidTimestamp) return std::nullopt;
    if (pendingTimestamps_.count(id)) {
      report(R::E_TIMESTAMP_PENDING, "timestampNs(" + std::to_string(id) + "): written after the last submit()");
      return std::nullopt;
    }
    return backend_->timestampNs(id);
  }

  void resetTimestamps() override {
    if (pass_ != PassState::None)
      return (void)report(R::E_TIMESTAMP_IN_PASS, "resetTimestamps inside pass " + passName(pass_label_));
    pendingTimestamps_.clear();
    backend_->resetTimestamps();
  }

  void submit() override {
    if (pass_ != PassState::None)
      return (void)report(R::E_SUBMIT_IN_PASS, "submit inside pass " + passName(pass_label_) + " (call endPass first)");
    pendingTimestamps_.clear();
    backend_->submit();
  }
  std::vector<std::string> takeNotes() override { return backend_->takeNotes(); }

 private:
  struct VertexBinding {
    BufferHandle buffer;
    size_t offset = 0;
  };
  struct IndexBinding {
    BufferHandle buffer;
    size_t offset = 0;
    IndexType type = IndexType::UInt32;
  };

  bool report(R rule, const std::string& message) {
    onError_(kRuleNames[static_cast<size_t>(rule)], message);
    return false;
  }
  template <class T>
  T fail(R rule, const std::string& message) {
    report(rule, message);
    return T{};
  }

  static std::string range(size_t offset, size_t size) {
    return "bytes [" + std::to_string(offset) + ", +" + std::to_string(size) + ")";
  }
  static std::string passName(const std::string& label) { return label.empty() ? "(unlabelled)" : "'" + label + "'"; }

  // Lookups (null when the handle is null or destroyed).
  bool samplerCompares(SamplerHandle h) const {
    auto it = samplers_.find(h.id);
    return h && it != samplers_.end() && it->second.compareEnabled;
  }
  const BufferRec* buffer(BufferHandle h) const {
    auto it = buffers_.find(h.id);
    return h && it != buffers_.end() ? &it->second : nullptr;
  }
  const TextureRec* texture(TextureHandle h) const {
    auto it = textures_.find(h.id);
    return h && it != textures_.end() ? &it->second : nullptr;
  }
  const ShaderRec* shader(ShaderHandle h) const {
    auto it = shaders_.find(h.id);
    return h && it != shaders_.end() ? &it->second : nullptr;
  }
  const PipelineRec* pipeline(PipelineHandle h) const {
    auto it = pipelines_.find(h.id);
    return h && it != pipelines_.end() ? &it->second : nullptr;
  }
  const ComputePipelineRec* computePipeline(ComputePipelineHandle h) const {
    auto it = computePipelines_.find(h.id);
    return h && it != computePipelines_.end() ? &it->second : nullptr;
  }

  std::string bufferName(BufferHandle h) const {
    const BufferRec* b = buffer(h);
    return quoted("buffer", b ? b->desc.label : "", h.id);
  }
  std::string textureName(TextureHandle h) const {
    const TextureRec* t = texture(h);
    return quoted(t && t->isView ? "texture view" : "texture", t ? t->desc.label : "", h.id);
  }
  std::string shaderName(ShaderHandle h) const {
    const ShaderRec* s = shader(h);
    return quoted("shader", s ? s->label : "", h.id);
  }
  std::string pipelineName(PipelineHandle h) const {
    const PipelineRec* p = pipeline(h);
    return quoted("pipeline", p ? p->desc.label : "", h.id);
  }

  const BufferRec* liveBuffer(BufferHandle h, const char* what) {
    const BufferRec* b = buffer(h);
    if (!b) report(R::E_HANDLE_INVALID, std::string(what) + ": buffer handle is " + (h ? "destroyed" : "null"));
    return b;
  }
  const TextureRec* liveTexture(TextureHandle h, const char* what) {
    const TextureRec* t = texture(h);
    if (!t) report(R::E_HANDLE_INVALID, std::string(what) + ": texture handle is " + (h ? "destroyed" : "null"));
    return t;
  }

  bool transferAllowed(const char* what) {
    if (pass_ == PassState::None) return true;
    return report(R::E_TRANSFER_IN_PASS, std::string(what) + " inside pass " + passName(pass_label_));
  }

  // Commands that belong inside a pass: false (after reporting) outside one, false silently in a
  // dropped pass.
  bool inPassCommand(const char* what) {
    if (pass_ == PassState::Active) return true;
    if (pass_ == PassState::Dropped) return false;
    return report(R::E_PASS_NOT_BEGUN, std::string(what) + " outside a pass");
  }

  bool subresourceOk(const TextureRec& t, uint32_t layer, uint32_t mip, const char* what, TextureHandle h) {
    if (mip < t.desc.mipLevels && layer < layersAt(t.desc, mip)) return true;
    std::ostringstream s;
    s << what << ": layer " << layer << ", mip " << mip << " outside " << textureName(h) << " ("
      << layersAt(t.desc, std::min(mip, t.desc.mipLevels - 1)) << " layers, " << t.desc.mipLevels << " mips)";
    return report(R::E_SUBRESOURCE_RANGE, s.str());
  }

  static AttachmentRef rootRef(const TextureRec& t, uint32_t layer, uint32_t mip) {
    return {t.root, t.baseLayer + layer, t.baseMip + mip};
  }

  bool validatePass(const PassDesc& desc) {
    std::string pname = "beginPass " + passName(desc.label);
    bool any = false;
    uint32_t width = 0, height = 0, samples = 0;
    std::string first;
    std::vector<AttachmentRef> refs;
    std::array<Format, kMaxColorTargets> colors{};
    colors.fill(Format::Undefined);
    Format depth = Format::Undefined;

    auto checkSize = [&](const TextureRec& t, uint32_t mip, const std::string& slot) {
      uint32_t w = mipSize(t.desc.width, mip), h = mipSize(t.desc.height, mip);
      if (!any) {
        any = true;
        width = w;
        height = h;
        samples = t.desc.samples;
        first = slot;
        return true;
      }
      if (w != width || h != height) {
        std::ostringstream s;
        s << pname << ": " << slot << " is " << w << "x" << h << " but " << first << " is " << width << "x" << height;
        return report(R::E_PASS_ATTACHMENT_SIZE_MISMATCH, s.str());
      }
      if (t.desc.samples != samples) {
        std::ostringstream s;
        s << pname << ": " << slot << " has " << t.desc.samples << " samples but " << first << " has " << samples;
        return report(R::E_PASS_ATTACHMENT_SAMPLES, s.str());
      }
      return true;
    };
    auto addRef = [&](AttachmentRef r, const std::string& slot) {
      for (const AttachmentRef& o : refs)
        if (o.root == r.root && o.layer == r.layer && o.mip == r.mip)
          return report(R::E_PASS_ATTACHMENT_DUPLICATE, pname + ": " + slot + " is already attached");
      refs.push_back(r);
      return true;
    };

    for (uint32_t i = 0; i < kMaxColorTargets; ++i) {
      const ColorAttachment& c = desc.colors[i];
      if (!c.texture) {
        if (c.resolveTarget)
          return report(R::E_PASS_RESOLVE,
                        pname + ": colour slot " + std::to_string(i) + " has a resolve target but no texture");
        continue;
      }
      const TextureRec* t = texture(c.texture);
      std::string slot = "colour " + std::to_string(i) + " (" + textureName(c.texture) + ")";
      if (!t) return report(R::E_HANDLE_INVALID, pname + ": colour " + std::to_string(i) + " texture was destroyed");
      if (isDepthFormat(t->desc.format))
        return report(R::E_PASS_ATTACHMENT_FORMAT, pname + ": " + slot + " has depth format " + fmt(t->desc.format));
      if (!(t->desc.usage & TextureUsage_RenderTarget))
        return report(R::E_PASS_ATTACHMENT_USAGE, pname + ": " + slot + " lacks TextureUsage_RenderTarget");
      if (t->swizzled) return report(R::E_VIEW_SWIZZLE, pname + ": " + slot + " has a swizzle (sampling only)");
      if (c.mip >= t->desc.mipLevels || c.layer >= layersAt(t->desc, c.mip)) {
        std::ostringstream s;
        s << pname << ": " << slot << " layer " << c.layer << ", mip " << c.mip << " outside " << layersAt(t->desc, 0)
          << " layers, " << t->desc.mipLevels << " mips";
        return report(R::E_PASS_ATTACHMENT_RANGE, s.str());
      }
      if (!checkSize(*t, c.mip, slot)) return false;
      if (!addRef(rootRef(*t, c.layer, c.mip), slot)) return false;
      colors[i] = t->desc.format;
      if (c.resolveTarget) {
        const TextureRec* r = texture(c.resolveTarget);
        if (!r) return report(R::E_HANDLE_INVALID, pname + ": resolve target of " + slot + " was destroyed");
        std::string rname = textureName(c.resolveTarget);
        const char* why = nullptr;
        if (t->desc.samples == 1)
          why = "the attachment is not multisampled";
        else if (r->desc.samples != 1)
          why = "the resolve target is multisampled";
        else if (r->desc.format != t->desc.format)
          why = "formats differ";
        else if (r->desc.width != mipSize(t->desc.width, c.mip) || r->desc.height != mipSize(t->desc.height, c.mip))
          why = "sizes differ";
        else if (isIntegerFormat(t->desc.format))
          why = "integer formats cannot be resolved";
        if (why) return report(R::E_PASS_RESOLVE, pname + ": " + slot + " resolving to " + rname + ": " + why);
        if (r->swizzled) return report(R::E_VIEW_SWIZZLE, pname + ": resolve target " + rname + " has a swizzle (sampling only)");
        if (!(r->desc.usage & TextureUsage_RenderTarget))
          return report(R::E_PASS_ATTACHMENT_USAGE,
                        pname + ": resolve target " + rname + " lacks TextureUsage_RenderTarget");
        if (!addRef(rootRef(*r, 0, 0), "resolve target " + rname)) return false;
      }
    }
    const DepthStencilAttachment& d = desc.depthStencil;
    if (d.texture) {
      const TextureRec* t = texture(d.texture);
      std::string slot = "depth-stencil (" + textureName(d.texture) + ")";
      if (!t) return report(R::E_HANDLE_INVALID, pname + ": depth-stencil texture was destroyed");
      if (!isDepthFormat(t->desc.format))
        return report(R::E_PASS_ATTACHMENT_FORMAT, pname + ": " + slot + " has colour format " + fmt(t->desc.format));
      if (!(t->desc.usage & TextureUsage_RenderTarget))
        return report(R::E_PASS_ATTACHMENT_USAGE, pname + ": " + slot + " lacks TextureUsage_RenderTarget");
      if (t->swizzled) return report(R::E_VIEW_SWIZZLE, pname + ": " + slot + " has a swizzle (sampling only)");
      if (d.layer >= t->desc.layers)
        return report(R::E_PASS_ATTACHMENT_RANGE, pname + ": " + slot + " layer " + std::to_string(d.layer) +
                                                      " outside " + std::to_string(t->desc.layers) + " layers");
      if (!checkSize(*t, 0, slot)) return false;
      if (!addRef(rootRef(*t, d.layer, 0), slot)) return false;
      depth = t->desc.format;
    }
    if (!any) return report(R::E_PASS_NO_ATTACHMENTS, pname + ": no colour or depth-stencil attachment");
    pass_color_ = colors;
    pass_depth_ = depth;
    pass_samples_ = samples;
    pass_refs_ = std::move(refs);
    return true;
  }

  const PipelineRec* drawPipeline(const char* what) {
    if (!pipeline_) {
      report(R::E_DRAW_NO_PIPELINE, std::string(what) + " in pass " + passName(pass_label_) + " without setPipeline");
      return nullptr;
    }
    const PipelineRec* p = pipeline(pipeline_);
    if (!p) {
      report(R::E_HANDLE_INVALID, std::string(what) + ": the current pipeline was destroyed");
      return nullptr;
    }
    const PipelineDesc& d = p->desc;
    std::string pre =
        std::string(what) + " with " + pipelineName(pipeline_) + " in pass " + passName(pass_label_) + ": ";
    for (uint32_t i = 0; i < kMaxColorTargets; ++i) {
      Format pf = i < d.colorTargetCount ? d.colorTargets[i].format : Format::Undefined;
      if (pf != pass_color_[i]) {
        report(R::E_DRAW_PIPELINE_MISMATCH, pre + "colour " + std::to_string(i) + " is " + fmt(pf) +
                                                " in the pipeline but " + fmt(pass_color_[i]) + " in the pass");
        return nullptr;
      }
    }
    if (d.depthStencilFormat != pass_depth_) {
      report(R::E_DRAW_PIPELINE_MISMATCH, pre + "depth-stencil is " + fmt(d.depthStencilFormat) +
                                              " in the pipeline but " + fmt(pass_depth_) + " in the pass");
      return nullptr;
    }
    if (d.samples != pass_samples_) {
      report(R::E_DRAW_PIPELINE_MISMATCH, pre + std::to_string(d.samples) + " samples in the pipeline but " +
                                              std::to_string(pass_samples_) + " in the pass");
      return nullptr;
    }
    return p;
  }

  // Vertex buffers every attribute slot needs; ranges for non-indexed draws (vertices) and all
  // draws (instances).
  bool vertexInputsOk(const PipelineRec& p, const char* what, uint32_t vertexCount, uint32_t instanceCount,
                      uint32_t firstVertex, uint32_t firstInstance, bool checkVertices) {
    const PipelineDesc& d = p.desc;
    for (uint32_t slot = 0; slot < kMaxVertexBuffers; ++slot) {
      uint64_t attribEnd = 0;
      bool used = false;
      for (uint32_t i = 0; i < d.attributeCount; ++i) {
        if (d.attributes[i].bufferSlot != slot) continue;
        used = true;
        attribEnd = std::max<uint64_t>(attribEnd, d.attributes[i].offset + vertexFormatSize(d.attributes[i].format));
      }
      if (!used) continue;
      if (!vertexBuffers_[slot])
        return report(R::E_VERTEX_BUFFER_MISSING, std::string(what) + " with " + pipelineName(pipeline_) +
                                                      ": no vertex buffer in slot " + std::to_string(slot));
      const BufferRec* b = buffer(vertexBuffers_[slot]->buffer);
      if (!b)
        return report(R::E_HANDLE_INVALID,
                      std::string(what) + ": the vertex buffer in slot " + std::to_string(slot) + " was destroyed");
      const VertexBufferLayout& layout = d.vertexBuffers[slot];
      uint64_t count = layout.perInstance ? instanceCount : vertexCount;
      uint64_t first = layout.perInstance ? firstInstance : firstVertex;
      if (!layout.perInstance && !checkVertices) continue;
      if (count == 0) continue;
      uint64_t end = vertexBuffers_[slot]->offset + (first + count - 1) * layout.stride + attribEnd;
      if (end > b->desc.size) {
        std::ostringstream s;
        s << what << " with " << pipelineName(pipeline_) << ": " << (layout.perInstance ? "instances [" : "vertices [")
          << first << ", " << first + count << ") read up to byte " << end << " of "
          << bufferName(vertexBuffers_[slot]->buffer) << " (" << b->desc.size << " bytes) in slot " << slot;
        return report(R::E_DRAW_VERTEX_RANGE, s.str());
      }
    }
    return true;
  }

  // The texture a SampledTexture/SeparateTexture binding reads is integer (a usampler on a D24S8
  // texture reads its stencil, an integer).
  static bool readsInteger(const TextureRec& t, const ShaderResource& r) {
    return isIntegerFormat(t.desc.format) || (r.integer && r.kind != BindingKind::StorageTexture && hasStencil(t.desc.format));
  }

  // Linear filtering of a texture not every device filters: an integer one (Vulkan forbids it, GL's
  // texture is incomplete and reads 0) or a depth one read without comparison (an optional
  // format feature). The null sampler is nearest.
  bool filtersUnfilterable(SamplerHandle sampler, const TextureRec& t, bool integerRead) const {
    auto it = samplers_.find(sampler.id);
    if (!sampler || it == samplers_.end()) return false;
    const SamplerDesc& d = it->second;
    const bool linear = d.minFilter == Filter::Linear || d.magFilter == Filter::Linear || d.mipFilter == MipFilter::Linear;
    return linear && (integerRead || (isDepthFormat(t.desc.format) && !d.compareEnabled));
  }

  // Null when a ClampToBorder sampler's border colour family fits the texture it samples.
  const char* borderMismatch(SamplerHandle sampler, bool integerTexture) const {
    auto it = samplers_.find(sampler.id);
    if (!sampler || it == samplers_.end() || !usesBorder(it->second)) return nullptr;
    if (intBorder(it->second.borderColor) == integerTexture) return nullptr;
    return integerTexture ? "the texture is integer but the sampler's border colour is a Float one"
                          : "the sampler's border colour is an Int one but the texture is not integer";
  }

  bool bindingsOk(const std::vector<ShaderResource>& resources, const std::vector<SeparatePair>& pairs,
                  uint32_t pushConstantSize, const std::string& what) {
    for (const ShaderResource& r : resources)
      for (uint32_t element = 0; element < r.arraySize; ++element) {
        std::string rn = what + ": binding " + std::to_string(r.binding) +
                         (r.arraySize > 1 ? "[" + std::to_string(element) + "]" : std::string()) + " ('" + r.name + "', " +
                         kindName(r.kind) + ")";
        if (r.binding >= kMaxBindings || !bindings_[r.binding][element])
          return report(R::E_BINDING_MISSING, rn + " was not supplied by setBindings");
        const ResourceBinding& b = *bindings_[r.binding][element];
        if (b.kind != r.kind) return report(R::E_BINDING_KIND, rn + " was bound as " + kindName(b.kind));
        if (b.kind == BindingKind::UniformBuffer || b.kind == BindingKind::StorageBuffer) {
          if (!buffer(b.buffer)) return report(R::E_HANDLE_INVALID, rn + ": the bound buffer was destroyed");
          continue;
        }
        if (b.kind == BindingKind::UniformTexelBuffer || b.kind == BindingKind::StorageTexelBuffer) {
          if (!buffer(b.buffer)) return report(R::E_HANDLE_INVALID, rn + ": the bound buffer was destroyed");
          if (r.integer != isIntegerFormat(b.texelFormat))
            return report(R::E_BINDING_TEXTURE_MISMATCH,
                          rn + ": texelFormat " + fmt(b.texelFormat) +
                              (r.integer ? ": the shader declares an integer texel buffer" : ": the format is integer"));
          continue;
        }
        if (b.kind == BindingKind::SeparateSampler) {
          if (b.sampler && !samplers_.count(b.sampler.id))
            return report(R::E_HANDLE_INVALID, rn + ": the bound sampler was destroyed");
          continue;
        }
        const TextureRec* t = texture(b.texture);
        if (!t) return report(R::E_HANDLE_INVALID, rn + ": the bound texture was destroyed");
        if (b.kind == BindingKind::SampledTexture && b.sampler && !samplers_.count(b.sampler.id))
          return report(R::E_HANDLE_INVALID, rn + ": the bound sampler was destroyed");
        std::string tn = textureName(b.texture);
        const char* why = nullptr;
        const bool integer = readsInteger(*t, r);
        if (r.integer != integer)
          why = r.integer ? "the shader declares an integer texture" : "the texture has an integer format";
        if (b.kind == BindingKind::SampledTexture || b.kind == BindingKind::SeparateTexture) {
          const bool combined = b.kind == BindingKind::SampledTexture;
          bool cube = t->desc.type == TextureType::Cube && t->desc.layers == 6;
          if (r.multisampled != (t->desc.samples > 1))
            why = r.multisampled ? "the shader declares a multisampled texture" : "the texture is multisampled";
          else if (combined && r.depthCompare && !isDepthFormat(t->desc.format))
            why = "a shadow sampler needs a depth texture";
          else if (combined && b.sampler && r.depthCompare != samplerCompares(b.sampler))  // null: fits both
            why = r.depthCompare ? "a shadow sampler needs a SamplerDesc with compareEnabled"
                                 : "a SamplerDesc with compareEnabled needs a shadow sampler in the shader";
          else if (r.cube && !cube)
            why = "the shader declares a cube texture";
          else if (!r.cube && r.arrayed && t->desc.type == TextureType::Tex2D)
            why = "the shader declares an array texture but the texture is Tex2D";
          else if (!r.cube && r.arrayed && t->desc.type == TextureType::Cube && !t->isView)
            why = "a cube texture needs a samplerCube";
          else if (!r.cube && !r.arrayed && t->desc.layers != 1)
            why = "the texture has several layers (bind a one-layer view)";
        }
        const uint32_t textureDimensions = t->desc.type == TextureType::Tex1D   ? 1
                                           : t->desc.type == TextureType::Tex3D ? 3
                                                                                : 2;
        if (!why && b.kind == BindingKind::StorageTexture && r.multisampled != (t->desc.samples > 1))
          why = r.multisampled ? "the shader declares a multisampled image" : "the texture is multisampled";
        if (!why && r.dimensions != textureDimensions)
          why = r.dimensions == 1   ? "the shader declares a 1D texture but the texture is not Tex1D"
                : r.dimensions == 3 ? "the shader declares a 3D texture but the texture is not Tex3D"
                                    : "the texture is Tex1D or Tex3D but the shader declares another dimension";
        if (why) return report(R::E_BINDING_TEXTURE_MISMATCH, rn + ": " + tn + " (" + fmt(t->desc.format) + "): " + why);
        if (b.kind == BindingKind::SampledTexture) {
          if (const char* border = borderMismatch(b.sampler, integer))
            return report(R::E_BINDING_BORDER_COLOR, rn + ": " + tn + " (" + fmt(t->desc.format) + "): " + border);
          if (filtersUnfilterable(b.sampler, *t, integer))
            return report(R::E_BINDING_FILTER_FORMAT, rn + ": " + tn + " (" + fmt(t->desc.format) + ") is read " +
                                                          (integer ? "as integers" : "as depth") + " through a Linear sampler");
        }
        if (pass_ == PassState::Active) {
          uint32_t layerLo = t->baseLayer, layerHi = t->baseLayer + layersAt(t->desc, 0);
          uint32_t mipLo = t->baseMip, mipHi = t->baseMip + t->desc.mipLevels;
          if (b.kind == BindingKind::StorageTexture) {
            mipLo = t->baseMip + b.mip;
            mipHi = mipLo + 1;
          }
          for (const AttachmentRef& a : pass_refs_)
            if (a.root == t->root && a.layer >= layerLo && a.layer < layerHi && a.mip >= mipLo && a.mip < mipHi)
              return report(R::E_BINDING_FEEDBACK, rn + ": " + tn + " is an attachment of pass " + passName(pass_label_));
        }
      }
    // The pairs a shader combines: the checks SampledTexture gets for its own sampler. Every
    // binding was checked above, so each pair's texture and sampler are live and of their kind.
    auto arraySize = [&](uint32_t binding) {
      auto r = std::find_if(resources.begin(), resources.end(), [&](const ShaderResource& o) { return o.binding == binding; });
      return r == resources.end() ? 1u : r->arraySize;
    };
    auto named = [&](uint32_t binding, uint32_t element) {
      return std::to_string(binding) + (arraySize(binding) > 1 ? "[" + std::to_string(element) + "]" : std::string());
    };
    for (const SeparatePair& pair : pairs) {
      const bool withSampler = pair.samplerBinding != kNoSamplerBinding;
      for (uint32_t te = 0; te < arraySize(pair.textureBinding); ++te) {
        for (uint32_t se = 0; se < (withSampler ? arraySize(pair.samplerBinding) : 1u); ++se) {
          const ResourceBinding& tb = *bindings_[pair.textureBinding][te];
          const TextureRec* t = texture(tb.texture);
          auto res = std::find_if(resources.begin(), resources.end(),
                                  [&](const ShaderResource& r) { return r.binding == pair.textureBinding; });
          if (!t || res == resources.end()) continue;
          const SamplerHandle sampler = withSampler ? bindings_[pair.samplerBinding][se]->sampler : SamplerHandle{};
          std::string rn = what + ": texture binding " + named(pair.textureBinding, te) + " with sampler binding " +
                           (withSampler ? named(pair.samplerBinding, se) : std::string("(none)")) + ": " +
                           textureName(tb.texture) + " (" + fmt(t->desc.format) + ")";
          const char* why = nullptr;
          if (pair.depthCompare && !isDepthFormat(t->desc.format))
            why = "a shadow sampler needs a depth texture";
          else if (sampler && pair.depthCompare != samplerCompares(sampler))
            why = pair.depthCompare ? "a shadow sampler needs a SamplerDesc with compareEnabled"
                                    : "a SamplerDesc with compareEnabled needs a shadow sampler in the shader";
          if (why) return report(R::E_BINDING_TEXTURE_MISMATCH, rn + ": " + why);
          if (const char* border = borderMismatch(sampler, readsInteger(*t, *res)))
            return report(R::E_BINDING_BORDER_COLOR, rn + ": " + border);
          if (filtersUnfilterable(sampler, *t, readsInteger(*t, *res)))
            return report(R::E_BINDING_FILTER_FORMAT, rn + ": read through a Linear sampler, which its format need not support");
        }
      }
    }
    if (pushConstantSize > pushedBytes_)
      return report(R::E_PUSH_CONSTANT_MISSING, what + ": the shaders declare " + std::to_string(pushConstantSize) +
                                                    " push-constant bytes, " + std::to_string(pushedBytes_) +
                                                    " were pushed");
    return true;
  }

  std::unique_ptr<Device> backend_;
  ValidationCallback onError_;

  std::unordered_map<uint32_t, BufferRec> buffers_;
  std::unordered_map<uint32_t, TextureRec> textures_;
  std::unordered_map<uint32_t, SamplerDesc> samplers_;  // live samplers
  std::unordered_map<uint32_t, ShaderRec> shaders_;
  std::unordered_map<uint32_t, PipelineRec> pipelines_;
  std::unordered_map<uint32_t, ComputePipelineRec> computePipelines_;

  PassState pass_ = PassState::None;
  std::string pass_label_;
  std::array<Format, kMaxColorTargets> pass_color_{};
  Format pass_depth_ = Format::Undefined;
  uint32_t pass_samples_ = 1;
  std::vector<AttachmentRef> pass_refs_;

  PipelineHandle pipeline_;
  ComputePipelineHandle computePipeline_;
  std::array<std::optional<VertexBinding>, kMaxVertexBuffers> vertexBuffers_{};
  std::optional<IndexBinding> indexBuffer_;
  std::array<std::array<std::optional<ResourceBinding>, kMaxArrayElements>, kMaxBindings> bindings_{};  // [binding][element]
  uint32_t pushedBytes_ = 0;
  std::unordered_set<TimestampId> pendingTimestamps_;
};

}  // namespace

const std::vector<ValidationRule>& validationRules() {
  static const std::vector<ValidationRule> rules = {
#define PARITY_RHI_VALIDATION_ENTRY(id, description) {#id, description},
      PARITY_RHI_VALIDATION_RULES(PARITY_RHI_VALIDATION_ENTRY)
#undef PARITY_RHI_VALIDATION_ENTRY
  };
  return rules;
}

const ValidationRule* findValidationRule(std::string_view id) {
  for (const ValidationRule& r : validationRules())
    if (r.id == id) return &r;
  return nullptr;
}

const char* validationRuleName(ValidationRuleId id) {
  size_t i = static_cast<size_t>(id);
  return i < static_cast<size_t>(ValidationRuleId::Count) ? kRuleNames[i] : "";
}

std::unique_ptr<Device> wrapWithValidation(std::unique_ptr<Device> backend, ValidationCallback onError) {
  if (!backend) return nullptr;
  if (!onError) onError = [](const std::string&, const std::string&) {};
  return std::make_unique<ValidatingDevice>(std::move(backend), std::move(onError));
}

// The formats a texel buffer may have on both backends (GL buffer textures that are also image
// load/store formats; Vulkan UNIFORM/STORAGE_TEXEL_BUFFER on lavapipe).
bool isTexelBufferFormat(Format f) {
  switch (f) {
    case Format::RGBA8: case Format::RGBA8_UINT: case Format::R32_UINT: case Format::R32F:
    case Format::RG32F: case Format::RGBA16F: case Format::RGBA32F: case Format::R32_SINT:
    case Format::RGBA32_UINT: case Format::RGBA32_SINT:
      return true;
    default:
      return false;
  }
}

}  // namespace parity::rhi
