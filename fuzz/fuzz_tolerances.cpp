// golden/tolerances.json parser: any byte string must load or fail with a message.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_file.h"
#include "harness/run/golden.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  parity::fuzz::InputFile file(data, size, ".json");
  parity::harness::CaseKey key{"forward", "default", "reference", "gl"};
  parity::harness::Tolerance tolerance;
  std::string error;
  parity::harness::loadTolerance(file.path(), key, &tolerance, &error);
  return 0;
}
