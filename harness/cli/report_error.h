// The one-line error every command prints. Apart from commands.h so that code that reports
// errors does not compile CLI11 (header-only, several seconds a file).
#pragma once

#include <string>

namespace parity::harness {

// Prints "parity: error: <message>" as one line on stderr and returns `code`.
int reportError(const std::string& message, int code = 2);

}  // namespace parity::harness
