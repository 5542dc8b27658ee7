#include "platforms/platforms.h"

#include "platforms/dx10/dx10_platform.h"
#include "platforms/ps3/ps3_platform.h"
#include "platforms/reference/reference_platform.h"
#include "platforms/x360/x360_platform.h"

namespace parity::platforms {

TargetMapping mapTarget(PlatformId platform, LogicalFormat logical, const PlatformParams& params) {
  switch (platform) {
    case PlatformId::Reference: return reference::mapTarget(logical, params);
    case PlatformId::Dx10: return dx10::mapTarget(logical, params);
    case PlatformId::Ps3: return ps3::mapTarget(logical, params);
    case PlatformId::X360: return x360::mapTarget(logical, params);
  }
  return reference::mapTarget(logical, params);
}

}  // namespace parity::platforms
