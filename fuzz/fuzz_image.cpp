// Image loading as goldens and `parity diff` inputs are loaded (harness/io/image_io.h). The first
// byte picks the file extension, which decides the decoder OpenImageIO tries first.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_file.h"
#include "harness/io/image_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* const kExtensions[] = {".png", ".exr", ".hdr", ".tga"};
  std::string extension = kExtensions[data[0] % 4];
  parity::fuzz::InputFile file(data + 1, size - 1, extension);
  OIIO::ImageBuf image;
  std::string error;
  parity::harness::readImage(file.path(), &image, &error);
  return 0;
}
