// The reference platform: no quirks. Logical formats become float formats, values pass through
// unchanged, and no rule fires; the other platforms are compared against it.
#pragma once

#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"

namespace parity::platforms::reference {

// The mapping of `logical` in the platform's target table (reference_layer.cpp).
TargetMapping mapTarget(LogicalFormat logical, const PlatformParams& params = {});

// Writing then reading a logical value is the identity.
inline float roundTrip(float value) { return value; }

}  // namespace parity::platforms::reference
