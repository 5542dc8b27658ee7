// What a platform can run at all: the second half of "what would break there", beside the
// render-target quirks. Each platform states it in one table of the same form (like its target
// rows, target_table.h): a row per capability with its support, its limit and the source it
// comes from, and a row per format with what the console does with it (render, blend, filter,
// vertex fetch, multisample).
//
// The platform device (platform_device.h) uses the table twice:
//  * it checks every pass, pipeline, draw and dispatch against it (capability_rules.h), so a
//    technique that needs what its platform lacks gets an error naming the capability, the pass
//    and the pipeline (E_CAP_*), and one that leans on an optional feature a warning
//    (W_CAP_OPTIONAL);
//  * it publishes the guaranteed part as the device's rhi::Capabilities (publishedCapabilities),
//    so that a technique chooses its port's path from capabilities, never from a platform's name
//    (hdr's luminance by pixel passes and tiled shading's light lists on the CPU where the device
//    has no compute shaders).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "platforms/common/platform.h"
#include "rhi/rhi.h"

namespace parity::platforms {

// Guaranteed: every device of the platform has it. Optional: the platform allows it and some of
// its devices have it (DX10 feature level 10.0's optional features); a port needs a fallback.
// None: no device of the platform has it.
enum class Support : uint8_t { None = 0, Optional, Guaranteed };
std::string_view supportName(Support support);  // "none", "optional", "guaranteed"

enum class Capability : uint8_t {
  Compute = 0,            // compute shaders at all
  ComputeInvocations,     // limit: invocations of one workgroup
  ComputeWorkgroupDepth,  // limit: a workgroup's size in z
  ComputeSharedMemory,    // limit: bytes of workgroup-shared memory
  ComputeAtomics,         // atomic operations in a compute shader
  ComputeStorageBuffers,  // limit: storage buffers a dispatch writes (UAVs)
  ComputeStorageImages,   // typed storage images (typed UAVs) in a compute shader
  ColorTargets,           // limit: colour attachments one pipeline writes
  FragmentTextures,       // limit: textures one fragment shader reads
  VertexTextures,         // limit: textures the vertex stages read (vertex texture fetch)
  Interpolators,          // limit: vec4 varyings into the fragment shader
  Multisampling,          // limit: samples per pixel
  GeometryShaders,        // a geometry stage
  TessellationShaders,    // tessellation control and evaluation stages
  GraphicsStorageWrites,  // storage buffer or image writes from a vertex or fragment shader
  EdramBytes,             // limit: bytes of render-target memory one pass binds at once
};
inline constexpr std::size_t kCapabilityCount = std::size_t(Capability::EdramBytes) + 1;  // EdramBytes is last

// Whether the row is a limit (a count or a size) rather than a feature.
constexpr bool isLimit(Capability c) {
  switch (c) {
    case Capability::ComputeInvocations: case Capability::ComputeWorkgroupDepth: case Capability::ComputeSharedMemory:
    case Capability::ComputeStorageBuffers: case Capability::ColorTargets: case Capability::FragmentTextures:
    case Capability::VertexTextures: case Capability::Interpolators: case Capability::Multisampling:
    case Capability::EdramBytes:
      return true;
    default:
      return false;
  }
}

// "compute", "compute invocations", ... (stable: used in reports and `parity explain`).
std::string_view capabilityName(Capability capability);
// The code a lacking capability raises, e.g. "E_CAP_COMPUTE".
std::string_view capabilityCode(Capability capability);

// One capability on one platform. A limit row with support Guaranteed and limit 0 has no limit of
// the platform's own (the host's applies).
struct CapabilityRow {
  Capability capability = Capability::Compute;
  Support support = Support::Guaranteed;
  uint32_t limit = 0;
  std::string_view source;  // where the value comes from
};
using CapabilityTable = std::array<CapabilityRow, kCapabilityCount>;

constexpr bool hasOneRowPerCapability(const CapabilityTable& table) {
  for (std::size_t i = 0; i < table.size(); ++i)
    if (table[i].capability != Capability(i)) return false;
  return true;
}

// How the console treats one format. `console` is its name as the platform's target rows begin
// their consoleFormat ("k_16_16 (fixed point ...)" -> "k_16_16"), so a platform target finds its
// row by the console format the plan chose and a texture the technique made itself by `host`.
struct FormatRow {
  rhi::Format host = rhi::Format::Undefined;  // Undefined: reached only as a platform target
  std::string_view console;
  Support render = Support::None;  // colour attachment, or depth attachment for depth formats
  Support blend = Support::None;
  Support filter = Support::None;  // sampled with a Linear filter
  Support vertexFetch = Support::None;
  Support multisample = Support::None;
  std::string_view source;
};

struct PlatformCapabilities {
  PlatformId platform = PlatformId::Reference;
  CapabilityTable rows{};
  // The formats the platform's sources speak of; a format not listed is not checked (the
  // reference lists none: every format for every use).
  std::span<const FormatRow> formats;

  const CapabilityRow& row(Capability capability) const { return rows[std::size_t(capability)]; }
  // The row of a texture: a platform target's (by the first word of its consoleFormat), else a
  // host format's. Null when the platform's sources say nothing of it.
  const FormatRow* format(std::string_view consoleFormat, rhi::Format host) const;
};

const PlatformCapabilities& platformCapabilities(PlatformId platform);

// `host` with only what `platform` guarantees: compute off unless guaranteed, at most the
// platform's guaranteed samples per pixel. What a technique on that platform branches on.
rhi::Capabilities publishedCapabilities(PlatformId platform, const rhi::Capabilities& host);

// A row's value as the docs and `parity explain` show it: "none", "768 (optional)", "no limit"
// (a limit row without one of the platform's own), "yes".
std::string rowValue(const CapabilityRow& row);

// "none on ps3 (RSX runs vertex and fragment programs only: ...)" / "768 on dx10 (...)": a
// row as a note names it.
std::string describeRow(PlatformId platform, const CapabilityRow& row);

namespace x360 {
const PlatformCapabilities& capabilities();
}
namespace ps3 {
const PlatformCapabilities& capabilities();
}
namespace dx10 {
const PlatformCapabilities& capabilities();
}

}  // namespace parity::platforms
