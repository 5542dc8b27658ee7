// Renders one frame of a technique on a backend and reads it back: the unit of work behind
// `parity render`, `parity run` and the cross-backend tests.
#pragma once

#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>
#include <nlohmann/json.hpp>

#include "rhi/rhi.h"
#include "rhi/shader_compiler.h"
#include "scene/scene.h"
#include "techniques/frame.h"

namespace parity::harness {

struct RenderRequest {
  std::string backend = "gl";
  std::string glProvider = "egl";
  bool debug = false;  // GL debug context / Vulkan validation layer
  techniques::FrameRequest frame;
};

struct RenderResult {
  bool ok = false;
  std::string error;           // one line (or compiler lines) when !ok
  OIIO::ImageBuf image;        // top row first
  std::vector<uint8_t> texels; // raw readback in frame.colorFormat
  std::vector<techniques::TargetTexels> targets;  // with frame.readTargets: every target of the frame
  std::vector<platforms::Diagnostic> diagnostics;  // the platform layer's, as techniques::FrameResult
  std::vector<std::string> unplannedTargets;       // as techniques::FrameResult
  std::vector<std::string> portPaths;              // as techniques::FrameResult
  rhi::DeviceInfo device;
};

// Creates a device for request.backend, renders, reads back.
RenderResult renderFrame(const RenderRequest& request);
// Renders on an existing device (the request's backend fields are ignored).
RenderResult renderFrame(rhi::Device& device, const RenderRequest& request);

// Writes every target of `result` into `dir` (created if needed) as "<name>.png" for 8-bit
// unsigned-normalised data and "<name>.exr" for everything else (float, depth); appends the
// paths written. False with a one-line reason.
bool writeTargets(const RenderResult& result, const std::string& dir, std::vector<std::string>* written,
                  std::string* error);

// Parses "WIDTHxHEIGHT"; false with a reason for 0, absurd (> 16384) or malformed sizes.
// [{"code", "severity", "section", "message", "targets"}] as results.json keeps them.
nlohmann::json toJson(const std::vector<platforms::Diagnostic>& diagnostics);

bool parseSize(const std::string& text, uint32_t* width, uint32_t* height, std::string* error);

}  // namespace parity::harness
