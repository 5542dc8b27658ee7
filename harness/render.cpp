#include "harness/render.h"

#include <exception>
#include <filesystem>
#include <memory>

#include "harness/image_io.h"

namespace parity::harness {

RenderResult renderFrame(const RenderRequest& request) {
  RenderResult result;
  rhi::DeviceDesc desc;
  desc.backend = request.backend;
  desc.glContextProvider = request.glProvider;
  desc.debug = request.debug;
  std::string why;
  std::unique_ptr<rhi::Device> device = rhi::createDevice(desc, &why);
  if (!device) {
    result.error = "backend " + request.backend + " unavailable: " + why;
    return result;
  }
  return renderFrame(*device, request);
}

RenderResult renderFrame(rhi::Device& device, const RenderRequest& request) {
  RenderResult result;
  result.device = device.info();
  techniques::FrameResult frame = techniques::renderFrameTexels(device, request.frame);
  if (!frame.ok) {
    result.error = frame.error;
    return result;
  }
  result.texels = std::move(frame.texels);
  result.targets = std::move(frame.targets);
  result.image = imageFromTexels(result.texels, request.frame.colorFormat, request.frame.width, request.frame.height);
  result.ok = true;
  return result;
}

bool writeTargets(const RenderResult& result, const std::string& dir, std::vector<std::string>* written,
                  std::string* error) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    *error = dir + ": cannot create the folder: " + ec.message();
    return false;
  }
  for (const techniques::TargetTexels& t : result.targets) {
    const rhi::FormatInfo& info = rhi::formatInfo(t.format);
    bool eightBit = !rhi::isDepthFormat(t.format) && info.channels > 0 && info.bytesPerTexel / info.channels == 1 &&
                    (info.kind == rhi::FormatKind::Unorm || info.kind == rhi::FormatKind::Srgb);
    std::string name = t.name;
    for (char& c : name)
      if (c == '/' || c == '\\' || c == ' ') c = '_';
    std::string path = (std::filesystem::path(dir) / (name + (eightBit ? ".png" : ".exr"))).string();
    if (!writeImage(path, imageFromTexels(t.texels, t.format, t.width, t.height), error)) return false;
    written->push_back(path);
  }
  return true;
}

bool parseSize(const std::string& text, uint32_t* width, uint32_t* height, std::string* error) {
  unsigned long w = 0, h = 0;
  size_t x = text.find('x');
  try {
    if (x == std::string::npos) throw std::invalid_argument("no x");
    size_t usedW = 0, usedH = 0;
    w = std::stoul(text.substr(0, x), &usedW);
    h = std::stoul(text.substr(x + 1), &usedH);
    if (usedW != x || usedH != text.size() - x - 1) throw std::invalid_argument("trailing");
  } catch (const std::exception&) {
    *error = "size '" + text + "' is not WIDTHxHEIGHT (e.g. 320x180)";
    return false;
  }
  if (w == 0 || h == 0) {
    *error = "size '" + text + "' has a zero dimension";
    return false;
  }
  if (w > 16384 || h > 16384) {
    *error = "size '" + text + "' is larger than 16384 in a dimension";
    return false;
  }
  *width = static_cast<uint32_t>(w);
  *height = static_cast<uint32_t>(h);
  return true;
}

}  // namespace parity::harness
