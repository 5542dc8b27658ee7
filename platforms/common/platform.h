// What every platform model shares: the platform names, the logical targets a technique asks
// for, how a platform maps them to what the console really allocates, and the small pieces of
// render state the rules look at (blend factors, filters).
//
// A technique asks for a logical target ("two 16-bit unorm channels for DSF data"); the platform
// answers with the console format, its size in memory, the host format the GPU path uses and
// what the shaders must do to write and read it. The CPU models in each platform folder compute
// exactly those writes and reads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "rhi/rhi.h"

namespace parity::platforms {

enum class PlatformId : uint8_t { Reference = 0, Dx10, Ps3, X360 };

std::string_view platformName(PlatformId id);  // "reference", "dx10", "ps3", "x360"
std::optional<PlatformId> platformFromName(std::string_view name);

enum class LogicalFormat : uint8_t {
  Rgba8Unorm = 0,   // four 8-bit unorm channels (albedo, normals at 8 bits)
  Rg16Unorm,        // two 16-bit unorm channels (the DSF buffer, packed normals)
  Rgba16Hdr,        // four 16-bit channels of light accumulation, range at least [0, 32)
  Depth24Stencil8,  // 24-bit depth plus 8-bit stencil
  // Four 8-bit unorm channels whose stored bits are data (LIDR's light indices, packed by the
  // blender): 8 bits per channel on every platform, the reference included, where float storage
  // would keep the fractions a blended shift leaves and break the packing.
  Rgba8Bits,
  // The frame's final colour, the image the harness reads: the console's 8-bit display surface
  // (R8G8B8A8 on dx10, A8R8G8B8 on ps3, k_8_8_8_8 in EDRAM resolved to the front buffer on x360),
  // held on the host in the format the harness asked for (LogicalTarget::outputFormat).
  Output,
  // One 8-bit unorm channel, 8 bits on every platform, the reference included (a count summed
  // by additive blending as k/255, an occlusion term): B8 on ps3, R8_UNORM on dx10; x360 has no
  // 8-bit colour render target and keeps it in the red of a k_8_8_8_8 surface.
  R8Unorm,
  // One 32-bit float channel: a depth kept as colour, an averaged count. F_X32 (ps3),
  // R32_FLOAT (dx10), k_32_FLOAT (x360): lossless everywhere.
  R32Float,
};
inline constexpr std::size_t kLogicalFormatCount = std::size_t(LogicalFormat::R32Float) + 1;  // R32Float is last

std::string_view logicalFormatName(LogicalFormat format);

struct TargetMapping {
  LogicalFormat logical = LogicalFormat::Rgba8Unorm;
  std::string consoleFormat;          // the console's own name, e.g. "k_16_16", "A8R8G8B8 (packed16x2)"
  uint32_t consoleBytesPerPixel = 0;  // per sample, as the console stores it
  rhi::Format hostFormat = rhi::Format::Undefined;  // what the GPU path allocates
  std::string write;   // what the shader does to write a logical value
  std::string read;    // what the shader does to read it back
  std::string source;  // pack section, e.g. "X2, X3"
};

// Blend factors the rules look at (subset of D3D9/GCM).
enum class BlendFactor : uint8_t {
  Zero = 0,
  One,
  SrcColor,
  OneMinusSrcColor,
  SrcAlpha,
  OneMinusSrcAlpha,
  DestColor,
  OneMinusDestColor,
  DestAlpha,
  OneMinusDestAlpha,
  ConstantAlpha,  // a constant blend factor, used for the pack's 0.5 src + 0.5 dst vectors
};

struct BlendState {
  bool enabled = false;
  BlendFactor srcColor = BlendFactor::One;
  BlendFactor dstColor = BlendFactor::Zero;
  BlendFactor srcAlpha = BlendFactor::One;
  BlendFactor dstAlpha = BlendFactor::Zero;
  float constantAlpha = 0.0f;
  friend bool operator==(const BlendState&, const BlendState&) = default;
};

enum class Filter : uint8_t { Nearest = 0, Linear, Anisotropic };

std::string_view filterName(Filter filter);

}  // namespace parity::platforms
