// parity's RHI validation layer: a Device that checks every call against the rules below and
// forwards valid calls to the backend it wraps. Backends assume valid input.
//
// Each rule has a stable id (tests assert on it; never renumber or rename). A call that breaks
// a rule is reported through DeviceDesc::onValidationError and dropped: creation returns a null
// handle, commands do nothing.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "rhi/rhi.h"

namespace parity::rhi {

using ValidationCallback = std::function<void(const std::string& id, const std::string& message)>;

std::unique_ptr<Device> wrapWithValidation(std::unique_ptr<Device> backend, ValidationCallback onError);

}  // namespace parity::rhi
