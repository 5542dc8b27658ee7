// What the steps of one script's run share: the script, the device, the resources and pipelines
// made for it and the platform layer's targets. Each family of steps (steps.h) is a layer over
// this one; the destructor releases everything in the order the RHI needs.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "harness/scripts/arb_program_glsl.h"
#include "harness/scripts/runner.h"
#include "harness/scripts/runner/spirv_edit.h"
#include "harness/scripts/runner/support.h"
#include "platforms/platform_layer.h"

namespace parity::harness::script::runner {

class RunnerState {
 public:
  RunnerState(const Script& s, rhi::Device& d, const RunOptions& o) : script_(s), dev_(d), opts_(o) {}
  ~RunnerState() {
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

 protected:
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
  // By pipeline: the push-constant bytes its shaders declare. Vulkan leaves bytes nobody pushed
  // undefined; VkRunner's scripts push only the values they set, and the rest are zeros here.
  std::map<std::string, uint32_t> pushConstantSizes_;
  rhi::BufferHandle zeroBuffer_;
  std::vector<rhi::ShaderHandle> shaders_;
  std::vector<rhi::SamplerHandle> samplers_;
  std::vector<rhi::BufferHandle> tempBuffers_;
  std::map<std::string, rhi::SamplerHandle> samplerByName_;
  std::map<std::string, Sampler> samplerStateByName_;  // a draw's piglit sampler states (useSamplerStates)
  // sampledTexture(): views of an image's levels, by image, first level, level count and what
  // the view is (its label, naming the swizzle).
  std::map<std::tuple<std::string, uint32_t, uint32_t, std::string>, rhi::TextureHandle> mipViews_;
  std::map<std::string, std::vector<uint32_t>> compiled_;  // SPIR-V per shader name, before remapping
  // Shaders whose port holds their declarations only (glslang cannot port their code, which the
  // device's driver compiles): why, for a pipeline that would run the port.
  std::map<std::string, std::string> declarationPorts_;
  // Of those, the shaders not even the declarations of which glslang ports, in a script that
  // expects a link error: an empty port stands in, good for OpenGL's linker and nothing else.
  std::set<std::string> linkOnlyPorts_;
  bool checkingLink_ = false;  // PassSteps::linkError is creating the pipeline
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
  // Sampler and image uniforms: each name at a binding of kOpenGlSamplerSet, reading the texture
  // unit (image unit) a `uniform int NAME unit` command chose (OpenGL's default: unit 0).
  // A sampler reading a unit that no texture command filled reads `standIn` (a res_ key), a
  // texture of its shape holding (0, 0, 0, 1): what OpenGL samples from an incomplete texture.
  struct OpenGlSampler {
    uint32_t binding = 0, element = 0;
    bool image = false;
    std::string standIn;  // empty: a shape without one (shadow, multisampled, buffer, cube array)
  };
  std::map<std::string, OpenGlSampler> openGlSamplers_;               // name ("s", "s[2]") -> where
  std::map<std::string, std::vector<std::string>> openGlSamplersOf_;  // shader -> its sampler names
  std::map<std::string, int64_t> samplerUnit_;                        // name -> texture unit
  // Atomic counters: the OpenGL atomic-counter buffer bindings each shader uses.
  std::map<std::string, std::vector<uint32_t>> openGlAtomicsOf_;
  // ARB assembly programs: the texture units each reads (unit -> the port's sampler type), and
  // the state `parameter`, `ortho`, `frustum`, `color` and `texcoord` left for the draws:
  // parameters by (stage, local, index), OpenGL's projection matrix and current attributes.
  std::map<std::string, std::map<uint32_t, std::string>> arbTexturesOf_;
  std::map<std::tuple<Stage, bool, uint32_t>, std::array<float, 4>> programParameters_;
  std::map<std::pair<rhi::Device::CurrentAttribute, uint32_t>, std::array<float, 4>> currentAttributes_;
  std::array<float, 16> projection_{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::map<Stage, ArbStateBlock> arbStateBlocks_;  // of the translations to GLSL, by stage

  // OpenGL matches one stage's outputs with the next stage's inputs by name (by location where both
  // give one); glslang's automatic locations number each stage's own declarations, which agree
  // only where both stages declare the same variables in the same order. Each input matched by
};

}  // namespace parity::harness::script::runner
