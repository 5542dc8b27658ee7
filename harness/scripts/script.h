// Shader-test scripts: a subset of Google's AmberScript (same spelling, same meaning) plus a few
// extensions of ours (REQUIRE, SET PLATFORM_PARAM, LOGICAL images resolved by the platform layer,
// RESOLVE, EXPECT ... MEMORY BYTES, EXPECT ... EQ_IMAGE). docs/script-format.md has the grammar.
//
// parseScript() turns a file into a Script; it never touches a GPU. Constructs that are valid
// AmberScript but that this runner cannot execute (DEVICE_EXTENSION, SPIR-V assembly shaders,
// REPEAT, ...) parse and are listed in Script::unsupported, so that the runner reports the case
// as skipped with the missing feature named, never as a silent pass. Anything else that does not
// parse is an error naming the file, line and column.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace parity::harness::script {

// What one script may ask for: a buffer or image larger than this, or an image or framebuffer
// side longer than this, is a parse error naming the line (docs/script-format.md, "Limits").
inline constexpr uint64_t kMaxBufferBytes = 256ull << 20;
inline constexpr uint32_t kMaxImageDimension = 16384;

struct Location {
  int line = 0, column = 0;  // 1-based; 0: unknown
};

// ---------------------------------------------------------------------------------------------
// Data types and buffer layouts
// ---------------------------------------------------------------------------------------------
enum class Scalar : uint8_t { Int8, Int16, Int32, Int64, Uint8, Uint16, Uint32, Uint64, Float16, Float32, Float64 };
enum class Mode : uint8_t { Int, Uint, Float, Unorm, Snorm, Srgb };

uint32_t scalarSize(Scalar s);

// One component of an element, at a byte offset within the element.
struct Field {
  uint32_t offset = 0;
  Scalar scalar = Scalar::Float32;
  Mode mode = Mode::Float;
  char channel = 0;  // FORMAT buffers: 'R', 'G', 'B', 'A', 'D', 'S'; DATA_TYPE buffers: 0
};

struct Layout {
  std::vector<Field> fields;  // in value order (the order DATA and EXPECT values are given)
  uint32_t stride = 0;        // bytes per element
};

// Element type of a BUFFER/IMAGE: either a DATA_TYPE (int32, vec3<float>, mat2x4<float>, ...;
// std430 by default, STD140 on request) or a FORMAT (R8G8B8A8_UNORM, ...; tightly packed).
struct ElementType {
  bool isFormat = false;
  std::string name;          // as written: "vec3<float>" or "B8G8R8A8_UNORM"
  Scalar scalar = Scalar::Float32;
  uint32_t rows = 1, columns = 1;  // vecN: rows = N; matCxR: columns C of R rows
  bool std140 = false;
  Layout layout;             // computed by the parser
};

// Parses a DATA_TYPE name (Amber spelling). False with a message when unknown.
bool parseDataType(const std::string& text, bool std140, ElementType* out, std::string* error);
// Parses an Amber/Vulkan format name (R8G8B8A8_UNORM, D32_SFLOAT_S8_UINT, ...).
bool parseFormat(const std::string& text, ElementType* out, std::string* error);

// ---------------------------------------------------------------------------------------------
// Declarations
// ---------------------------------------------------------------------------------------------
enum class Stage : uint8_t { Vertex, Fragment, Compute, Geometry, TessControl, TessEvaluation };

struct Shader {
  std::string name;
  Stage stage = Stage::Vertex;
  bool passthrough = false;  // SHADER vertex NAME PASSTHROUGH
  // GLSL, SPIRV-ASM or SPIRV-BIN (FILE); others are unsupported. ARB: an ARB assembly program
  // (piglit's [vertex program] and [fragment program]; rhi::ShaderDesc::arbProgram).
  std::string format = "GLSL";
  std::string source;        // GLSL or SPIR-V assembly; SPIRV-BIN: the file's bytes
  int sourceLine = 0;        // line of the first source line in the script
  // OpenGL GLSL (piglit's shader_test files): loose uniforms, no explicit locations; compiled with
  // rhi::ShaderCompileOptions::openGlSource and its uniforms set by name (Command::Kind::SetUniform).
  bool openGl = false;
  int glslVersion = 110;  // openGl: the version of a shader without #version ([require] GLSL >= ...)
  // piglit's SPIR-V programs (GL_ARB_gl_spirv): OpenGL's bindings, a sampler at binding B reading
  // texture unit B (element E of an array of them: unit B + E).
  bool openGlSpirv = false;
  int spirvMinor = 0;     // TARGET_ENV spv1.x (SPIR-V assembly is assembled for that version)
  Location loc;
  // shader_test files: further GLSL sections of the same stage, linked with this one as OpenGL
  // links several shader objects of one stage (rhi::ShaderCompileOptions::linkedSources).
  struct LinkedUnit {
    std::string source;
    int sourceLine = 0;
  };
  std::vector<LinkedUnit> linkedUnits;
};

struct Buffer {
  std::string name;
  bool isImage = false;  // IMAGE
  bool hasType = false;  // DATA_TYPE or FORMAT given
  ElementType type;
  std::vector<uint8_t> bytes;  // initial contents (DATA, SIZE + FILL/SERIES_FROM); may be empty
  bool sized = false;          // SIZE or DATA given (else: sized by its use, e.g. a framebuffer)
  uint32_t width = 0, height = 0, depth = 1;  // IMAGE
  uint32_t samples = 1, mipLevels = 1;
  std::string dim = "DIM_2D";
  std::string viewOf;  // ours: IMAGE name FORMAT f VIEW_OF parent (a texture view of parent)
  // Ours: IMAGE name LOGICAL rg16_unorm|rgba8_unorm|rgba16_hdr|depth24_stencil8: a logical target
  // whose real format, resolve and console memory layout the platform layer decides.
  std::string logical;
  int textureUnit = -1;  // shader_test: the OpenGL texture unit the image is on (`texture rgbw 0 ...`)
  int imageUnit = -1;    // shader_test: the OpenGL image unit it is bound to (`image texture N`)
  uint32_t layers = 1;   // shader_test: the layers of an array texture (`texture rgbw 2DArray ...`)
  bool arrayTexture = false;  // shader_test: an array texture, of one layer too (`... 2DArray 0 (w, h, 1)`)
  int atomicCounterBinding = -1;  // shader_test: the OpenGL atomic-counter buffer binding it is (`atomic counters N`)
  Location loc;
};

struct Sampler {
  std::string name;
  bool linearMag = false, linearMin = false;
  std::string mipmapMode = "nearest";
  std::array<std::string, 3> addressMode{"repeat", "repeat", "repeat"};
  std::string borderColor = "float_transparent_black";  // BORDER_COLOR, lower case
  // The level of detail's clamp (MIN_LOD, MAX_LOD: Amber's defaults 0 and 1; piglit's OpenGL
  // ones -1000 and 1000) and bias (piglit's `texparameter lod_bias`).
  double minLod = 0.0, maxLod = 1.0, lodBias = 0.0;
  bool compare = false;                   // COMPARE on: a depth comparison sampler
  std::string compareOp = "never";        // COMPARE_OP, lower case (Amber's default never)
  int textureUnit = -1;  // shader_test: the state of that OpenGL texture unit's texture (`texparameter`)
  // shader_test: the levels of that texture the sampler reads (GL_TEXTURE_BASE_LEVEL, _MAX_LEVEL).
  uint32_t baseLevel = 0, maxLevel = 1000;
  // shader_test: where that texture's sampled r, g, b and a come from (GL_TEXTURE_SWIZZLE_R.._A):
  // red, green, blue, alpha, zero or one.
  std::array<std::string, 4> swizzle{"red", "green", "blue", "alpha"};
  Location loc;
};

enum class BindKind : uint8_t {
  Color, DepthStencil, Resolve, Storage, Uniform, CombinedImageSampler, SampledImage, StorageImage,
  Sampler, PushConstant, UniformTexelBuffer, StorageTexelBuffer, Other
};

struct Bind {
  BindKind kind = BindKind::Color;
  std::string buffer;    // buffer/image name (or sampler name for BindKind::Sampler)
  std::string sampler;   // CombinedImageSampler
  std::string asWord;    // the AS word as written
  uint32_t location = 0; // Color
  uint32_t set = 0, binding = 0;
  uint32_t arrayElement = 0;  // BUFFER_ARRAY / SAMPLER_ARRAY: one Bind per element, in order
  uint32_t baseMipLevel = 0;  // colour attachments and images: the mip level bound (and up)
  // Storage/Uniform buffers: the bound range. Amber's dynamic buffers (storage_dynamic,
  // uniform_dynamic) are bound like the plain ones with their dynamic OFFSET added to
  // DESCRIPTOR_OFFSET: the RHI binds a buffer range, the result is the same.
  uint64_t offset = 0, range = 0;  // range 0: to the end of the buffer
  Location loc;
};

struct VertexData {
  std::string buffer;
  uint32_t location = 0;
  bool perInstance = false;
  uint32_t offset = 0, stride = 0;  // stride 0: the element size
  std::string format;               // FORMAT override; empty: the buffer's type
  // shader_test: the vertex shader input of this name (its location is read from the compiled
  // shader, plus locationOffset: an array element's or a matrix column's); empty: `location`.
  std::string attribute;
  uint32_t locationOffset = 0;
  Location loc;
};

struct StencilFace {
  bool test = false;
  std::string failOp = "keep", passOp = "keep", depthFailOp = "keep", compareOp = "always";
  uint32_t compareMask = 0xFF, writeMask = 0xFF, reference = 0;
};

struct BlendSettings {
  bool enabled = false;
  std::string srcColor = "one", dstColor = "zero", colorOp = "add";
  std::string srcAlpha = "one", dstAlpha = "zero", alphaOp = "add";
  std::array<float, 4> constant{0, 0, 0, 0};  // ours: CONSTANT r g b a inside BLEND
};

// SUBGROUP in a PIPELINE: subgroup size control of one of its shaders (rhi::ComputePipelineDesc).
struct SubgroupControl {
  bool fullyPopulated = false, varyingSize = false;
  std::string requiredSize;  // empty: the device's choice; a number, "MIN" or "MAX"
};

struct Pipeline {
  std::string name;
  bool compute = false;
  std::vector<std::string> shaders;  // ATTACHed, in order
  std::map<std::string, std::string> entryPoints;
  // SPECIALIZE on ATTACH: shader name -> SpecId -> the constant's 32 bits.
  std::map<std::string, std::map<uint32_t, uint32_t>> specializations;
  uint32_t fbWidth = 250, fbHeight = 250;
  std::vector<Bind> binds;
  std::vector<VertexData> vertexData;
  std::string indexData;
  bool depthTest = false, depthWrite = false;
  std::string depthCompare = "less";  // Amber's default when TEST on without COMPARE_OP
  StencilFace front, back;
  BlendSettings blend;
  uint8_t colorWriteMask = 0xF;  // bits R 1, G 2, B 4, A 8 (VkRunner's colorWriteMask)
  std::string cullMode = "none", frontFace = "counter_clockwise";
  bool provokingVertexLast = false;  // OpenGL's flat shading convention (piglit); Vulkan's is the first
  std::optional<std::array<float, 4>> viewport;  // x y w h (pixels)
  std::array<float, 2> viewportDepth{0, 1};      // MIN_DEPTH, MAX_DEPTH
  uint32_t patchControlPoints = 0;               // PATCH_CONTROL_POINTS (tessellation)
  // Without a tessellation control shader (OpenGL allows it, Vulkan does not): the levels every
  // patch gets, outer 0-3 then inner 0-1 (OpenGL's defaults: 1; shader_test `patch parameter
  // default level outer|inner`), given by a generated pass-through control shader.
  std::array<float, 6> defaultTessLevels{1, 1, 1, 1, 1, 1};
  std::string polygonMode = "fill";              // POLYGON_MODE fill|line|point
  bool depthClamp = false;                       // DEPTH ... CLAMP on
  float depthBiasConstant = 0, depthBiasClamp = 0, depthBiasSlope = 0;  // DEPTH ... BIAS constant c clamp k slope s
  // SHADER_OPTIMIZATION: shader name -> spirv-opt flags ("--merge-return"), run in order.
  std::map<std::string, std::vector<std::string>> optimizations;
  std::map<std::string, SubgroupControl> subgroups;  // SUBGROUP: shader name -> its control
  Location loc;
};

// ---------------------------------------------------------------------------------------------
// Commands and expectations
// ---------------------------------------------------------------------------------------------
struct Value {
  double d = 0;
  int64_t i = 0;
  bool isInteger = false;
};

struct Tolerance {
  double value = 0;
  bool percent = false;
};

enum class Comparator : uint8_t { Eq, Ne, Lt, Le, Gt, Ge, FuzzyEq };

struct Command {
  enum class Kind : uint8_t {
    ClearColor, ClearDepth, ClearStencil, Clear, DrawRect, DrawGrid, DrawArray, Compute,
    ExpectProbe,   // EXPECT img IDX x y [SIZE w h] EQ_RGB(A) ...
    ExpectValues,  // EXPECT buf IDX byteOffset [TOLERANCE ...] EQ|NE|LT|... values
    ExpectBuffer,  // EXPECT a EQ_BUFFER b / RMSE_BUFFER b TOLERANCE t
    Copy,
    Resolve,       // ours: RESOLVE img [SAMPLES n]
    ExpectMemory,  // ours: EXPECT img MEMORY BYTES [RESOLVED] [PLATFORM p] IDX x y [SIZE w h] EQ bytes
    ExpectImage,   // ours: EXPECT img EQ_IMAGE (FILE path | GOLDEN name) [RMSE t] [MAX t] [FLIP t]
    SetUniform,    // shader_test: a uniform of an OpenGL-GLSL shader set by name (`uniform vec4 color 0 1 0 1`)
    WriteBuffer,   // shader_test: bytes written into a buffer at a byte offset (ubo/ssbo subdata, push)
    ExpectUniform, // piglit: `active uniform NAME PNAME VALUE`, a property of a uniform's layout
    ExpectLink,    // piglit: `link success` / `link error`, the pipeline's shaders link (its pipeline is created) or not
    ExpectProgramQuery,  // piglit, SPIR-V programs: `verify program_interface_query|program_query`, read from the modules
    // piglit: `parameter env_vp|local_vp|env_fp|local_fp INDEX (x, y, z, w)`, a parameter of the ARB
    // assembly programs: `other` names the kind, `px` is INDEX, `values` the four components.
    ProgramParameter,
    // piglit: `ortho` and `frustum` where ARB assembly programs read OpenGL's projection matrix:
    // `values` are its 16 elements, column by column.
    LoadProjection,
    // piglit: `color r g b a` and `texcoord N (x, y, z, w)` where ARB assembly programs read
    // OpenGL's current colour or texture coordinates N: `other` is "color" or "texcoord", `px`
    // is N (0 for the colour), `values` the four components.
    CurrentAttribute,
    // piglit: `hint TARGET MODE` (glHint): `other` is "TARGET MODE". Recorded in the result's notes
    // and not passed on: OpenGL lets an implementation ignore any hint and Vulkan has none.
    Hint,
  };
  Kind kind = Kind::Clear;
  Location loc;
  std::string pipeline;  // CLEAR*, RUN
  // CLEAR_COLOR r g b a (0..255 as written), CLEAR_DEPTH d, CLEAR_STENCIL s
  std::array<double, 4> color{0, 0, 0, 0};
  // DRAW_RECT / DRAW_GRID: POS x y SIZE w h [CELLS c r]; compute: x y z group counts
  float x = 0, y = 0, w = 0, h = 0;
  bool ndc = false;  // shader_test `draw rect`: x y w h in normalised device coordinates, not pixels
  std::array<float, 4> texcoords{0, 0, 1, 1};  // DRAW_RECT: piglit_texcoord's x y w h across the rectangle (`draw rect tex`)
  bool patch = false;  // shader_test `draw rect patch`: the four corners as one patch
  uint32_t patchControlPoints = 0;  // shader_test: `patch parameter vertices` at this draw (0: the pipeline's)
  std::vector<Sampler> samplerStates;  // piglit: every sampler as `texparameter` left it at this draw or dispatch
  // shader_test `draw rect`: the strip (x, y), (x + w, y), (x, y + h), (x + w, y + h), as piglit
  // and VkRunner draw it (gl_VertexID and flat inputs see that order); Amber's starts at (x, y + h).
  bool piglitCorners = false;
  uint32_t cellsX = 1, cellsY = 1;
  uint32_t groups[3] = {1, 1, 1};
  // DRAW_ARRAY
  std::string topology = "TRIANGLE_LIST";
  bool indexed = false;
  uint32_t start = 0, count = 0;  // count 0: all
  bool countGiven = false;
  uint32_t instanceStart = 0, instanceCount = 1;
  int32_t baseVertex = 0;  // INDEXED: added to every index (shader_test's `draw arrays indexed MODE FIRST COUNT`)
  // EXPECT
  std::string buffer, other;
  uint32_t px = 0, py = 0, pw = 1, ph = 1;
  bool rgba = true;
  // ExpectProbe: piglit's `probe warn ...`, whose failure is piglit's "warn", not "fail".
  bool warnOnly = false;
  std::vector<Value> values;
  std::vector<Tolerance> tolerances;
  Comparator comparator = Comparator::Eq;
  bool rmse = false;  // ExpectBuffer: RMSE_BUFFER or EQ_HISTOGRAM_EMD_BUFFER (else EQ_BUFFER)
  bool emd = false;   // ExpectBuffer: EQ_HISTOGRAM_EMD_BUFFER
  double rmseTolerance = 0;
  // ExpectMemory
  bool afterResolve = false;
  bool linkError = false;  // ExpectLink: piglit's `link error`, the shaders do not link
  std::string platform;  // empty: every platform
  // ExpectImage: the reference PNG (resolved against the script's folder) and the tolerances
  std::string imageFile;
  std::optional<double> imageRmse, imageMax, imageFlip;
  // Resolve
  uint32_t resolveSamples = 1;
  // SetUniform: `uniform` is the name as written (may index: "a[2]", "s.f"); values are `values`
  // of `valueType`. WriteBuffer: `bytes` at byte offset `px` of `buffer`. ExpectValues: when
  // `valueTypeGiven`, the values are read as `valueType` elements from byte `px` (shader_test's
  // `probe ssbo TYPE ...`), not in the buffer's own layout.
  std::string uniform;
  uint32_t arrayElement = 0;  // SetUniform: which element of an array of blocks (piglit's `ubo array index`)
  // ExpectUniform: `uniform` has the property `other` (GL_UNIFORM_OFFSET, ...) of value values[0]
  // or, for GL_UNIFORM_TYPE, of the type named `typeName` (GL_FLOAT_VEC4).
  // ExpectProgramQuery: the property `other` (GL_BUFFER_DATA_SIZE, GL_ACTIVE_UNIFORMS, ...) is
  // values[0]: of the block of `programInterface` (GL_UNIFORM_BLOCK, GL_SHADER_STORAGE_BLOCK) at
  // OpenGL binding `blockBinding` (`uniform`: the name as written), or of the program where
  // `programInterface` is empty.
  std::string programInterface, typeName;
  int64_t blockBinding = -1;
  ElementType valueType;
  bool valueTypeGiven = false;
  std::vector<uint8_t> bytes;
};

// Ours: REQUIRE backend gl|vk, REQUIRE platform NAME, REQUIRE capability NAME. Several
// REQUIRE platform lines allow any of the platforms named. Amber's DEVICE_FEATURE and
// DEVICE_EXTENSION (and shader_test's [require] feature and extension lines) are requirements
// "device_feature" and "device_extension", checked against rhi::DeviceInfo when the script runs.
struct Requirement {
  std::string what;   // "backend", "platform", "capability", "device_feature", "device_extension"
  std::string value;
  Location loc;
};

struct Unsupported {
  std::string feature;  // "DEVICE_EXTENSION VK_KHR_8bit_storage", "SHADER format SPIRV-ASM", ...
  Location loc;
};

// OpenGL's fixed-function state that changes what a compatibility-profile shader computes, as
// piglit's [test] sets it before the first draw (opengl_glsl.h).
struct FixedFunctionState {
  bool flatShading = false;    // glShadeModel(GL_FLAT): unqualified colour varyings are flat
  bool twoSidedColor = false;  // GL_VERTEX_PROGRAM_TWO_SIDE: back faces read the back colours
};

struct Script {
  std::string file;
  std::vector<Shader> shaders;
  // piglit's [shader include] and [shader include paths]: OpenGL's named strings, which the
  // shaders' #include reads (rhi::ShaderCompileOptions::namedStrings), and the search paths.
  std::vector<std::pair<std::string, std::string>> namedStrings;
  std::vector<std::string> namedStringSearchPaths;
  FixedFunctionState fixedFunction;
  bool compatibilityContext = false;  // piglit's `[require] GL COMPAT >= v`: an OpenGL compatibility profile
  bool separateShaderObjects = false;  // piglit's SSO ENABLED: stages meet by location, as separate programs
  bool separableProgram = false;  // piglit's SEPARABLE PROGRAM ENABLED: the stages as one program linked separable
  std::vector<Buffer> buffers;
  std::vector<Sampler> samplers;
  std::vector<Pipeline> pipelines;
  std::vector<Command> commands;
  std::vector<Requirement> requirements;
  // Ours: SET PLATFORM_PARAM name value, by the catalogue's names (platforms/common/platform_params.h;
  // aliases such as HALFPIXELOFFSET are stored under the catalogue name).
  std::map<std::string, std::string> platformParams;
  std::vector<Unsupported> unsupported;

  const Shader* findShader(const std::string& n) const;
  bool hasArbPrograms() const;  // a shader of format ARB
  const Buffer* findBuffer(const std::string& n) const;
  const Sampler* findSampler(const std::string& n) const;
  const Pipeline* findPipeline(const std::string& n) const;
};

struct ParseResult {
  bool ok = false;
  Script script;
  std::string error;  // "file:line:column: error: message", one line
};

// AmberScript (harness/scripts/amber/). `name` is used in messages and to resolve files the
// script loads (relative to its folder).
ParseResult parseScript(const std::string& text, const std::string& name);
// A script file in the format its extension names: .shader_test (parseShaderTest) or AmberScript.
ParseResult parseScriptFile(const std::string& path);

// Stores one value as scalar type `s` at byte `offset`, growing `bytes` as needed (integers wrap,
// floats round to the type).
void storeValue(std::vector<uint8_t>& bytes, size_t offset, Scalar s, const Value& v);

// piglit (strtof_hex) and VkRunner (vr_hex_strtof) read a floating-point value written in
// hexadecimal as its bits: 0x3f800000 is 1.0 for a float, 0x3ff0000000000000 for a double.
// Makes `v`, parsed from `word`, that value where `s` is Float32 or Float64.
void applyHexFloatBits(const std::string& word, Scalar s, Value* v);

// A float as int64: NaN gives 0 and values out of range saturate (converting them is undefined).
int64_t saturatingInt64(double d);
// ASCII lower case: format and keyword names compare without case.
std::string lower(std::string s);

// A PNG as tightly packed RGBA8 texels, row 0 (the top row) first (FILE PNG, EQ_IMAGE).
bool loadPng(const std::string& path, std::vector<uint8_t>* bytes, uint32_t* width, uint32_t* height, std::string* error);

}  // namespace parity::harness::script
