// The one form every platform states its render-target rules in: a table with one row per
// logical format. A row says how the console stores the format (TargetMapping), which textures
// and views the host allocates for it, and what brings it to the texture a later pass samples
// (ResolveSpec). applyTargetRow() (platforms/platform_layer.h) turns a row into a PhysicalTarget;
// each platform's planTarget (<platform>/<platform>_layer.cpp) picks the row and adds what no
// row can state (x360: the DSF path the parameters choose).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "platforms/common/platform.h"
#include "rhi/rhi.h"

namespace parity::platforms {

// One logical format on one platform. The defaults are a target read in place: no views, no
// resolve.
struct TargetRow {
  LogicalFormat format = LogicalFormat::Rgba8Unorm;
  // How the console stores it and what the shaders do (TargetMapping).
  std::string_view consoleFormat;                   // the console's own name, e.g. "k_16_16"
  uint32_t consoleBytesPerPixel = 0;                // per sample, as the console stores it
  rhi::Format hostFormat = rhi::Format::Undefined;  // the attachment the GPU path renders to
  std::string_view write;                           // what the shader does to write a logical value
  std::string_view read;                            // what the shader does to read it back
  std::string_view source;                          // pack section, e.g. "X2, X3"
  // What the host allocates besides the attachment (PhysicalTarget).
  rhi::Format readFormat = rhi::Format::Undefined;      // the texture sampled later; Undefined: the attachment
  rhi::Format readViewFormat = rhi::Format::Undefined;  // view shaders sample; Undefined: the read texture
  rhi::Format rawViewFormat = rhi::Format::Undefined;   // bit view of attachment and read; Undefined: none
  rhi::Format writeFormat = rhi::Format::Undefined;     // view exact writes render into; Undefined: the attachment
  // The resolve (or the platform's copy) into the read texture.
  bool resolvedWhenRead = false;  // a target a later pass reads (readLater) needs it
  std::string_view resolve;       // what it does, or why none is needed
  double effectiveBits = 0;       // of the whole write -> resolve -> read path, for the logical range
};

// Row i is the row of LogicalFormat(i).
using TargetTable = std::array<TargetRow, kLogicalFormatCount>;

// Every logical format has its row, in its place (a platform's table static_asserts it).
constexpr bool hasOneRowPerFormat(const TargetTable& table) {
  for (std::size_t i = 0; i < table.size(); ++i)
    if (table[i].format != LogicalFormat(i)) return false;
  return true;
}

constexpr const TargetRow& rowOf(const TargetTable& table, LogicalFormat format) {
  return table[std::size_t(format)];
}

// `row` for another format that the platform stores alike (the three 8-bit RGBA formats).
constexpr TargetRow withFormat(TargetRow row, LogicalFormat format) {
  row.format = format;
  return row;
}

}  // namespace parity::platforms
