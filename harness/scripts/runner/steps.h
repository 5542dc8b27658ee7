// The script runner, one class per family of steps, each a layer over the ones it uses:
// resources (resources.cpp) under shaders (shaders.cpp) under passes (passes.cpp) under
// expectations (expectations.cpp), and Runner (runner.cpp) on top, which runs the script's
// commands in order.
#pragma once

#include <map>
#include <optional>
#include <tuple>

#include "harness/scripts/runner/state.h"
#include "harness/scripts/spirv_interface.h"

namespace parity::harness::script::runner {

// BUFFER and IMAGE objects, their contents, COPY, samplers, and the platform's targets of LOGICAL images.
class ResourceSteps : public RunnerState {
 public:
  using RunnerState::RunnerState;

 protected:
  // The platform layer: parameters, the plan of every LOGICAL image, the shader defines and
  // include folders that let a script's GLSL `#include "platform.glsl"` (and any project shader).
  void setupPlatform();
  void createResources();
  std::vector<uint8_t> toTextureBytes(const Resource& r, std::vector<uint8_t> bytes);    // script layout -> texels
  std::vector<uint8_t> fromTextureBytes(const Resource& r, std::vector<uint8_t> bytes);  // texels -> script layout
  rhi::SamplerHandle makeSampler(const Sampler& s);  // the caller keeps it in samplers_
  // Current contents of a script buffer in the script's own layout.
  std::vector<uint8_t> contents(const std::string& name);
  // COPY a TO b: whole contents, in the script's layout.
  void copy(const Command& c);
  rhi::BufferHandle gpuBuffer(const std::string& name, const Location& loc);
  rhi::BufferHandle zeroBuffer();
  // The res_ key of a 1x1 texture of the sampler's shape holding (0, 0, 0, 1), made once per
  // shape; empty for a shape the RHI has no texture of or OpenGL gives no defined result for.
  std::string incompleteTextureStandIn(const SamplerVariable& shape);
  // What a combined_image_sampler or sampled_image binding samples: the texture, or from
  // BASE_MIP_LEVEL m a view of levels m and up (created once per image and level).
  // `levels`: the piglit sampler state whose base_level and max_level narrow the levels read.
  rhi::TextureHandle sampledTexture(const Bind& b, const Sampler* state = nullptr);
  rhi::BufferHandle tempBuffer(const void* data, size_t size, const char* label);
};

// Shaders: compilation, SPIR-V edits, OpenGL GLSL's linking (varyings, uniform blocks, samplers,
// atomic counters) and uniforms, and the unbound bindings' defaults.
class ShaderSteps : public ResourceSteps {
 public:
  using ResourceSteps::ResourceSteps;

 protected:
  std::map<SetBinding, uint32_t>& bindingMap(const Pipeline& p, const std::vector<std::vector<uint32_t>>& modules);
  std::vector<uint32_t> compile(const Shader& s);
  // What glslang compiles a shader's unit with, and the unit as it gets it (OpenGL GLSL's
  // declarations added, the script's line numbers kept).
  rhi::ShaderCompileOptions portOptions(const Shader& s) const;
  std::string portSource(const Shader& s, const std::string& source, int sourceLine, const std::string* wholeUnit = nullptr) const;
  // glslang's verdict on the pipeline's program, its stages compiled and linked together as
  // OpenGL links a program object; nothing where a shader is not GLSL.
  std::optional<rhi::ProgramLink> linkPort(const Pipeline& p) const;
  // An OpenGL GLSL tessellation or geometry shader of the script is compiled as a version before
  // 4.50 (what a passthrough vertex shader's gl_PerVertex must match).
  bool nextStageBeforeGlsl450() const;
  bool lastBeforeRasterisation(Stage stage) const;
  // OpenGL matches one stage's outputs with the next stage's inputs by name (by location where both
  // give one); glslang's automatic locations number each stage's own declarations, which agree
  // only where both stages declare the same variables in the same order. Each input matched by
  // name takes the location of its producer's output.
  void linkOpenGlVaryings();
  void linkOpenGlBlocks();
  // glslang drops the initialisers of block members (`uniform vec4 c = vec4(1.0);`): the literal
  // ones are written into the blocks here.
  void applyUniformInitializers();
  // The pipeline's binds and the uniform blocks of its OpenGL-GLSL shaders.
  std::vector<Bind> bindsOf(const Pipeline& p) const;
  // A SPIR-V program's samplers (Shader::openGlSpirv): the texture on unit B + E at element E
  // of the sampler at OpenGL binding B.
  void addOpenGlSpirvSamplers(const Shader& s, std::vector<Bind>& binds, std::set<std::string>& added) const;
  // `uniform TYPE NAME values`: written wherever a block holds NAME (a member of a block may be
  // named "Block.member"); a name no block holds was optimised away, as OpenGL drivers do.
  void setUniform(const Command& c);
  // Where `name` lies in block `b`, if there ("Block.member" names a member of a named block).
  std::optional<script::UniformSlot> uniformIn(const OpenGlBlock& b, const std::string& name) const;
  // piglit's `active uniform NAME PNAME VALUE`: the uniform's offset, strides, majority, type or size.
  ExpectResult activeUniform(const Command& c);
  struct OpaqueUniform {
    std::string type;  // OpenGL's name: GL_SAMPLER_2D, ...
    int64_t elements = 1;
  };
  // The sampler or image uniform `name` ("s", or "s[0]" of an array) of the program, if any.
  std::optional<OpaqueUniform> opaqueUniform(const std::string& name) const;
  // piglit's `verify program_interface_query|program_query` of a SPIR-V program (program_queries.cpp).
  ExpectResult programQuery(const Command& c);
  // A SPIR-V extension that Vulkan 1.3 has not made core needs the device extension that brings
  // it: SPV_<VENDOR>_<name> comes with VK_<VENDOR>_<name> or VK_<VENDOR>_shader_<name>.
  void requireSpirvExtension(const std::string& extension);
  // What a module needs of the device (its SPIR-V extensions, subgroup operations), checked for
  // every shader before the first command, as Amber creates every pipeline first.
  void requireShaderSupport(const std::vector<uint32_t>& module);
  // A stage's outputs within the device's output locations (rhi::Capabilities::maxOutputLocations).
  void requireOutputLocations(const Shader& s, const std::vector<uint32_t>& module);
  // Whether the pipeline's OpenGL GLSL goes to the device's own compiler (rhi::ShaderDesc::
  // openGlGlsl; the port runs elsewhere): where the device offers it, unless the program reads
  // compatibility state the runner keeps only in the port (flat shading, two-sided colour, user
  // clip planes, depth texture modes), named strings, atomic counters or rectangle textures,
  // separate shader objects, or the runner adds a stage the file lacks.
  bool runsOpenGlGlsl(const Pipeline& p) const;
  // Whether every pipeline of the shader runs its OpenGL GLSL on the driver (and some does): its
  // port then only places the program, and what the port needs of the device does not count.
  bool runsOnlyOpenGlGlsl(const std::string& shader) const;
  // The shader's units as the driver compiles them (nativeOpenGlGlsl); openGlSources adds the
  // pass-through vertex shader of a pipeline without one.
  std::vector<std::string> openGlUnits(const Shader& s) const;
  std::vector<std::string> openGlSources(const Shader& s, const Pipeline& p) const;
  // Whether the device's driver compiles the shader's OpenGL GLSL: "" when it does, its log when
  // it does not, nothing when the device compiles no OpenGL GLSL.
  std::optional<std::string> driverCompiles(const Shader& s);
  // The device whose driver compiles OpenGL GLSL: this one, or RunOptions::openGlCompiler's.
  rhi::Device* openGlJudge();
  // A [require]d OpenGL extension the judge's context lacks: its refusal of a shader then says
  // nothing about the shader (the Vulkan port may still run it), so the case skips naming it.
  std::optional<std::string> judgeLacksRequirement();
  // A stage's module that declares nothing: where the driver compiles a unit, what stands in for
  // its port when only the driver's verdict is asked (driverCompiles, linkError); empty if
  // glslang fails.
  static std::vector<uint32_t> emptyPort(Stage stage);
  // ARB assembly programs (arb_programs.cpp): the port that places a program in the binding
  // model (its texture units as samplers at bindings of those numbers), the binds of those
  // units' textures, the state of a `parameter`, `ortho`, `frustum`, `color` or `texcoord`
  // command, and that state given to the device after a draw's setPipeline.
  std::vector<uint32_t> arbProgramPort(const Shader& s);
  // Whether the device loads ARB assembly programs itself; elsewhere their translation to GLSL
  // runs, reading OpenGL's state from a block per stage that writeArbStateBlocks fills.
  bool driverLoadsArbPrograms() const;
  std::vector<uint32_t> arbProgramTranslation(const Shader& s);
  void writeArbStateBlocks();
  void arbProgramBinds(const Shader& s, std::vector<Bind>& binds) const;
  void setArbProgramState(const Command& c);
  void applyArbProgramState(const Pipeline& p);
  std::vector<rhi::ShaderHandle> makeShaders(const Pipeline& p);
  // Why the device refused a shader or pipeline: its notes (the driver's log of OpenGL GLSL), or
  // a pointer to its validation message.
  std::string deviceLog();
  // A binding a shader declares and the script leaves unbound is left unwritten by Amber: a shader
  // that runs does not read it. The RHI needs every binding, so it gets a zeroed resource of its
  // kind (pipeline defaults_, bound before the script's binds). An array the script binds only
  // some elements of is a SKIP: what the others read is the peer runner's accident.
  void defaultBindings(const Pipeline& p, const std::vector<uint32_t>& spirv, rhi::ShaderStage stage,
                       const std::map<uint32_t, std::set<uint32_t>>& boundElements);
};

// RUN and CLEAR: attachments, pipelines, bindings, draws and dispatches.
class PassSteps : public ShaderSteps {
 public:
  using ShaderSteps::ShaderSteps;

 protected:
  struct Attachments {
    rhi::PassDesc pass;
    std::vector<rhi::Format> colorFormats;
    rhi::Format depthFormat = rhi::Format::Undefined;
    uint32_t samples = 1;
  };

  // Fills the vertex input of `desc` from the pipeline's VERTEX_DATA (or the generated
  // position-only buffer of DRAW_RECT/DRAW_GRID when `rectBuffer`).
  void vertexInput(const Pipeline& p, rhi::BufferHandle rectBuffer, rhi::PipelineDesc& desc,
                   std::vector<std::pair<rhi::BufferHandle, size_t>>& slots);
  Attachments attachments(const Pipeline& p, rhi::LoadOp load, const ClearState& cs);
  // Pipeline state the device cannot give is a SKIP naming the construct.
  void requireFeature(bool needed, const std::string& feature, const std::string& construct) const;
  // OpenGL's tessellation without a control shader, for Vulkan: a control shader that passes each
  // of the evaluation shader's inputs through and writes the pipeline's default levels.
  rhi::ShaderHandle passThroughControlShader(const Pipeline& p, const Shader& evaluation, uint32_t patchPoints);
  rhi::PipelineHandle graphicsPipeline(const Pipeline& p, rhi::PrimitiveTopology topology, bool rect,
                                       const Attachments& att, std::vector<std::pair<rhi::BufferHandle, size_t>>& slots,
                                       rhi::BufferHandle rectBuffer, uint32_t patchPoints = 0);
  // Contents of the pipeline's push_constant buffer, read before a pass begins (reads are
  // transfers, which the RHI does not allow inside passes).
  std::vector<uint8_t> pushConstantBytes(const Pipeline& p);
  void bindResources(const Pipeline& p, const std::vector<uint8_t>& pushBytes);
  // Uniform texel buffers of snorm formats the RHI has no texel buffer of (GL has none): their
  // texels as 32-bit floats, converted as a read converts them, in buffers of their own that
  // bindResources binds instead. Before the pass: the texels are read back.
  void genericAttributes(const std::vector<uint32_t>& vertexShader, rhi::PipelineDesc& desc,
                         std::vector<std::pair<rhi::BufferHandle, size_t>>& slots);
  void convertSnormTexelBuffers(const Pipeline& p);
  // shader_test: the samplers as the draw's texture parameters left them (Command::samplerStates),
  // made once per distinct state.
  void useSamplerStates(const std::vector<Sampler>& states);
  std::map<std::string, rhi::SamplerHandle> samplerStates_;
  std::map<std::tuple<uint32_t, uint32_t, uint32_t>, rhi::ResourceBinding> snormTexels_;  // (set, binding, element)
  void draw(const Command& c, const Pipeline& p);
  void compute(const Command& c, const Pipeline& p);
  // piglit's `link success`: the pipeline is created now, as the next `draw rect` or dispatch
  // would create it (a failure is the script's Failure).
  void link(const Pipeline& p);
  // piglit's `link error`: OpenGL's linker refuses the program. A device whose driver links the
  // OpenGL GLSL (runsOpenGlGlsl) says so; a shader that does not compile is a Failure, as in piglit.
  ExpectResult linkError(const Command& c, const Pipeline& p);
  // `link error` on a device that runs only the port, which has no OpenGL linker: what its side
  // checks stands in, glslang linking the program's stages together (ShaderSteps::linkPort), then
  // the RHI creating the pipeline. Only a link rule's refusal passes (rhi::ProgramLink::linkError);
  // glslang refusing code it cannot port, a pipeline the RHI refuses, or a program that links and
  // whose pipeline is created, is a SKIP naming why.
  ExpectResult portLinkError(const Command& c, const Pipeline& p);
  rhi::ComputePipelineHandle computePipeline(const Pipeline& p);
  // SUBGROUP: the compute shader's subgroup size control (the RHI has it for compute only).
  void subgroupControl(const Pipeline& p, rhi::ComputePipelineDesc& d) const;
  void clearPass(const Pipeline& p);
};

// EXPECT: probes, values, buffer comparisons, console memory bytes and images.
class ExpectSteps : public PassSteps {
 public:
  using PassSteps::PassSteps;

 protected:
  ExpectResult probe(const Command& c);
  ExpectResult values(const Command& c);
  ExpectResult buffers(const Command& c);
  // Ours: the console memory bytes of a LOGICAL image (platforms::GpuTargets::consoleBytes), per
  // pixel in the console's byte order; the expected bytes are one pixel's (every pixel of the
  // rectangle must hold them) or every pixel's, row by row.
  ExpectResult memory(const Command& c);
  // Ours: an RGBA8 image against a PNG: RMSE over all channels (0-255 units), the largest
  // channel difference, and (FLIP t) the mean LDR-FLIP error (harness/compare/flip.h, 0..1).
  ExpectResult image(const Command& c);
};

// The whole run: every shader compiled, resources created, then the commands in order.
class Runner : public ExpectSteps {
 public:
  using ExpectSteps::ExpectSteps;
  RunResult run();

 private:
  void execute(const Command& c, RunResult& result);
};

}  // namespace parity::harness::script::runner
