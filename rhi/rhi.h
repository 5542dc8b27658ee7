// parity RHI: the portable rendering interface every technique, platform layer and test is
// written against. It never names a GL or Vulkan type.
//
// Shape (after sokol_gfx and NVRHI):
//  * Descriptors are plain structs. A value-initialised descriptor ({}) is a documented, valid
//    default; every field's default is written next to it. Enum value 0 is always the default.
//  * Objects are typed handles (index + generation), never pointers. A null handle (id 0) is
//    what a failed creation returns.
//  * One Device per process and backend. Commands are recorded on the device (setPipeline,
//    draw, ...) and executed in order; submit() waits until the GPU has finished them.
//  * Validation is a separate layer (rhi/validation.h) wrapping any Device; backends assume
//    valid input.
//
// Conventions, identical on every backend (each backend normalises them in one place, see
// docs/ARCHITECTURE.md and tests/rhi_conformance_test.cpp):
//  * Clip space: Vulkan style. NDC y = -1 is framebuffer memory row 0, which is the top row of
//    every saved image; depth range is [0, 1]. Projections map "up" to NDC y = -1.
//  * Framebuffer and texture rows: memory row 0 first. Readback returns row 0 first;
//    texture coordinate v = 0 addresses row 0; gl_FragCoord.y = 0.5 is row 0.
//  * Viewport and scissor rectangles are in framebuffer pixels with y counted from row 0.
//  * Front face: FrontFace::CounterClockwise means counter-clockwise as seen in the saved image
//    (that is, as seen by the camera when the projection maps up to NDC y = -1).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace parity::rhi {

// ---------------------------------------------------------------------------------------------
// Handles
// ---------------------------------------------------------------------------------------------
template <class Tag>
struct Handle {
  uint32_t id = 0;  // 0 is the null handle; otherwise (generation << 20) | slot.
  explicit operator bool() const { return id != 0; }
  friend bool operator==(Handle a, Handle b) { return a.id == b.id; }
  friend bool operator!=(Handle a, Handle b) { return a.id != b.id; }
};
using BufferHandle = Handle<struct BufferTag>;
using TextureHandle = Handle<struct TextureTag>;
using SamplerHandle = Handle<struct SamplerTag>;
using ShaderHandle = Handle<struct ShaderTag>;
using PipelineHandle = Handle<struct PipelineTag>;
using ComputePipelineHandle = Handle<struct ComputePipelineTag>;

// ---------------------------------------------------------------------------------------------
// Formats
// ---------------------------------------------------------------------------------------------
enum class Format : uint8_t {
  Undefined = 0,
  RGBA8,        // unorm, 32-bit class
  RGBA8_SRGB,   // sRGB-encoded RGB, linear alpha, 32-bit class
  RGBA8_UINT,   // 32-bit class
  R8,           // unorm, 8-bit class
  RG16_UNORM,   // 32-bit class
  RG16_SNORM,   // 32-bit class
  RG16_FLOAT,   // 32-bit class
  RG16_UINT,    // 32-bit class
  R32_UINT,     // 32-bit class
  R32F,         // 32-bit class
  RGBA16F,      // 64-bit class
  RG32F,        // 64-bit class
  RGBA32F,      // 128-bit class
  D24S8,        // depth 24-bit unorm + stencil 8
  D32F,         // depth 32-bit float, no stencil
  D16,          // depth 16-bit unorm, no stencil
  RG8_UINT,     // 16-bit class
  RG8_SNORM,    // 16-bit class
  R16_SNORM,    // 16-bit class
  RGBA8_SNORM,  // 32-bit class
  RGBA16_SNORM, // 64-bit class
  // Unsigned 11/11/10-bit floats packed in one 32-bit word: R in bits 0-10, G in 11-21 (6-bit
  // mantissa, 5-bit exponent each), B in 22-31 (5-bit mantissa, 5-bit exponent). 32-bit class.
  B10G11R11_UFLOAT,
  R32_SINT,     // 32-bit class
  RGBA32_UINT,  // 128-bit class
  RGBA32_SINT,  // 128-bit class
  Count
};

enum class FormatKind : uint8_t { Unorm, Snorm, Float, Uint, Srgb, Depth, DepthStencil, Sint };

struct FormatInfo {
  const char* name;        // "RGBA8", ... (stable: used in file formats and reports)
  uint32_t bytesPerTexel;  // size class: formats with equal values may view each other
  uint32_t channels;       // colour channels (depth formats: 1)
  FormatKind kind;
};
const FormatInfo& formatInfo(Format f);
// Whether a texel buffer may have format f on both backends.
bool isTexelBufferFormat(Format f);
std::optional<Format> formatFromName(std::string_view name);
inline bool isDepthFormat(Format f) { return f == Format::D24S8 || f == Format::D32F || f == Format::D16; }
// Read as integers in shaders (usampler/isampler, uimage/iimage) and cleared with integer values.
inline bool isIntegerFormat(Format f) {
  return f != Format::Undefined && f < Format::Count &&
         (formatInfo(f).kind == FormatKind::Uint || formatInfo(f).kind == FormatKind::Sint);
}
inline bool hasStencil(Format f) { return f == Format::D24S8; }
// D16 texels (16-bit unorm words) as a depth readback returns them: one float per texel,
// q / 65535 correctly rounded. Shared by the backends so that both round alike.
std::vector<uint8_t> unorm16DepthToFloat(const std::vector<uint8_t>& texels);

// ---------------------------------------------------------------------------------------------
// Buffers
// ---------------------------------------------------------------------------------------------
enum BufferUsage : uint32_t {
  BufferUsage_Vertex = 1u << 0,
  BufferUsage_Index = 1u << 1,
  BufferUsage_Uniform = 1u << 2,  // also UniformTexelBuffer bindings
  BufferUsage_Storage = 1u << 3,  // also StorageTexelBuffer bindings
  BufferUsage_All = 0xF,
};

struct BufferDesc {
  size_t size = 0;                       // bytes; must be > 0
  uint32_t usage = BufferUsage_All;      // default: usable for everything
  const void* initialData = nullptr;     // default: contents zeroed
  std::string label;                     // for debug output and validation messages
};

// ---------------------------------------------------------------------------------------------
// Textures and samplers
// ---------------------------------------------------------------------------------------------
// Tex1D: height 1 (sampler1D; sampler1DArray reads its layers); Tex3D: `depth` slices
// (sampler3D), one layer.
enum class TextureType : uint8_t { Tex2D = 0, Tex2DArray, Cube, Tex1D, Tex3D };

enum TextureUsage : uint32_t {
  TextureUsage_Sampled = 1u << 0,
  TextureUsage_RenderTarget = 1u << 1,  // colour or depth-stencil attachment
  TextureUsage_Storage = 1u << 2,       // image load/store from compute
  TextureUsage_Default = TextureUsage_Sampled | TextureUsage_RenderTarget,
};

struct TextureDesc {
  TextureType type = TextureType::Tex2D;
  Format format = Format::RGBA8;
  uint32_t width = 1, height = 1;  // Tex1D: height must be 1
  uint32_t depth = 1;      // Tex3D: slices (each mip halves it too); other types: must be 1
  uint32_t layers = 1;     // array layers; Cube: must be 6; Tex3D: must be 1
  uint32_t mipLevels = 1;
  uint32_t samples = 1;    // 1 or 4 (MSAA); MSAA textures are Tex2D, 1 mip, Storage only where
                           // Capabilities::storageMultisample
  uint32_t usage = TextureUsage_Default;
  // Mip 0 of every layer (Tex3D: every slice), tightly packed, row 0 first. D24S8 texels are
  // 32-bit words with the depth in the high 24 bits and the stencil in the low 8; D32F texels
  // are floats, D16 texels 16-bit unorm.
  const void* initialData = nullptr;
  std::string label;
};

// A view reinterprets a texture's memory in another format of the same size class (for example
// RGBA8 storage read as RG16_UNORM), optionally restricted to one layer/mip. Views are
// textures: sample them, render to them, read them back. Destroy views before their parent.
// Where a sampled texel's component comes from (OpenGL's TEXTURE_SWIZZLE_* values, Vulkan's
// VkComponentSwizzle): Identity is the component itself, Zero and One constants.
enum class Swizzle : uint8_t { Identity = 0, Zero, One, Red, Green, Blue, Alpha };

// The component mapping of a view's sampled reads (sampler*, texelFetch, textureGather), per
// result component. Default: identity, every component its own.
struct ComponentMapping {
  Swizzle r = Swizzle::Identity, g = Swizzle::Identity, b = Swizzle::Identity, a = Swizzle::Identity;
  // Every component its own, by Identity or by its own name (Red for r, ...).
  bool isIdentity() const {
    auto own = [](Swizzle s, Swizzle self) { return s == Swizzle::Identity || s == self; };
    return own(r, Swizzle::Red) && own(g, Swizzle::Green) && own(b, Swizzle::Blue) && own(a, Swizzle::Alpha);
  }
  bool operator==(const ComponentMapping&) const = default;
};

struct TextureViewDesc {
  TextureHandle parent;
  Format format = Format::Undefined;  // default: the parent's format
  uint32_t baseLayer = 0;
  uint32_t layerCount = 0;            // 0: all layers from baseLayer
  uint32_t baseMip = 0;
  uint32_t mipCount = 0;              // 0: all mips from baseMip
  // Sampling only (SampledTexture, SeparateTexture): a view with another mapping cannot be an
  // attachment or a StorageTexture (Vulkan wants the identity there; E_VIEW_SWIZZLE).
  // Transfers and readback see the texels as stored.
  ComponentMapping swizzle;
  std::string label;
};

enum class Filter : uint8_t { Nearest = 0, Linear };
enum class MipFilter : uint8_t { None = 0, Nearest, Linear };
enum class AddressMode : uint8_t { ClampToEdge = 0, Repeat, MirroredRepeat, ClampToBorder };
enum class CompareOp : uint8_t { Always = 0, Never, Less, LessEqual, Equal, NotEqual, Greater, GreaterEqual };
// What AddressMode::ClampToBorder returns outside the texture. The Float values are for textures
// sampled as floats (unorm, snorm, float, sRGB, depth), the Int values for integer textures
// (usampler/isampler): 0 or 1 in each channel. Pick the family that matches the texture, as
// on Vulkan (GL and Vulkan leave the other combination undefined).
enum class BorderColor : uint8_t {
  FloatTransparentBlack = 0,  // (0, 0, 0, 0)
  FloatOpaqueBlack,           // (0, 0, 0, 1)
  FloatOpaqueWhite,           // (1, 1, 1, 1)
  IntTransparentBlack,        // (0, 0, 0, 0)
  IntOpaqueBlack,             // (0, 0, 0, 1)
  IntOpaqueWhite,             // (1, 1, 1, 1)
};

struct SamplerDesc {
  Filter minFilter = Filter::Nearest, magFilter = Filter::Nearest;
  MipFilter mipFilter = MipFilter::None;
  AddressMode addressU = AddressMode::ClampToEdge, addressV = AddressMode::ClampToEdge,
              addressW = AddressMode::ClampToEdge;
  bool compareEnabled = false;            // depth comparison (hardware PCF)
  CompareOp compare = CompareOp::LessEqual;
  BorderColor borderColor = BorderColor::FloatTransparentBlack;  // used by ClampToBorder only
  // The level of detail's clamp and bias (OpenGL's TEXTURE_MIN_LOD, _MAX_LOD and _LOD_BIAS;
  // Vulkan's minLod, maxLod and mipLodBias). The defaults are OpenGL's: no clamp, no bias.
  // Without a mip filter only the base level is read, whatever they say.
  float minLod = -1000.0f, maxLod = 1000.0f;  // minLod <= maxLod
  float mipLodBias = 0.0f;                    // |mipLodBias| <= Capabilities::maxSamplerLodBias
  std::string label;
};

// ---------------------------------------------------------------------------------------------
// Shaders (SPIR-V in; the GL backend cross-compiles it to GLSL 450 core)
// ---------------------------------------------------------------------------------------------
enum class ShaderStage : uint8_t { Vertex = 0, Fragment, Compute, Geometry, TessControl, TessEvaluation };

// Binding model, the same on both APIs: every resource lives in descriptor set 0 at a binding
// number below kMaxBindings; a push-constant block of at most kMaxPushConstantBytes holds small
// per-draw data. A binding may hold an array of up to kMaxArrayElements resources of its kind
// (`uniform sampler2D s[4]`, `buffer B { } b[2]`; one-dimensional, sized; a Vulkan descriptor
// array), each bound by its own ResourceBinding::arrayElement.
// On GL (rhi/gl/gl_pipeline.cpp, assignGlBindingPoints) element e of binding b becomes UBO/SSBO
// binding point, texture unit or image unit P(b) + e, where P(b) = b + the sum of (arraySize - 1)
// over the bindings below b that the pipeline declares: without arrays, binding N is point N.
// The push-constant block becomes a UBO (or a read-only SSBO when std430 needs it) at point
// P(kMaxBindings), which no user binding can take (kMaxBindings without arrays).
constexpr uint32_t kMaxBindings = 16;
constexpr uint32_t kMaxArrayElements = 16;
// Distinct (SeparateTexture, SeparateSampler) pairs one pipeline's shaders may combine. On GL,
// pair k (in order of texture binding, then sampler binding) is texture unit P(kMaxBindings) + k.
constexpr uint32_t kMaxSeparatePairs = 16;
constexpr uint32_t kMaxPushConstantBytes = 128;
constexpr uint32_t kMaxColorTargets = 4;
constexpr uint32_t kMaxViewports = 16;  // Capabilities::viewports is at most this
constexpr uint32_t kMaxVertexAttributes = 16;  // GL_MAX_VERTEX_ATTRIBS and maxVertexInputAttributes minimums
constexpr uint32_t kMaxVertexBuffers = 4;

struct ShaderDesc {
  ShaderStage stage = ShaderStage::Vertex;
  std::vector<uint32_t> spirv;  // required
  std::string entryPoint = "main";
  std::string label;            // usually the source file name
  // OpenGL GLSL of which `spirv` is the port (a shader test's shader as its author wrote it for
  // OpenGL), as compilation units of this stage (OpenGL links several shader objects into one).
  // A device with DeviceInfo feature "openGlGlsl" (GL) gives these to its driver in place of the
  // SPIR-V; the others run the port. The port's interface places the program's: input and output
  // names take the port's locations, blocks, samplers and images by name the port's bindings, and
  // the members of the port's block named `looseUniformBlock` are copied from that block's bound
  // buffer into the program's uniforms at each draw and dispatch. All stages of a pipeline have
  // it or none, and such a pipeline draws with OpenGL's clip-space depth (-w..w; the RHI's 0..w).
  std::vector<std::string> openGlGlsl;
  // Default: the block glslang gathers loose uniforms into (ShaderCompileOptions::openGlSource).
  std::string looseUniformBlock = "gl_DefaultUniformBlock";
  // An ARB assembly program of the Vertex or Fragment stage ("!!ARBvp1.0" / "!!ARBfp1.0" ...
  // "END", OpenGL's ARB_vertex_program and ARB_fragment_program), of which `spirv` is the port:
  // the port declares each texture[N] the program reads as a sampler of its target at binding N,
  // which the program reads as texture unit N, and a vertex program reads attribute location L as
  // vertex.attrib[L] (location 0 is also vertex.position). A device with DeviceInfo feature
  // "arbAssemblyPrograms" (GL in a compatibility context) gives it to its driver; the others
  // refuse the shader with a note (takeNotes). All stages of a pipeline have one or none; such a
  // pipeline draws with OpenGL's clip-space depth (-w..w) and reads the state that
  // setProgramParameter, setTransformMatrices and setCurrentAttribute set.
  std::string arbProgram;
};

// ---------------------------------------------------------------------------------------------
// Pipelines
// ---------------------------------------------------------------------------------------------
// UInt* and Int* are read as uint/uvecN and int/ivecN (not converted to float). Double* are
// 64-bit components read as double/dvecN (Double3 and Double4 take two locations, the next one
// free for no other attribute); they need Capabilities::doubleVertexFormats.
enum class VertexFormat : uint8_t {
  Float = 0, Float2, Float3, Float4, UByte4Norm, UInt, UInt2, UInt4, UInt3, Int, Int2, Int3, Int4,
  Double, Double2, Double3, Double4
};
// The *WithAdjacency lists feed a geometry shader the neighbours of each primitive (4 vertices per
// line, 6 per triangle); they need DeviceInfo::features "geometryShader".
enum class PrimitiveTopology : uint8_t {
  Triangles = 0, TriangleStrip, Lines, Points, LineStrip, Patches,
  LinesWithAdjacency, LineStripWithAdjacency, TrianglesWithAdjacency, TriangleStripWithAdjacency
};
enum class IndexType : uint8_t { UInt32 = 0, UInt16 };
enum class CullMode : uint8_t { None = 0, Front, Back };
enum class FrontFace : uint8_t { CounterClockwise = 0, Clockwise };
// How triangles are rasterised: filled, as their edges (lines), or as their vertices (points).
// Line and Point need DeviceInfo::features "fillModeNonSolid".
enum class PolygonMode : uint8_t { Fill = 0, Line, Point };
enum class BlendFactor : uint8_t {
  One = 0, Zero, SrcColor, OneMinusSrcColor, DstColor, OneMinusDstColor, SrcAlpha,
  OneMinusSrcAlpha, DstAlpha, OneMinusDstAlpha, ConstantColor, OneMinusConstantColor
};
enum class BlendOp : uint8_t { Add = 0, Subtract, ReverseSubtract, Min, Max };
enum class StencilOp : uint8_t {
  Keep = 0, Zero, Replace, IncrementClamp, DecrementClamp, Invert, IncrementWrap, DecrementWrap
};
enum ColorMask : uint8_t { ColorMask_R = 1, ColorMask_G = 2, ColorMask_B = 4, ColorMask_A = 8, ColorMask_All = 0xF };

struct VertexAttribute {
  uint32_t location = 0;
  VertexFormat format = VertexFormat::Float;
  uint32_t offset = 0;       // bytes from the start of the vertex
  uint32_t bufferSlot = 0;   // which VertexBufferLayout / setVertexBuffer slot
};

struct VertexBufferLayout {
  // Bytes between elements. 0: every vertex (or instance) reads the one element at the slot's
  // offset, a constant attribute (Vulkan's and GL's vertex bindings both read a stride of 0 so).
  uint32_t stride = 0;
  bool perInstance = false;  // default: per vertex
};

struct BlendState {
  bool enabled = false;  // default: no blending, the output replaces the target
  BlendFactor srcColor = BlendFactor::One, dstColor = BlendFactor::Zero;
  BlendOp colorOp = BlendOp::Add;
  BlendFactor srcAlpha = BlendFactor::One, dstAlpha = BlendFactor::Zero;
  BlendOp alphaOp = BlendOp::Add;  // Min/Max ignore the factors, as on both APIs
};

struct ColorTargetState {
  Format format = Format::Undefined;  // must match the attachment bound at draw time
  BlendState blend;
  uint8_t writeMask = ColorMask_All;
};

struct StencilFaceState {
  CompareOp compare = CompareOp::Always;
  StencilOp fail = StencilOp::Keep, depthFail = StencilOp::Keep, pass = StencilOp::Keep;
};

struct DepthStencilState {
  CompareOp depthCompare = CompareOp::Always;  // default: depth test passes everything
  bool depthWrite = false;                     // default: depth not written
  bool stencilEnabled = false;
  StencilFaceState front, back;  // two-sided stencil: back applies to back-facing triangles
  uint8_t stencilReadMask = 0xFF, stencilWriteMask = 0xFF;
};

// Depth bias, Vulkan's definition on every backend: each fragment's depth is offset by
//   o = constantFactor * r + slopeFactor * m, then min(o, clamp) for clamp > 0, max(o, clamp) for
//   clamp < 0,
// where m is the triangle's maximum depth slope and r the depth format's minimum resolvable
// difference: D24S8 one step, 1 / (2^24 - 1), or twice that (the device's, as in Vulkan; Mesa: twice);
// D32F 2^(e - 23), e the exponent of the triangle's largest |depth|. Fill, Line and Point alike.
struct DepthBias {
  float constantFactor = 0;  // default 0 and slopeFactor 0: no bias
  float slopeFactor = 0;
  float clamp = 0;           // default: not clamped; else needs DeviceInfo::features "depthBiasClamp"
};

enum class ProvokingVertex { First, Last };

struct RasterState {
  CullMode cull = CullMode::None;
  FrontFace frontFace = FrontFace::CounterClockwise;
  bool scissorEnabled = false;  // default: scissor rectangle ignored
  PolygonMode polygonMode = PolygonMode::Fill;
  // Default: primitives are clipped to the viewport's depth range. Enabled (needs
  // DeviceInfo::features "depthClamp"): not clipped in z; fragment depths are clamped to it.
  bool depthClampEnabled = false;
  DepthBias depthBias;
  // Default: First, the vertex whose values flat inputs take (Vulkan's convention). Last is
  // OpenGL's default (needs DeviceInfo::features "provokingVertexLast").
  ProvokingVertex provokingVertex = ProvokingVertex::First;
};

struct PipelineDesc {
  ShaderHandle vertexShader, fragmentShader;  // both required
  // Optional stages between them: a geometry shader, and tessellation as a pair (control and
  // evaluation, drawn as Patches of patchControlPoints vertices, 1..32).
  ShaderHandle geometryShader, tessControlShader, tessEvaluationShader;
  uint32_t patchControlPoints = 0;
  std::array<VertexAttribute, kMaxVertexAttributes> attributes{};
  uint32_t attributeCount = 0;                // default: no vertex input (vertices from gl_VertexIndex)
  std::array<VertexBufferLayout, kMaxVertexBuffers> vertexBuffers{};
  PrimitiveTopology topology = PrimitiveTopology::Triangles;
  RasterState raster;
  DepthStencilState depthStencil;
  std::array<ColorTargetState, kMaxColorTargets> colorTargets{};
  uint32_t colorTargetCount = 0;
  Format depthStencilFormat = Format::Undefined;  // default: no depth-stencil attachment
  uint32_t samples = 1;
  // Stages from OpenGL GLSL (ShaderDesc::openGlGlsl) on a device that gives it to its driver link
  // as one separable program (OpenGL's GL_PROGRAM_SEPARABLE), under the rules OpenGL adds for
  // those: e.g. a stage that uses gl_PerVertex members must redeclare the block, or the pipeline
  // fails with the driver's log (takeNotes). Default false: an ordinary program. Other shaders
  // are separate modules on every backend already: it changes nothing for them.
  bool separablePrograms = false;
  std::string label;
};

struct ComputePipelineDesc {
  ShaderHandle computeShader;  // required
  // Subgroup size control (Capabilities::subgroupSizeControl; Vulkan 1.3's form of
  // VK_EXT_subgroup_size_control). The defaults leave the subgroups to the device.
  // requiredSubgroupSize: 0, or a power of two in [minSubgroupSize, maxSubgroupSize] that every
  // subgroup of the dispatch has. fullSubgroups: every subgroup is full (the shader's local size x
  // must be a multiple of the subgroup size: of maxSubgroupSize without a required size).
  // varyingSubgroupSize: the size may differ between subgroups (SubgroupSize then reads the
  // largest, as Vulkan's ALLOW_VARYING_SUBGROUP_SIZE).
  uint32_t requiredSubgroupSize = 0;
  bool fullSubgroups = false;
  bool varyingSubgroupSize = false;
  std::string label;
};

// ---------------------------------------------------------------------------------------------
// Passes and commands
// ---------------------------------------------------------------------------------------------
enum class LoadOp : uint8_t { Clear = 0, Load, DontCare };

struct ColorAttachment {
  TextureHandle texture;           // null: slot unused
  uint32_t layer = 0, mip = 0;     // array layer / cube face / Tex3D slice and mip level rendered to
  LoadOp load = LoadOp::Clear;
  std::array<float, 4> clearColor{0, 0, 0, 0};
  TextureHandle resolveTarget;     // MSAA only: single-sample texture whose layer 0, mip 0 is
                                   // resolved to at endPass
};

struct DepthStencilAttachment {
  TextureHandle texture;           // null: no depth-stencil
  uint32_t layer = 0;
  LoadOp load = LoadOp::Clear;
  float clearDepth = 1.0f;
  uint8_t clearStencil = 0;
};

struct PassDesc {
  std::array<ColorAttachment, kMaxColorTargets> colors{};
  DepthStencilAttachment depthStencil;
  std::string label;  // shows up in timestamps and debug output
};

struct Viewport {
  float x = 0, y = 0;            // may be fractional
  float width = 0, height = 0;   // 0: the pass's full attachment size
  float minDepth = 0, maxDepth = 1;
};

struct Rect {
  int32_t x = 0, y = 0;
  uint32_t width = 0, height = 0;
};

// SampledTexture is a combined texture + sampler (GLSL sampler2D, ...). SeparateTexture and
// SeparateSampler are the two halves a shader combines itself (Vulkan GLSL texture2D and
// sampler, `texture(sampler2D(tex, smp), uv)`): each has its own binding number. A shader may
// combine up to kMaxSeparatePairs distinct (texture, sampler) binding pairs.
// UniformTexelBuffer and StorageTexelBuffer read a buffer range as a 1D array of texels of
// ResourceBinding::texelFormat (GLSL samplerBuffer with texelFetch, imageBuffer with
// imageLoad/imageStore).
enum class BindingKind : uint8_t {
  UniformBuffer = 0, StorageBuffer, SampledTexture, StorageTexture, SeparateTexture, SeparateSampler,
  UniformTexelBuffer, StorageTexelBuffer
};

// One resource bound at `binding` (set 0) for the next draws or dispatches.
struct ResourceBinding {
  uint32_t binding = 0;
  // Which element of an arrayed binding this resource is (below kMaxArrayElements); default 0,
  // the only element of a binding that is not an array. A draw needs every element of every
  // array its pipeline declares.
  uint32_t arrayElement = 0;
  BindingKind kind = BindingKind::UniformBuffer;
  BufferHandle buffer;        // UniformBuffer, StorageBuffer, UniformTexelBuffer, StorageTexelBuffer
  size_t offset = 0, size = 0;  // size 0: to the end of the buffer
  // UniformTexelBuffer, StorageTexelBuffer: the texels' format (one of RGBA8, RGBA8_UINT,
  // R32_UINT, R32F, RG32F, RGBA16F, RGBA32F); the bound size is a whole number of texels.
  Format texelFormat = Format::Undefined;
  TextureHandle texture;      // SampledTexture, StorageTexture, SeparateTexture
  SamplerHandle sampler;      // SampledTexture, SeparateSampler; null: a nearest/clamp default
                              // (LessEqual comparison for sampler2DShadow). A usampler on a
                              // D24S8 texture reads its stencil.
  uint32_t mip = 0;           // StorageTexture: mip level bound
};

enum class TextureAspect : uint8_t { Color = 0, Depth, Stencil };

struct ReadbackRegion {
  uint32_t layer = 0, mip = 0;  // Tex3D: layer is the depth slice (of that mip)
  TextureAspect aspect = TextureAspect::Color;
};

// ---------------------------------------------------------------------------------------------
// Device
// ---------------------------------------------------------------------------------------------
struct DeviceDesc {
  std::string backend = "gl";   // "gl" or "vk"
  // GL only: "egl" (surfaceless EGL, default) or "osmesa".
  std::string glContextProvider = "egl";
  bool debug = false;           // GL debug context / Vulkan validation layer, messages to log
  // GL only: an OpenGL 4.5 compatibility-profile context, whose GLSL has what GLSL 1.10-1.50
  // shaders read (gl_Vertex, gl_Color, gl_FragColor ...; ShaderDesc::openGlGlsl). What the RHI
  // defines behaves as in a core context (point sprites stay on).
  bool glCompatibilityProfile = false;
  // Which of the backend's devices (default: the system's). GL: a Mesa Gallium driver by name
  // ("llvmpipe", "zink": OpenGL over the process's Vulkan device), chosen through Mesa's
  // GALLIUM_DRIVER for the whole process when its first GL device is made (one GL driver per
  // process); creation fails when the context's renderer does not name it. Vulkan: the first
  // physical device whose name contains this text (PARITY_VK_DEVICE when empty).
  std::string adapter;
  // Called for every debug/validation message of the driver; default: printed to stderr.
  std::function<void(const std::string&)> log;
  // Wrap the backend in parity's own validation layer (rhi/validation.h). A call that breaks a
  // rule is reported with a stable id and dropped (creation returns a null handle).
  bool validation = true;
  // Called with (id, message) for every rule broken; default: printed to stderr.
  std::function<void(const std::string& id, const std::string& message)> onValidationError;
};

// The names of the devices `backend` could give with DeviceDesc::adapter (Vulkan: its physical
// devices' names; GL: the Mesa Gallium drivers parity knows, which need not all load here).
std::vector<std::string> adapterNames(const std::string& backend);

// What a backend offers; techniques branch on these, never on the API name.
struct Capabilities {
  uint32_t maxSamples = 4;
  bool textureViews = true;
  bool compute = true;
  bool timestamps = true;
  bool independentBlend = true;
  bool subgroups = true;  // subgroup operations in shaders (GL: needs GL_KHR_shader_subgroup)
  // ComputePipelineDesc's subgroup size control, and the sizes a compute subgroup may have
  // (0 where unknown). GL: none, OpenGL has no control of the subgroup size.
  bool subgroupSizeControl = false;
  uint32_t minSubgroupSize = 0, maxSubgroupSize = 0;
  // Arrays of SeparateSampler (`uniform sampler s[2]`). GL: false, SPIRV-Cross cannot combine
  // them into GLSL sampler2D arrays (arrays of SeparateTexture it can).
  bool separateSamplerArrays = true;
  // TextureUsage_Storage on multisampled textures (image2DMS load/store from compute).
  bool storageMultisample = false;
  // VertexFormat::Double..Double4 (GL: core since 4.1; Vulkan: the device's vertex buffer formats).
  bool doubleVertexFormats = false;
  // Output locations (vec4 slots) a stage may write, indexed by ShaderStage: every output's
  // Location plus the locations its type takes stays within it (Vulkan: max<Stage>OutputComponents
  // / 4, a tessellation control shader's patch outputs sharing the per-vertex locations; GL:
  // GL_MAX_<STAGE>_OUTPUT_COMPONENTS / 4). Fragment and compute: 0, not counted this way. The
  // default is Vulkan's minimum for the vertex stage.
  std::array<uint32_t, 6> maxOutputLocations{16, 0, 0, 16, 16, 16};
  // Viewport indices a shader may select (ViewportIndex, gl_ViewportIndex): setViewport and
  // setScissor set every one of them alike, as glViewport and glScissor do (GL: GL_MAX_VIEWPORTS;
  // Vulkan: maxViewports with the multiViewport feature, else 1).
  uint32_t viewports = 1;
  // The largest |SamplerDesc::mipLodBias| (GL: GL_MAX_TEXTURE_LOD_BIAS; Vulkan: maxSamplerLodBias;
  // both at least 2).
  float maxSamplerLodBias = 2.0f;
};

struct DeviceInfo {
  std::string backend;      // "gl" or "vk"
  std::string api;          // "OpenGL 4.5 (Core Profile) Mesa 22.3.6", "Vulkan 1.3.230"
  std::string renderer;     // "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string driver;       // "Mesa 22.3.6", ...
  std::string contextProvider;  // GL: "egl" or "osmesa"; Vulkan: ICD json or empty
  Capabilities caps;
  // What shaders may use, by Vulkan's names, so that shader tests check their requirements
  // against the device: features as members of VkPhysicalDeviceFeatures and
  // VkPhysicalDeviceVulkan11/12/13Features ("shaderFloat64", "storageBuffer16BitAccess"),
  // extensions as VK_* names. Vulkan: what the physical device offers (its features are all
  // enabled); GL: the features and extensions whose shaders its context runs once translated.
  std::vector<std::string> features;
  std::vector<std::string> extensions;
  // Devices with feature "openGlGlsl": the OpenGL extensions (GL_ARB_...) of the context whose
  // driver compiles ShaderDesc::openGlGlsl.
  std::vector<std::string> openGlExtensions;
  // Boolean device properties that hold, by Vulkan's member names: the float controls of
  // VkPhysicalDeviceVulkan12Properties ("shaderSignedZeroInfNanPreserveFloat32",
  // "shaderDenormPreserveFloat16", ...). GL: none; OpenGL does not report them.
  std::vector<std::string> properties;
};

// Timestamps are read back in nanoseconds on one monotonic clock per device.
using TimestampId = uint32_t;

class Device {
 public:
  virtual ~Device() = default;
  virtual const DeviceInfo& info() const = 0;

  // --- resources ---
  virtual BufferHandle createBuffer(const BufferDesc& desc) = 0;
  virtual TextureHandle createTexture(const TextureDesc& desc) = 0;
  virtual TextureHandle createTextureView(const TextureViewDesc& desc) = 0;
  virtual SamplerHandle createSampler(const SamplerDesc& desc) = 0;
  virtual ShaderHandle createShader(const ShaderDesc& desc) = 0;
  virtual PipelineHandle createPipeline(const PipelineDesc& desc) = 0;
  virtual ComputePipelineHandle createComputePipeline(const ComputePipelineDesc& desc) = 0;
  virtual void destroy(BufferHandle h) = 0;
  virtual void destroy(TextureHandle h) = 0;
  virtual void destroy(SamplerHandle h) = 0;
  virtual void destroy(ShaderHandle h) = 0;
  virtual void destroy(PipelineHandle h) = 0;
  virtual void destroy(ComputePipelineHandle h) = 0;
  // The descriptor a live handle was created with (views: their own desc resolved against the
  // parent). Used by validation, platform layers and readback sizing.
  virtual const BufferDesc* describe(BufferHandle h) const = 0;
  virtual const TextureDesc* describe(TextureHandle h) const = 0;

  // --- data transfer (ordered with the recorded commands; outside passes) ---
  virtual void writeBuffer(BufferHandle h, size_t offset, const void* data, size_t size) = 0;
  // Tightly packed texels of one layer/mip (Tex3D: one depth slice of the mip), row 0 first.
  virtual void writeTexture(TextureHandle h, uint32_t layer, uint32_t mip, const void* data) = 0;
  // Finishes all recorded work, then reads. Buffer: raw bytes.
  virtual std::vector<uint8_t> readBuffer(BufferHandle h, size_t offset, size_t size) = 0;
  // Finishes all recorded work, then reads one layer/mip, tightly packed, memory row 0 first.
  // Color aspect: the texels in the texture's format (snorm: the most negative value, a second
  // encoding of -1.0, may come back as -1.0's other encoding on GL, which converts on upload).
  // Depth aspect (depth formats): one float per pixel, D24 values as q / 16777215 and D16 as
  // q / 65535, correctly rounded. Stencil aspect: one byte per pixel.
  // MSAA textures cannot be read; resolve them first.
  virtual std::vector<uint8_t> readTexture(TextureHandle h, const ReadbackRegion& region = {}) = 0;
  // Copies between two textures of the same size class, whole layer/mip, outside passes.
  virtual void copyTexture(TextureHandle src, TextureHandle dst, const ReadbackRegion& srcRegion = {},
                           const ReadbackRegion& dstRegion = {}) = 0;
  virtual void copyBuffer(BufferHandle src, size_t srcOffset, BufferHandle dst, size_t dstOffset,
                          size_t size) = 0;

  // --- render passes ---
  virtual void beginPass(const PassDesc& desc) = 0;
  virtual void endPass() = 0;  // resolves MSAA attachments with a resolveTarget
  virtual void setPipeline(PipelineHandle h) = 0;  // resets viewport/scissor to the full pass
  virtual void setViewport(const Viewport& vp) = 0;
  virtual void setScissor(const Rect& r) = 0;
  // Stencil reference and blend constant persist across pipelines and passes until set again.
  virtual void setStencilReference(uint8_t ref) = 0;
  virtual void setBlendConstant(const std::array<float, 4>& c) = 0;
  virtual void setVertexBuffer(uint32_t slot, BufferHandle h, size_t offset = 0) = 0;
  virtual void setIndexBuffer(BufferHandle h, IndexType type, size_t offset = 0) = 0;
  virtual void draw(uint32_t vertexCount, uint32_t instanceCount = 1, uint32_t firstVertex = 0,
                    uint32_t firstInstance = 0) = 0;
  virtual void drawIndexed(uint32_t indexCount, uint32_t instanceCount = 1, uint32_t firstIndex = 0,
                           int32_t vertexOffset = 0, uint32_t firstInstance = 0) = 0;

  // --- compute (outside passes) ---
  virtual void setComputePipeline(ComputePipelineHandle h) = 0;
  virtual void dispatch(uint32_t x, uint32_t y = 1, uint32_t z = 1) = 0;

  // --- shared by draws and dispatches: set before draw/dispatch, kept until replaced ---
  // Merges: each entry replaces only the (binding, arrayElement) it names; others stay bound.
  virtual void setBindings(std::span<const ResourceBinding> bindings) = 0;
  virtual void pushConstants(const void* data, uint32_t size) = 0;

  // --- ARB assembly programs (ShaderDesc::arbProgram): state they read, kept until set again ---
  // program.env[index] of the stage's programs (local = false), or program.local[index] of the
  // bound pipeline's program of the stage (local = true; set after setPipeline). Stage: Vertex
  // or Fragment. Devices without feature "arbAssemblyPrograms" ignore it.
  virtual void setProgramParameter(ShaderStage stage, bool local, uint32_t index, const std::array<float, 4>& value) {
    (void)stage, (void)local, (void)index, (void)value;
  }
  // OpenGL's model-view and projection matrices (column-major), which state.matrix.* and
  // OPTION ARB_position_invariant read. Initially the identity.
  virtual void setTransformMatrices(const std::array<float, 16>& modelView, const std::array<float, 16>& projection) {
    (void)modelView, (void)projection;
  }
  // OpenGL's current vertex attributes, which a vertex program reads where no vertex attribute
  // supplies them: the colour (glColor4f; vertex.color, index 0) and texture coordinates `index`
  // (glMultiTexCoord4f; vertex.texcoord[index], below 8). Initially (1, 1, 1, 1) and (0, 0, 0, 1).
  enum class CurrentAttribute : uint8_t { Color = 0, TexCoord };
  virtual void setCurrentAttribute(CurrentAttribute attribute, uint32_t index, const std::array<float, 4>& value) {
    (void)attribute, (void)index, (void)value;
  }

  // --- timing ---
  // Records a GPU timestamp after all previously recorded work (outside passes).
  virtual TimestampId writeTimestamp() = 0;
  // Nanoseconds; valid after submit(). nullopt for an id not written since the last reset.
  virtual std::optional<uint64_t> timestampNs(TimestampId id) = 0;
  virtual void resetTimestamps() = 0;

  // Executes everything recorded so far and waits for the GPU.
  virtual void submit() = 0;

  // What the backend did, since the last call, that differs from its usual path and that a test
  // report should say (one line each). GL: a module whose SPIRV-Cross GLSL fails to compile or
  // link ran through GL_ARB_gl_spirv instead (the GLSL's failure is a translator finding); the
  // driver's log of ShaderDesc::openGlGlsl that does not compile or link (the shader's own error,
  // so not a debug message: the creation returns a null handle).
  virtual std::vector<std::string> takeNotes() { return {}; }
};

// Creates a device by backend name. On failure returns null and sets *whyNot to a one-line
// reason (e.g. "no Vulkan ICD found (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER)").
std::unique_ptr<Device> createDevice(const DeviceDesc& desc, std::string* whyNot);

// Backends compiled into this build, in preference order.
std::vector<std::string> compiledBackends();

// Loads the libraries createDevice() loads for every compiled backend (the Vulkan loader's
// drivers, implicit layers and validation layer; EGL's vendors and Mesa's DRI driver), found the
// way their loaders find them, and creates nothing: no instance, display, context or thread. A
// process that forks children which each create a device calls it once before its first fork,
// so that every child finds the drivers mapped and relocated instead of loading them anew (the
// dynamic linker's symbol lookups were most of a script case's device creation: docs/BENCH.md).
// Returns the libraries loaded; one that does not load is left for createDevice() to report.
std::vector<std::string> preloadDriverLibraries();

}  // namespace parity::rhi
