#include "harness/cli/cli.h"
#include "harness/run/process.h"
#include "rhi/rhi.h"
#include "rhi/shader_compiler.h"
#include "scene/scene.h"

#include <string>
#include <utility>

namespace {

// In the fork server, before its first fork, what every child of the default matrix would
// compute again: the default scene (its lights placed by casting rays through it), glslang's
// built-in symbol tables, which glslang parses from GLSL text on a process's first compile of
// each stage (also when the compiled module then comes from the shader cache), and the drivers'
// libraries loaded and relocated (rhi::preloadDriverLibraries).
void warmForkServer() {
  parity::rhi::preloadDriverLibraries();
  parity::scene::Scene scene;
  std::string error;
  parity::scene::makeScene("default", {}, &scene, &error);
  using parity::rhi::ShaderStage;
  const std::pair<ShaderStage, const char*> stages[] = {
      {ShaderStage::Vertex, ""},
      {ShaderStage::Fragment, ""},
      {ShaderStage::Compute, "layout(local_size_x = 1) in;"},
      {ShaderStage::Geometry, "layout(points) in; layout(points, max_vertices = 1) out;"},
      {ShaderStage::TessControl, "layout(vertices = 1) out;"},
      {ShaderStage::TessEvaluation, "layout(triangles) in;"}};
  for (const auto& [stage, layout] : stages)
    parity::rhi::compileGlslSource(std::string("#version 450\n") + layout + "\nvoid main() {}\n", "fork server", stage);
}

}  // namespace

int main(int argc, char** argv) {
  parity::harness::fixAllocatorThresholds();
  // Before anything else: the children of `parity run` and `parity test` are forked from this
  // state (harness/run/process.h).
  // Only the commands whose children the server forks pay for warming it: a `parity merge` or
  // `bless` would spend a core on it for nothing (they run by the hundred in the tests).
  const std::string command = argc > 1 ? argv[1] : "";
  const bool forksChildren = command == "run" || command == "test" || command == "bench" || command == "list";
  parity::harness::startForkServer(&parity::harness::runCli, forksChildren ? &warmForkServer : nullptr);
  return parity::harness::runCli(argc, argv);
}
