// Per-pass rows of a study: the device's per-pass timings (rhi/timing_device.h) grouped by pass
// name, so that a multi-pass technique's "light 0" .. "light 254" form one "light" row.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "rhi/timing_device.h"

namespace parity::bench {

// "light 12" -> "light", "blur pass 2/3" -> "blur pass", "" -> "(unnamed)".
std::string passGroupName(const std::string& label);

// Milliseconds per group name, in order of first appearance.
std::vector<std::pair<std::string, double>> groupPassTimes(const std::vector<rhi::PassTiming>& timings);

}  // namespace parity::bench
