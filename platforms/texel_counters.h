// Rules about the values a frame really writes, counted on the GPU by the platform's own passes.
//
// x360's fixed-point surfaces clamp what the shaders and the blender store to -32...32 and store
// NaN as 0 (X2), its 7e3 surfaces clamp to [0, 31.875], and a resolve into an unsigned k_16_16
// texture clamps negative values to 0 and values above 1 to 1 (X3). The host surfaces keep the
// unclamped values until the platform's pass that stores them as the console would
// (GpuTargets::clampFixedPoint, quantiseFloat7e3, resolve), and that pass counts the samples it
// changes: each counting pass takes a slot (open()), binds buffer() at kBinding and pushes the
// slot's index; its shader adds 1 to lane L of its slot for every sample that breaks the rule of
// lane L (shaders/platforms/x360/texel_counts.glsl). collect() reads the slots once, at the end
// of the frame, and reports one diagnostic per code, target and pass with the count.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "platforms/common/diagnostics.h"
#include "rhi/rhi.h"

namespace parity::platforms {

class TexelCounters {
 public:
  static constexpr uint32_t kBinding = 15;  // the storage buffer binding of the counting shaders
  static constexpr uint32_t kLanes = 4;

  // What a slot counts: a code per lane (empty: unused), the target and the technique's pass
  // whose values they are, and for each lane what a count of n means ("n samples ... ").
  struct Slot {
    std::string target, pass;
    std::array<std::string_view, kLanes> codes{};
    std::array<std::string, kLanes> what{};
  };

  explicit TexelCounters(rhi::Device& host) : host_(host) {}
  ~TexelCounters();
  TexelCounters(const TexelCounters&) = delete;
  TexelCounters& operator=(const TexelCounters&) = delete;

  // A slot for one counting pass; its counts start at 0. Null buffer when none can be created.
  uint32_t open(Slot slot);
  rhi::BufferHandle buffer() const { return buffer_; }
  // Reads every open slot, adds its counts to the frame's and reports the totals so far (each
  // code, target and pass once, with its count) into `out`; the slots are free again.
  void collect(DiagnosticList& out);

 private:
  void drain();  // reads the open slots into totals_ and frees them

  rhi::Device& host_;
  rhi::BufferHandle buffer_;
  std::vector<Slot> open_;
  using Key = std::tuple<std::string, std::string, std::string>;  // code, target, pass
  std::map<Key, std::pair<uint64_t, std::string>> totals_;        // count, what
  std::vector<Key> order_;                                        // first-seen order
};

}  // namespace parity::platforms
