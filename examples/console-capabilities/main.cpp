// The parity command with one more technique: "compute-lists" clears a tiled renderer's light
// lists with a compute dispatch, then clears the frame. It has no port path, so on a platform
// without compute shaders the platform device raises E_CAP_COMPUTE on the dispatch, naming the
// pipeline, and `render` fails naming the capability.
#include <memory>

#include "harness/cli/cli.h"
#include "harness/run/process.h"
#include "rhi/shader_compiler.h"
#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace {

namespace pt = parity::techniques;
namespace rhi = parity::rhi;

const char* kClearLists = R"(#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Lists { uint counts[]; };
void main() { counts[gl_GlobalInvocationID.x] = 0u; })";

class ComputeLists final : public pt::Technique {
 public:
  std::string name() const override { return "compute-lists"; }
  std::vector<pt::PassInfo> passes() const override {
    return {{"clear lists", "a compute dispatch zeroes each tile's light count", {}},
            {"frame", "the frame cleared", {"color"}}};
  }
  std::vector<parity::platforms::LogicalTarget> logicalTargets(const pt::RenderSettings& settings) const override {
    return {pt::outputColorTarget(settings, "frame")};
  }
  void prepare(rhi::Device& device, const pt::RenderSettings& settings) override {
    targets_ = std::make_unique<pt::PlannedTargets>(device, settings, logicalTargets(settings), name());
    rhi::CompiledShader compiled = rhi::compileGlslSource(kClearLists, "clear_lists.comp", rhi::ShaderStage::Compute);
    if (!compiled.ok()) throw pt::TechniqueError(compiled.error);
    shader_ = device.createShader({rhi::ShaderStage::Compute, compiled.spirv, "main", "clear_lists.comp"});
    rhi::ComputePipelineDesc p;
    p.computeShader = shader_;
    p.label = "clear light lists";
    pipeline_ = device.createComputePipeline(p);
    lists_ = device.createBuffer({64 * 4, rhi::BufferUsage_Storage, nullptr, "light lists"});
  }
  rhi::TextureHandle render(rhi::Device& device, parity::scene::SceneGpu&, const parity::scene::Camera&) override {
    const rhi::ResourceBinding lists{.binding = 0, .kind = rhi::BindingKind::StorageBuffer, .buffer = lists_};
    device.setComputePipeline(pipeline_);
    device.setBindings({&lists, 1});
    device.dispatch(1);
    rhi::PassDesc pass;
    pass.colors[0].texture = targets_->attachment(pt::kOutputColor);
    pass.colors[0].clearColor = {0.25f, 0.5f, 0.75f, 1.0f};
    pass.label = "frame";
    device.beginPass(pass);
    device.endPass();
    return targets_->present();
  }
  std::vector<pt::NamedTarget> targets() const override {
    return targets_ ? std::vector<pt::NamedTarget>{{pt::kOutputColor, targets_->readTexture(pt::kOutputColor)}}
                    : std::vector<pt::NamedTarget>{};
  }
  void release(rhi::Device& device) override {
    device.destroy(pipeline_);
    device.destroy(shader_);
    device.destroy(lists_);
    targets_.reset();
  }

 private:
  std::unique_ptr<pt::PlannedTargets> targets_;
  rhi::ShaderHandle shader_;
  rhi::ComputePipelineHandle pipeline_;
  rhi::BufferHandle lists_;
};

}  // namespace

int main(int argc, char** argv) {
  pt::registerTechnique({"compute-lists", "light lists cleared by a compute dispatch (no port path)",
                         [] { return std::make_unique<ComputeLists>(); }});
  parity::harness::startForkServer(&parity::harness::runCli);
  return parity::harness::runCli(argc, argv);
}
