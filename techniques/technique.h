// A technique renders a scene through the RHI as a declared list of passes. Techniques never
// name GL or Vulkan and never branch on the platform: they branch only on published
// capabilities (rhi::Capabilities).
#pragma once

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "platforms/common/capabilities.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "platforms/platform_layer.h"
#include "rhi/rhi.h"
#include "rhi/shader_compiler.h"
#include "scene/scene.h"
#include "scene/scene_gpu.h"

namespace parity::techniques {

// Thrown for failures a user can act on (a shader that does not compile, ...); the message is
// one or more "file:line: error: ..." lines.
struct TechniqueError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct RenderSettings {
  uint32_t width = 320, height = 180;       // CI size
  rhi::Format colorFormat = rhi::Format::RGBA8;  // format of the final image
  rhi::ShaderCompileOptions shaderOptions;  // extra defines for every shader of the technique
  // The platform layer the technique's logical targets go through (platforms/platform_layer.h).
  // A technique never branches on it: it plans its targets with it and compiles its shaders
  // with the plan's defines (platformShaderOptions), nothing else.
  platforms::PlatformId platform = platforms::PlatformId::Reference;
  platforms::PlatformParams platformParams;
  // Passes whose only product is a diagnostic target (LIDR's overlap count, which feeds
  // "lidr.dropped", the lost-light count of the run report). Off in `parity bench`, which times
  // the paper's passes only; the diagnostic target then reads zero.
  bool diagnostics = true;
  // What the technique may use: it chooses its port's paths from it (portPaths). prepare() runs
  // with the device's capabilities narrowed by these (runnableCapabilities), so the default
  // (everything) is the device's own, and a caller may take a port's path on a device that has
  // more, to compare the two. What plans without a device (`parity explain`, the case worker's
  // target list) sets the platform's published capabilities (platforms::publishedCapabilities).
  rhi::Capabilities capabilities;
};

// `base` followed by `extra`'s include folders and defines.
rhi::ShaderCompileOptions mergeShaderOptions(const rhi::ShaderCompileOptions& base, const rhi::ShaderCompileOptions& extra);

// A render target of the last frame, for dumping (`parity render --passes DIR`).
struct NamedTarget {
  std::string name;  // e.g. "color", "depth", "gbuffer.normals"
  rhi::TextureHandle texture;
};

// Width and height of a technique's logical targets.
struct TargetExtent {
  uint32_t width = 0, height = 0;
  bool operator==(const TargetExtent&) const = default;
};

// A pass a technique runs another way than its paper does because the device lacks a
// capability: the path a port takes (hdr's luminance by pixel passes where there are no compute
// shaders). `parity render` notes it, `parity explain` names it with the capability.
struct PortPath {
  std::string pass;                    // the paper's pass, e.g. "luminance"
  std::string path;                    // what runs instead, in one line
  platforms::Capability capability{};  // what chose it
};

// "luminance: pixel passes ... (the port's path; capability compute: none on ps3 (RSX runs ...))".
std::string describePortPath(const PortPath& path, platforms::PlatformId platform);

// What prepare() runs with: the device's capabilities, with compute and samples per pixel no
// more than `settings.capabilities` allows (the two a port's path is chosen by).
rhi::Capabilities runnableCapabilities(rhi::Device& device, const RenderSettings& settings);

struct PassInfo {
  std::string name;                  // e.g. "shade"
  std::string description;           // one line, in the words of the technique's paper
  std::vector<std::string> targets;  // logical targets written, e.g. "color", "depth"
};

class Technique {
 public:
  virtual ~Technique() = default;
  virtual std::string name() const = 0;
  virtual std::vector<PassInfo> passes() const = 0;
  // The logical targets it asks the platform layer for at these settings (platforms::planTargets;
  // `parity explain --technique NAME` shows their plan). Empty for a technique that renders only
  // to its final colour and a depth buffer nothing reads.
  virtual std::vector<platforms::LogicalTarget> logicalTargets(const RenderSettings&) const { return {}; }
  // The size the technique plans and allocates those targets at: the output size unless it
  // renders them at a reduced resolution (inferred lighting). Console budgets such as x360 EDRAM
  // depend on it, so `parity explain` plans with it too.
  virtual TargetExtent logicalTargetExtent(const RenderSettings& settings) const {
    return {settings.width, settings.height};
  }
  // Targets planned at sizes of their own (a plan has one size): shadow maps, bloom levels,
  // SSAO's occlusion chain, inferred's output. prepare() plans exactly these; `parity explain
  // --technique NAME` shows each beside the main plan.
  struct SizedTargets {
    std::string role;  // e.g. "bloom level 1"
    TargetExtent extent;
    std::vector<platforms::LogicalTarget> targets;
  };
  virtual std::vector<SizedTargets> furtherTargetPlans(const RenderSettings&) const { return {}; }
  // The port's paths it takes on a device with these capabilities; empty where it runs as its
  // paper does. prepare() takes exactly these.
  virtual std::vector<PortPath> portPaths(const rhi::Capabilities&) const { return {}; }
  // Creates pipelines and render targets. Throws TechniqueError.
  virtual void prepare(rhi::Device& device, const RenderSettings& settings) = 0;
  // Records one frame of the scene seen from `camera`; returns the final colour target
  // (settings.colorFormat, width x height). Submission is the caller's.
  virtual rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) = 0;
  // The targets of the last render(), with their logical names, in pass order; valid until
  // release(). The final colour target is among them.
  virtual std::vector<NamedTarget> targets() const = 0;
  // Destroys what prepare() created.
  virtual void release(rhi::Device& device) = 0;
};

struct TechniqueEntry {
  std::string name;
  std::string description;
  std::function<std::unique_ptr<Technique>()> create;
  // Renders shadow maps for the lights that cast shadows (scene::Light::castsShadows);
  // the others ignore the flag. `parity bench` measures its shadowed scenarios with these.
  bool rendersShadows = false;
};

// The project's techniques, then those registered, in order.
const std::vector<TechniqueEntry>& techniqueRegistry();
// Adds a technique of another project (examples/external-technique): every parity command
// (render, run, bless, explain, bench, view) then offers it like the project's own. Call it in
// main() before harness::startForkServer, whose children are forked from that state. Throws
// TechniqueError for an empty name, a name with '/' or spaces, or one already registered.
void registerTechnique(TechniqueEntry entry);
// Null for an unknown name.
std::unique_ptr<Technique> createTechnique(const std::string& name);

// Loads shaders for one device and destroys them with it. A relative path is found in the
// project's shaders/ folder (an installed parity's share/parity/shaders); an absolute path is
// used as it is, so a technique of another project keeps its shaders in its own tree and still
// includes the project's (parity_math.glsl, scene_data.glsl, platforms/platform.glsl).
class ShaderLibrary {
 public:
  explicit ShaderLibrary(rhi::Device& device) : device_(device) {}
  ~ShaderLibrary();
  // `path` relative to shaders/, e.g. "forward/forward.vert", or absolute. Throws TechniqueError with the
  // compiler's file:line messages.
  rhi::ShaderHandle load(const std::string& path, const rhi::ShaderCompileOptions& options = {});

 private:
  rhi::Device& device_;
  std::vector<rhi::ShaderHandle> shaders_;
};

}  // namespace parity::techniques
