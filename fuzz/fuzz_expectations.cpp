// golden/expectations.json parser: any byte string must load or fail with a message.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz/fuzz_file.h"
#include "harness/run/golden.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  parity::fuzz::InputFile file(data, size, ".json");
  std::vector<parity::harness::Expectation> list;
  std::string error;
  if (parity::harness::loadExpectations(file.path(), &list, &error))
    parity::harness::findExpectation(list, "forward/default/reference/gl", "llvmpipe | Mesa");
  return 0;
}
