// Text the harness writes into one-line places: error lines, verdict reasons, JSON fields.
#pragma once

#include <cstddef>
#include <string>

namespace parity::harness {

// `text` on one line: trailing newlines and blanks dropped, inner newlines turned into blanks,
// and cut after `maxChars` characters (marked "...").
std::string oneLine(std::string text, size_t maxChars = std::string::npos);

// Now, in UTC, as ISO 8601 ("2026-12-02T18:47:53Z").
std::string nowIso();

}  // namespace parity::harness
