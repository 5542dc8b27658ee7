// The DX10 platform: native formats; depth readable only through R24X8 (depth_read.h, D1).
#pragma once

#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"

namespace parity::platforms::dx10 {

// The mapping of `logical` in the platform's target table (dx10_layer.cpp).
TargetMapping mapTarget(LogicalFormat logical, const PlatformParams& params = {});

}  // namespace parity::platforms::dx10
