// Small file helpers shared by the golden, tolerance and expectation code (harness/run/golden.h
// declares the tolerance and expectation parsers, defined in harness/run/expectations.cpp).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace parity::harness {

// The whole file; false with "<path>: cannot read".
bool readTextFile(const std::string& path, std::string* text, std::string* error);
// The file parsed as JSON; false with "<path>: cannot read" or "<path>: not valid JSON: ...".
bool readJsonFile(const std::string& path, nlohmann::json* j, std::string* error);
// fnmatch(3) glob; an empty pattern matches everything.
bool globMatch(const std::string& pattern, const std::string& text);

}  // namespace parity::harness
