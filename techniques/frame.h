// One frame of a technique on a device, read back as texels: the unit of work behind
// `parity render`, `parity run` and the cross-backend tests. No image library involved, so it
// also runs where only the RHI is deployed.
#pragma once

#include <string>
#include <vector>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "rhi/rhi.h"
#include "rhi/shader_compiler.h"
#include "scene/scene.h"

namespace parity::techniques {

struct FrameRequest {
  std::string technique = "forward";
  std::string scene = "default";
  std::string camera = "default";
  uint32_t width = 320, height = 180;
  scene::SceneParams sceneParams;
  rhi::Format colorFormat = rhi::Format::RGBA8;  // RGBA8 or RGBA32F
  rhi::ShaderCompileOptions shaderOptions;
  platforms::PlatformId platform = platforms::PlatformId::Reference;
  platforms::PlatformParams platformParams;
  bool readTargets = false;  // also read back every target of the frame (Technique::targets())
  bool diagnostics = true;   // RenderSettings::diagnostics
};

// One render target of the frame as read back.
struct TargetTexels {
  std::string name;  // the technique's logical name, e.g. "color", "depth"
  rhi::Format format = rhi::Format::RGBA8;
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> texels;  // memory row 0 first; depth formats as one float per texel
};

struct FrameResult {
  bool ok = false;
  std::string error;            // when !ok: one line, or the compiler's file:line lines
  std::vector<uint8_t> texels;  // colorFormat, memory row 0 (the top row) first
  std::vector<TargetTexels> targets;  // with request.readTargets: every target, in the technique's order
  // What the platform layer found in the frame's real targets and resolves (plan rules, X3
  // alignment, ...), each distinct diagnostic once (platforms/platform_device.h).
  std::vector<platforms::Diagnostic> diagnostics;
  // "pass: texture" for each attachment the technique rendered outside its platform plan
  // (PlatformDevice::unplannedAttachments): host formats, no console rule.
  std::vector<std::string> unplannedTargets;
  // The port's paths the technique took on the device (Technique::portPaths), each as
  // describePortPath words it.
  std::vector<std::string> portPaths;
};

FrameResult renderFrameTexels(rhi::Device& device, const FrameRequest& request);

}  // namespace parity::techniques
