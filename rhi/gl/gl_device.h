// OpenGL 4.5 core backend: internal declarations shared by the rhi/gl/*.cpp files.
//
// One GlDevice implements rhi::Device. Its methods are defined by concept, mirroring the
// Vulkan backend: gl_device.cpp (creation, info, conventions, submit), gl_buffer.cpp,
// gl_texture.cpp (formats, textures, views, samplers, transfers), gl_shader.cpp (SPIR-V to
// GLSL), gl_opengl_glsl.cpp (OpenGL GLSL the driver compiles, placed by its SPIR-V port),
// gl_arb_program.cpp (ARB assembly programs the driver loads, in a compatibility context),
// gl_pipeline.cpp (programs, vertex arrays), gl_commands.cpp (passes, state, draws,
// dispatches, bindings, push constants, timestamps). Direct state access (GL 4.5) throughout.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rhi/gl/gl_context.h"
#include "rhi/gl/gl_functions.h"
#include "rhi/handle_pool.h"
#include "rhi/rhi.h"
#include "rhi/shader_reflection.h"

namespace parity::rhi::gl {

// The push-constant block becomes a uniform block at this binding point (see rhi.h's binding
// model): SPIRV-Cross emits it as a UBO and the device keeps one small buffer bound there. A
// block std140 cannot express becomes a storage block at the same binding (gl_shader.cpp).
// A program with descriptor arrays moves it to P(kMaxBindings) when it links (GlProgram::points).
constexpr uint32_t kGlPushConstantBinding = kMaxBindings;  // one past every user binding: no clash

// --- formats (gl_texture.cpp) ---
struct GlFormat {
  GLenum internalFormat;  // glTextureStorage*
  GLenum format, type;    // pixel transfer of raw texels (upload and colour readback)
};
const GlFormat& glFormat(Format f);

// --- objects ---
// A buffer texture (GL_TEXTURE_BUFFER) over a range of a buffer: what a UniformTexelBuffer
// (texture unit N) or StorageTexelBuffer (image unit N) binding binds. Created on demand.
struct GlTexelView {
  Format format;
  size_t offset, size;
  GLuint name;
};

struct GlBuffer {
  GLuint name = 0;
  BufferDesc desc;
  std::vector<GlTexelView> texelViews;
};

// A view of a texture created at bind time because a shader samples it through another
// texture type (sampler2DArray on a 2D texture, ...) or reads D24S8 stencil (usampler).
struct GlSamplingView {
  GLenum target;
  bool stencil;
  GLuint name;
};

struct GlTexture {
  GLuint name = 0;
  GLenum target = GL_TEXTURE_2D;
  TextureDesc desc;  // views: resolved against the parent
  bool isView = false;
  ComponentMapping swizzle;  // views: TEXTURE_SWIZZLE_*, on the view and on its sampling views
  std::vector<GlSamplingView> samplingViews;
};

struct GlSampler {
  GLuint name = 0;
  SamplerDesc desc;
};

// `name` is the shader object compiled from the GLSL SPIRV-Cross generates, or 0 where that GLSL
// could not be had (`translationError` says why) and `spirvName` holds the module itself, taken
// through GL_ARB_gl_spirv (gl_shader.cpp). A program is all one or all the other.
struct GlShader {
  GLuint name = 0;
  GLuint spirvName = 0;
  std::string translationError;
  std::vector<uint32_t> spirv;
  std::string entryPoint;
  ShaderStage stage = ShaderStage::Vertex;
  ShaderReflection reflection;
  bool pushConstantsInStorageBlock = false;  // std430-only block: see gl_shader.cpp
  std::string label;
  std::vector<GLuint> openGlUnits;  // ShaderDesc::openGlGlsl compiled by the driver (gl_opengl_glsl.cpp)
  std::string looseUniformBlock;    // ShaderDesc::looseUniformBlock
  GLuint arbProgram = 0;            // ShaderDesc::arbProgram loaded by the driver (gl_arb_program.cpp)
};

// A loose uniform of a program from OpenGL GLSL (ShaderDesc::openGlGlsl): one scalar, vector or
// matrix, its value at `offset` of the port's gl_DefaultUniformBlock bound at `binding`.
struct LooseUniform {
  enum class Type : uint8_t { Float, Int, UInt, Double, Int64, UInt64 };
  GLint location = -1;
  uint32_t binding = 0;
  uint32_t offset = 0;
  Type type = Type::Float;
  uint32_t rows = 1, columns = 1;  // a vector has one column
  uint32_t matrixStride = 0;       // bytes from column to column in the block
};

// Separate textures and samplers on GL. GLSL (without Vulkan semantics) has no separate
// texture or sampler objects, so the shaders' (SeparateTexture, SeparateSampler) pairs become
// combined sampler uniforms (gl_shader.cpp), named by combinedSamplerName() so that every stage of
// a program names a pair alike. linkProgram gives pair k of the program (mergeSeparatePairs order)
// texture unit P(kMaxBindings) + k (kMaxBindings + k without descriptor arrays; a pair whose
// texture is an array of N takes N units), above every unit a binding number takes, and at each
// draw the texture bound at the pair's texture binding and the sampler object bound at its
// sampler binding both go to that unit (glBindTextureUnit + glBindSampler).
// Per-API consequence: a texture used with two samplers occupies two GL units (Vulkan: one
// SAMPLED_IMAGE descriptor); the units are private to the backend, so a pipeline may combine at
// most kMaxSeparatePairs pairs (validation: E_PIPELINE_SEPARATE_PAIRS), and GL needs
// kMaxBindings + k + 1 combined texture units for k pairs (checked when a program links).
std::string combinedSamplerName(const SeparatePair& pair);
// What SPIRV-Cross names the GLSL uniform of a sampler, image or texel buffer at `binding`, so that
// linkProgram can find it by name when it moves the binding to its point.
std::string glResourceName(uint32_t binding);
// rhi.h's binding model on GL, in one place: element e of binding b is GL binding point / texture
// unit / image unit points[b] + e with points[b] = b + the sum of (arraySize - 1) over the
// resources below b; points[kMaxBindings] is the first reserved point (push constants, pairs).
std::array<uint32_t, kMaxBindings + 1> glBindingPoints(const std::vector<ShaderResource>& resources);
// A vertex input's location as OpenGL counts it (one per vector of a dvec3 or dvec4, where Vulkan
// and PipelineDesc count two).
uint32_t openGlAttributeLocation(const ShaderReflection& vs, uint32_t location);
GLenum glStage(ShaderStage stage);  // GL_VERTEX_SHADER, ... (gl_shader.cpp)

// A linked program and what the device needs to feed it.
struct GlProgram {
  GLuint name = 0;
  std::vector<ShaderResource> resources;  // union of the stages' resources
  std::vector<SeparatePair> separatePairs;  // pair k (element e) samples through unit pairUnits[k] + e
  std::vector<uint32_t> pairUnits;
  std::array<uint32_t, kMaxBindings + 1> points{};  // glBindingPoints(resources)
  uint32_t pushConstantSize = 0;
  bool pushConstantsInUniformBlock = false;
  bool pushConstantsInStorageBlock = false;
  GLint baseInstanceLocation = -1;  // SPIRV_Cross_BaseInstance (gl_InstanceIndex emulation)
  uint32_t clipDistances = 0;       // written by the last stage before rasterisation: enabled at draws
  bool readsBaseVertex = false;     // the vertex stage reads gl_BaseVertex (see GlDevice::draw)
  // From OpenGL GLSL: OpenGL's clip-space depth, and the uniforms copied before each draw.
  bool openGlClipSpace = false;
  std::vector<LooseUniform> looseUniforms;
  // From ARB assembly programs (ShaderDesc::arbProgram): no program object (name 0), these bound
  // and enabled at draws instead. Owned by their shaders.
  GLuint arbVertexProgram = 0, arbFragmentProgram = 0;
  // The vertex inputs' locations in the program, by the port's (PipelineDesc's) location.
  std::map<uint32_t, uint32_t> attributeLocations;
  // Uniform blocks the driver lays out otherwise than the port (OpenGL's `shared` and `packed`):
  // at each draw the bound buffer, in the port's layout, is copied member by member into a
  // buffer of the program's own, bound in its place.
  struct RepackedBlock {
    uint32_t binding = 0, element = 0;
    GLuint shadow = 0;  // owned by the program
    uint32_t size = 0;
    struct Move {
      uint32_t from, to, bytes;
    };
    std::vector<Move> moves;
  };
  std::vector<RepackedBlock> repackedBlocks;
  // Atomic counters the driver keeps in atomic counter buffers where the port has a storage
  // block with members of the same names: at each draw the buffer bound at the block's binding
  // is bound as the atomic counter buffer of the binding the source gave (which no call moves).
  struct AtomicCounterBuffer {
    uint32_t binding = 0;  // the port block's (rhi.h's binding model)
    GLuint point = 0;      // GL_ATOMIC_COUNTER_BUFFER's
  };
  std::vector<AtomicCounterBuffer> atomicCounterBuffers;
};

struct GlPipeline {
  GlProgram program;
  GLuint vao = 0;
  PipelineDesc desc;
};

struct GlComputePipeline {
  GlProgram program;
  ComputePipelineDesc desc;
};

// Attachment set of a pass: (texture id, layer, mip) for 4 colours, then depth-stencil.
using FramebufferKey = std::array<uint32_t, 3 * (kMaxColorTargets + 1)>;

class GlDevice final : public Device {
 public:
  static std::unique_ptr<Device> create(const DeviceDesc& desc, std::string* whyNot);
  ~GlDevice() override;

  const DeviceInfo& info() const override { return info_; }

  BufferHandle createBuffer(const BufferDesc& desc) override;
  TextureHandle createTexture(const TextureDesc& desc) override;
  TextureHandle createTextureView(const TextureViewDesc& desc) override;
  SamplerHandle createSampler(const SamplerDesc& desc) override;
  ShaderHandle createShader(const ShaderDesc& desc) override;
  PipelineHandle createPipeline(const PipelineDesc& desc) override;
  ComputePipelineHandle createComputePipeline(const ComputePipelineDesc& desc) override;
  void destroy(BufferHandle h) override;
  void destroy(TextureHandle h) override;
  void destroy(SamplerHandle h) override;
  void destroy(ShaderHandle h) override;
  void destroy(PipelineHandle h) override;
  void destroy(ComputePipelineHandle h) override;
  const BufferDesc* describe(BufferHandle h) const override;
  const TextureDesc* describe(TextureHandle h) const override;

  void writeBuffer(BufferHandle h, size_t offset, const void* data, size_t size) override;
  void writeTexture(TextureHandle h, uint32_t layer, uint32_t mip, const void* data) override;
  std::vector<uint8_t> readBuffer(BufferHandle h, size_t offset, size_t size) override;
  std::vector<uint8_t> readTexture(TextureHandle h, const ReadbackRegion& region) override;
  void copyTexture(TextureHandle src, TextureHandle dst, const ReadbackRegion& srcRegion,
                   const ReadbackRegion& dstRegion) override;
  void copyBuffer(BufferHandle src, size_t srcOffset, BufferHandle dst, size_t dstOffset, size_t size) override;

  void beginPass(const PassDesc& desc) override;
  void endPass() override;
  void setPipeline(PipelineHandle h) override;
  void setViewport(const Viewport& vp) override;
  void setScissor(const Rect& r) override;
  void setStencilReference(uint8_t ref) override;
  void setBlendConstant(const std::array<float, 4>& c) override;
  void setVertexBuffer(uint32_t slot, BufferHandle h, size_t offset) override;
  void setIndexBuffer(BufferHandle h, IndexType type, size_t offset) override;
  void draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) override;
  void drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                   uint32_t firstInstance) override;

  void setComputePipeline(ComputePipelineHandle h) override;
  void dispatch(uint32_t x, uint32_t y, uint32_t z) override;

  void setBindings(std::span<const ResourceBinding> bindings) override;
  void pushConstants(const void* data, uint32_t size) override;

  TimestampId writeTimestamp() override;
  std::optional<uint64_t> timestampNs(TimestampId id) override;
  void resetTimestamps() override;

  void setProgramParameter(ShaderStage stage, bool local, uint32_t index, const std::array<float, 4>& value) override;
  void setTransformMatrices(const std::array<float, 16>& modelView, const std::array<float, 16>& projection) override;
  void setCurrentAttribute(CurrentAttribute attribute, uint32_t index, const std::array<float, 4>& value) override;

  void submit() override;
  std::vector<std::string> takeNotes() override;

 private:
  GlDevice() = default;

  // gl_device.cpp
  bool initialise(const DeviceDesc& desc, std::string* whyNot);
  void setConventions();
  // DeviceInfo::features and ::extensions: what GL 4.5 and this context's extensions run of the
  // Vulkan features and extensions, once SPIRV-Cross has translated a module.
  void listShaderFeatures();
  void installDebugOutput();
  void log(const std::string& message) const;
  void label(GLenum identifier, GLuint name, const std::string& text);

  // gl_buffer.cpp
  GLuint texelView(GlBuffer& buffer, Format format, size_t offset, size_t size);

  // gl_texture.cpp
  GLuint samplingTexture(GlTexture& texture, const ShaderResource& use);
  void deleteTextureObjects(GlTexture& texture);

  // gl_shader.cpp: the generated GLSL, and GL_ARB_gl_spirv for modules whose GLSL fails.
  GLuint compileGlsl(ShaderStage stage, const std::string& glsl, std::string* error);
  bool takesSpirv(const GlShader& shader) const;
  GLuint compileSpirv(const GlShader& shader, std::string* error);
  std::string shaderInfoLog(GLuint shader);

  // gl_opengl_glsl.cpp: programs the driver compiles from OpenGL GLSL, placed by their ports.
  std::vector<GLuint> compileOpenGlGlsl(const ShaderDesc& desc, std::string* error);
  GLuint linkOpenGlGlsl(const std::vector<const GlShader*>& shaders, std::string* error, bool separable = false);
  void placeOpenGlInterface(const std::vector<const GlShader*>& shaders, GlProgram& program);
  // Before each draw or dispatch: the loose uniforms copied, blocks repacked and atomic counter
  // buffers bound, as placeOpenGlInterface found them.
  void applyOpenGlInterface(const GlProgram& program);
  void copyLooseUniforms(const GlProgram& program);
  void repackUniformBlocks(const GlProgram& program);
  void bindAtomicCounterBuffers(const GlProgram& program);

  // gl_arb_program.cpp: ARB assembly programs, in a compatibility context.
  bool loadArbProgramFunctions();
  GLuint loadArbProgram(const ShaderDesc& desc, std::string* error);
  void deleteArbProgram(GLuint program);
  bool placeArbPrograms(const std::vector<const GlShader*>& shaders, const std::string& label, GlProgram* out);
  void bindArbPrograms(const GlProgram& program);

  // gl_pipeline.cpp
  GLuint linkShaders(const std::vector<GLuint>& names, std::string* error);
  std::string programInfoLog(GLuint program);
  bool linkProgram(const std::vector<const GlShader*>& shaders, const std::string& label, GlProgram* out, bool separable = false);
  void moveToBindingPoints(const GlProgram& program);

  // gl_commands.cpp
  GLuint framebuffer(const FramebufferKey& key);
  void forgetFramebuffersOf(TextureHandle texture);
  void attach(GLuint fbo, GLenum attachment, const GlTexture& texture, uint32_t layer, uint32_t mip);
  void applyRenderState(const GlPipeline& pipeline);
  void applyDepthBias(const DepthBias& bias);
  void applyVertexInput(const GlPipeline& pipeline);
  void applyBindings(const GlProgram& program);
  void applyPushConstants(const GlProgram& program);
  void prepareDraw(uint32_t firstInstance);
  GLuint sequentialIndices(uint32_t count);  // an index buffer holding 0..count-1 (and maybe more)

  // --- context, entry points, description ---
  std::unique_ptr<GlContext> context_;
  GlFunctions gl;
  DeviceInfo info_;
  std::function<void(const std::string&)> log_;

  // --- objects (textures and buffers boxed so describe() pointers stay valid) ---
  HandlePool<BufferHandle, std::unique_ptr<GlBuffer>> buffers_;
  HandlePool<TextureHandle, std::unique_ptr<GlTexture>> textures_;
  HandlePool<SamplerHandle, GlSampler> samplers_;
  HandlePool<ShaderHandle, GlShader> shaders_;
  HandlePool<PipelineHandle, GlPipeline> pipelines_;
  HandlePool<ComputePipelineHandle, GlComputePipeline> computePipelines_;
  GLuint defaultSampler_ = 0;
  GLuint defaultShadowSampler_ = 0;
  GLint maxTextureUnits_ = 0;  // GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS
  // GL_ARB_polygon_offset_clamp's entry point (core only in GL 4.6); null without the extension.
  PFNGLPOLYGONOFFSETCLAMPPROC polygonOffsetClamp_ = nullptr;
  // GL_ARB_gl_spirv's (core only in GL 4.6); null without the extension.
  PFNGLSPECIALIZESHADERARBPROC specializeShader_ = nullptr;
  // GL_ARB_gpu_shader_int64's glProgramUniform{1,2,3,4}{i64,ui64}vARB (64-bit loose uniforms), or null.
  std::array<PFNGLPROGRAMUNIFORM1I64VARBPROC, 4> programUniformI64_{};
  std::array<PFNGLPROGRAMUNIFORM1UI64VARBPROC, 4> programUniformUI64_{};
  std::vector<std::string> notes_;  // takeNotes()
  // The compatibility entry points of ARB assembly programs (gl_arb_program.cpp), which the
  // core header does not declare: null until loadArbProgramFunctions() finds them all.
  struct ArbProgramFunctions {
    void(APIENTRYP GenPrograms)(GLsizei, GLuint*) = nullptr;
    void(APIENTRYP DeletePrograms)(GLsizei, const GLuint*) = nullptr;
    void(APIENTRYP BindProgram)(GLenum, GLuint) = nullptr;
    void(APIENTRYP ProgramString)(GLenum, GLenum, GLsizei, const void*) = nullptr;
    void(APIENTRYP ProgramEnvParameter4fv)(GLenum, GLuint, const GLfloat*) = nullptr;
    void(APIENTRYP ProgramLocalParameter4fv)(GLenum, GLuint, const GLfloat*) = nullptr;
    void(APIENTRYP MatrixMode)(GLenum) = nullptr;
    void(APIENTRYP LoadMatrixf)(const GLfloat*) = nullptr;
    void(APIENTRYP Color4fv)(const GLfloat*) = nullptr;
    void(APIENTRYP MultiTexCoord4fv)(GLenum, const GLfloat*) = nullptr;
  } arb_;
  bool arbProgramsEnabled_ = false;  // GL_VERTEX_PROGRAM_ARB and GL_FRAGMENT_PROGRAM_ARB are on
  // Push constants live in a persistently mapped ring, a slot per change (applyPushConstants):
  // a write into a buffer that issued draws still read makes llvmpipe finish those draws first,
  // one flush per light volume in a multi-light pass. submit() waits, so it rewinds the ring.
  static constexpr size_t kPushConstantRingBytes = size_t(1) << 20;
  GLuint pushConstantBuffer_ = 0;
  uint8_t* pushConstantRing_ = nullptr;  // the mapping (coherent: no flush needed)
  size_t pushConstantSlotBytes_ = kMaxPushConstantBytes;  // rounded up to the UBO/SSBO offset alignments
  size_t pushConstantNext_ = 0, pushConstantBound_ = 0;   // the next free slot, the slot the draws read
  GLuint sequentialIndices_ = 0;  // 0, 1, 2, ...: sequentialIndices()
  uint32_t sequentialIndexCount_ = 0;
  std::map<FramebufferKey, GLuint> framebuffers_;

  // --- recorded state ---
  bool inPass_ = false;
  bool openGlClipSpace_ = false;  // glClipControl's depth is -1..1 (a program from OpenGL GLSL)
  PassDesc pass_;
  GLuint passFramebuffer_ = 0;
  uint32_t passWidth_ = 0, passHeight_ = 0;
  PipelineHandle pipeline_;
  ComputePipelineHandle computePipeline_;
  Viewport viewport_;
  Rect scissor_;
  uint8_t stencilReference_ = 0;
  std::array<float, 4> blendConstant_{0, 0, 0, 0};
  struct VertexBufferBinding {
    BufferHandle buffer;
    size_t offset = 0;
  };
  std::array<VertexBufferBinding, kMaxVertexBuffers> vertexBuffers_{};
  BufferHandle indexBuffer_;
  IndexType indexType_ = IndexType::UInt32;
  size_t indexOffset_ = 0;
  std::array<std::array<std::optional<ResourceBinding>, kMaxArrayElements>, kMaxBindings> bindings_{};  // [binding][element]
  std::array<uint8_t, kMaxPushConstantBytes> pushConstantData_{};
  bool pushConstantsDirty_ = true;
  uint32_t enabledClipDistances_ = 0;  // GL_CLIP_DISTANCE0 .. n-1 enabled (GL starts with none)

  // --- timestamps: one GL_TIMESTAMP query per id, reused after resetTimestamps() ---
  std::vector<GLuint> timestampQueries_;
  uint32_t timestampsWritten_ = 0;
};

}  // namespace parity::rhi::gl
