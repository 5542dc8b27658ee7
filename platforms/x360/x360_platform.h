// The Xbox 360 platform: how each logical target is really allocated, written and read.
//
// Rules and models live next to this file: edram.h (X1, X4), fixed16.h (X2), resolve.h (X3),
// pixel_center.h (X5), edram_frame.h (a frame checked in order).
#pragma once

#include <cstdint>

#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "platforms/platform_layer.h"
#include "platforms/x360/edram.h"

namespace parity::platforms::x360 {

// The mapping of `logical` in the platform's target table (x360_layer.cpp).
TargetMapping mapTarget(LogicalFormat logical, const PlatformParams& params = {});

// The EDRAM surface of a planned target at width x height (its format, MSAA, role and placement).
EdramSurface edramSurface(const PhysicalTarget& target, uint32_t width, uint32_t height, const PlatformParams& params);

}  // namespace parity::platforms::x360
