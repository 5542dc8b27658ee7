// The PS3 platform: how each logical target is really allocated, written and read.
//
// Rules and models live next to this file: surface.h (P1), remap.h (texture remap, P2/P4),
// packed16.h (P2, P3), depth_read.h (P4), msaa_layout.h (P5, the contrast to Xenos).
#pragma once

#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"

namespace parity::platforms::ps3 {

// The mapping of `logical` in the platform's target table (ps3_layer.cpp).
TargetMapping mapTarget(LogicalFormat logical, const PlatformParams& params = {});

}  // namespace parity::platforms::ps3
