// The project's parsers take file paths (they resolve references relative to the file), so a
// fuzz input is written to a private temporary file first.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace parity::fuzz {

// A file holding the input, created with mkstemps (owner-only, unpredictable name) in its own
// temporary folder and removed with it on destruction.
class InputFile {
 public:
  InputFile(const uint8_t* data, size_t size, const std::string& extension);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string dir_, path_;
};

}  // namespace parity::fuzz
