#include "harness/io/image_io.h"

#include <OpenImageIO/imagebufalgo.h>

#include <cstdio>
#include <filesystem>
#include <mutex>

#include "harness/io/atomic_file.h"

namespace fs = std::filesystem;

namespace parity::harness {

OIIO::ImageBuf imageFromTexels(const std::vector<uint8_t>& texels, rhi::Format format, uint32_t width,
                               uint32_t height) {
  const rhi::FormatInfo& info = rhi::formatInfo(format);
  OIIO::TypeDesc type = OIIO::TypeDesc::UINT8;
  switch (info.kind) {
    case rhi::FormatKind::Float: type = info.bytesPerTexel / info.channels == 2 ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT; break;
    case rhi::FormatKind::Depth:
    case rhi::FormatKind::DepthStencil: type = OIIO::TypeDesc::FLOAT; break;
    case rhi::FormatKind::Uint: type = info.bytesPerTexel / info.channels == 1 ? OIIO::TypeDesc::UINT8
                                       : info.bytesPerTexel / info.channels == 2 ? OIIO::TypeDesc::UINT16
                                                                                 : OIIO::TypeDesc::UINT32; break;
    case rhi::FormatKind::Unorm: type = info.bytesPerTexel / info.channels == 2 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8; break;
    case rhi::FormatKind::Snorm:
    case rhi::FormatKind::Sint: type = info.bytesPerTexel / info.channels == 1 ? OIIO::TypeDesc::INT8
                                       : info.bytesPerTexel / info.channels == 2 ? OIIO::TypeDesc::INT16
                                                                                 : OIIO::TypeDesc::INT32; break;
    case rhi::FormatKind::Srgb: type = OIIO::TypeDesc::UINT8; break;
  }
  int channels = static_cast<int>(rhi::isDepthFormat(format) ? 1 : info.channels);
  OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height), channels, type);
  OIIO::ImageBuf buf(spec);
  buf.set_pixels(OIIO::ROI::All(), type, texels.data());
  return buf;
}

bool writeImage(const std::string& path, const OIIO::ImageBuf& image, std::string* error) {
  fs::path target(path);
  fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    *error = path + ": folder '" + dir.string() + "' does not exist";
    return false;
  }
  std::string ext = target.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  OIIO::TypeDesc type;
  if (ext == ".png") type = OIIO::TypeDesc::UINT8;
  else if (ext == ".exr") type = OIIO::TypeDesc::FLOAT;
  else {
    *error = path + ": unsupported image extension '" + ext + "' (use .png or .exr)";
    return false;
  }
  // Same folder, so the rename is atomic; the name keeps the extension for OIIO's format choice.
  fs::path tmp = temporarySibling(path);
  OIIO::ImageBuf out = image;
  // Texels as rendered: data targets keep values where alpha is 0 (a light index, a specular
  // power), so PNG's alpha is not taken as premultiplication to undo.
  out.specmod().attribute("oiio:UnassociatedAlpha", 1);
  // zlib's fastest level: a matrix run writes more than a thousand PNGs (images, targets and
  // their previews), and at OpenImageIO's default level 6 their compression was a tenth of the
  // children's time. The texels are the same at every level.
  // No row filter either: libpng's adaptive choice tries all five filters on every row, which
  // doubled the time of a write, and on these renders (flat regions, sharp edges) the files
  // came out larger with it than without (a G-buffer target: 17.7 KB against 13.0 KB).
  if (ext == ".png") {
    out.specmod().attribute("png:compressionLevel", 1);
    out.specmod().attribute("png:filter", 8);  // PNG_FILTER_NONE
  }
  atomicWriteStep();
  if (!out.write(tmp.string(), type)) {
    *error = path + ": cannot write image: " + out.geterror();
    fs::remove(tmp, ec);
    return false;
  }
  atomicWriteStep();
  fs::rename(tmp, target, ec);
  if (ec) {
    *error = path + ": cannot replace file: " + ec.message();
    fs::remove(tmp, ec);
    return false;
  }
  atomicWriteStep();
  return true;
}

namespace {

std::string joinLines(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text;
}

// Image libraries below OpenImageIO (libpng's default error handler above all) print straight
// to file descriptor 2, which would put stray lines next to the harness's one-line error. While
// `body` runs, descriptor 2 goes to a temporary file; what was printed is returned and, when the
// caller does not use it, written back. Serialised: descriptor 2 belongs to the whole process.
template <typename Body>
std::string withStderrCaptured(Body body) {
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  std::fflush(stderr);
  std::FILE* capture = std::tmpfile();
  int saved = capture ? ::dup(2) : -1;
  if (saved < 0 || ::dup2(::fileno(capture), 2) < 0) {
    if (saved >= 0) ::close(saved);
    if (capture) std::fclose(capture);
    body();
    return "";
  }
  auto restore = [&] {
    std::fflush(stderr);
    ::dup2(saved, 2);
    ::close(saved);
  };
  try {
    body();
  } catch (...) {
    restore();
    std::fclose(capture);
    throw;
  }
  restore();
  std::string text;
  std::rewind(capture);
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, capture)) > 0;) text.append(buf, n);
  std::fclose(capture);
  return text;
}

}  // namespace

bool readImage(const std::string& path, OIIO::ImageBuf* image, std::string* error) {
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    *error = path + ": no such file";
    return false;
  }
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // the texels as written, not multiplied by alpha
  OIIO::ImageBuf buf(path, 0, 0, nullptr, &config);
  bool ok = false;
  std::string printed = withStderrCaptured([&] { ok = buf.read(0, 0, true); });
  if (!ok) {
    std::string why = joinLines(buf.geterror());
    // Kept only when it adds to OpenImageIO's own message, which usually repeats libpng's text
    // without the "libpng error: " prefix.
    std::string library = joinLines(printed);
    const std::string prefix = "libpng error: ";
    std::string text = library.rfind(prefix, 0) == 0 ? library.substr(prefix.size()) : library;
    if (!text.empty() && why.find(text) == std::string::npos) why += why.empty() ? library : " (" + library + ")";
    *error = path + ": not a readable image: " + why;
    return false;
  }
  if (!printed.empty()) std::fputs(printed.c_str(), stderr);  // warnings of a readable image stay visible
  *image = std::move(buf);
  return true;
}

}  // namespace parity::harness
