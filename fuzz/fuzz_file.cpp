#include "fuzz/fuzz_file.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

namespace parity::fuzz {

InputFile::InputFile(const uint8_t* data, size_t size, const std::string& extension) {
  // One folder per input: a scene's relative references (buffers, mtllib) then resolve inside it
  // and the confinement rules are exercised rather than reading whatever lies in /tmp.
  std::string tmpl = (std::filesystem::temp_directory_path() / "parity-fuzz-XXXXXX").string();
  std::vector<char> dirName(tmpl.begin(), tmpl.end());
  dirName.push_back('\0');
  if (!mkdtemp(dirName.data())) std::abort();
  dir_ = dirName.data();
  std::string file = dir_ + "/input-XXXXXX" + extension;
  std::vector<char> name(file.begin(), file.end());
  name.push_back('\0');
  int fd = mkstemps(name.data(), static_cast<int>(extension.size()));
  if (fd < 0) std::abort();
  size_t written = 0;
  while (written < size) {
    ssize_t n = ::write(fd, data + written, size - written);
    if (n <= 0) std::abort();
    written += static_cast<size_t>(n);
  }
  ::close(fd);
  path_ = name.data();
}

InputFile::~InputFile() {
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);
}

}  // namespace parity::fuzz
