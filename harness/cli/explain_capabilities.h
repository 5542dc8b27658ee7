// `parity explain`'s capability section: the platform's table (platforms/common/capabilities.h)
// and the port's paths a technique takes there, each with the capability that chose it.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "platforms/common/platform.h"

namespace parity::harness {

// The technique's port paths on `platform` ("-" for none) and the platform's capability rows
// and format rows, as text on stdout.
void printCapabilities(platforms::PlatformId platform, const std::string& technique);
// The same as JSON: {"port_paths": [...], "capabilities": [...], "formats": [...]}.
nlohmann::json capabilitiesJson(platforms::PlatformId platform, const std::string& technique);

}  // namespace parity::harness
