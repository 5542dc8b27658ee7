// Shader-test script parser (harness/scripts/script.h): any text must parse or fail with a
// "file:line:column: error" message. Parsed from memory: the parser never touches a GPU.
#include <cstddef>
#include <cstdint>
#include <string>

#include "harness/scripts/script.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  parity::harness::script::parseScript(text, "fuzz.amber");
  return 0;
}
