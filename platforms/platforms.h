// Entry point to the platform models: one call that maps a logical target on any platform.
// Each platform's rules live in its own folder (reference, dx10, ps3, x360); the shared pieces
// (diagnostics, parameters, logical targets) in common/.
#pragma once

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"

namespace parity::platforms {

// The row of the platform's target table for `logical` (platform_layer.h, applyTargetRow).
TargetMapping mapTarget(PlatformId platform, LogicalFormat logical, const PlatformParams& params = {});

}  // namespace parity::platforms
