#include "harness/run/render.h"

#include <charconv>
#include <exception>
#include <filesystem>
#include <memory>
#include <string_view>
#include <system_error>

#include "harness/io/image_io.h"
#include "harness/run/devices.h"

namespace parity::harness {

nlohmann::json toJson(const std::vector<platforms::Diagnostic>& diagnostics) {
  nlohmann::json out = nlohmann::json::array();
  for (const platforms::Diagnostic& d : diagnostics)
    out.push_back({{"code", d.code},
                   {"severity", std::string(platforms::severityName(d.severity))},
                   {"section", d.section},
                   {"message", d.message},
                   {"targets", d.targets},
                   {"pass", d.pass},
                   {"pipeline", d.pipeline},
                   {"count", d.count}});
  return out;
}

RenderResult renderFrame(const RenderRequest& request) {
  RenderResult result;
  rhi::DeviceDesc desc;
  desc.glContextProvider = request.glProvider;
  desc.debug = request.debug;
  std::string why;
  std::unique_ptr<rhi::Device> device = resolveDevice(request.backend, &desc, &why) ? rhi::createDevice(desc, &why) : nullptr;
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
  result.diagnostics = std::move(frame.diagnostics);
  result.unplannedTargets = std::move(frame.unplannedTargets);
  result.portPaths = std::move(frame.portPaths);
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

namespace {

// Digits only: std::stoul would skip blanks, accept '+' and wrap a '-' to a huge value.
enum class Dimension { Ok, NotANumber, TooLarge };
Dimension parseDimension(std::string_view text, unsigned long* value) {
  if (text.empty()) return Dimension::NotANumber;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), *value);
  if (ec == std::errc::result_out_of_range) return Dimension::TooLarge;
  if (ec != std::errc() || end != text.data() + text.size()) return Dimension::NotANumber;
  return Dimension::Ok;
}

}  // namespace

bool parseSize(const std::string& text, uint32_t* width, uint32_t* height, std::string* error) {
  unsigned long w = 0, h = 0;
  size_t x = text.find('x');
  Dimension dw = Dimension::NotANumber, dh = Dimension::NotANumber;
  if (x != std::string::npos) {
    std::string_view all(text);
    dw = parseDimension(all.substr(0, x), &w);
    dh = parseDimension(all.substr(x + 1), &h);
  }
  if (dw == Dimension::NotANumber || dh == Dimension::NotANumber) {
    *error = "size '" + text + "' is not WIDTHxHEIGHT (e.g. 320x180)";
    return false;
  }
  if (dw == Dimension::Ok && dh == Dimension::Ok && (w == 0 || h == 0)) {
    *error = "size '" + text + "' has a zero dimension";
    return false;
  }
  if (dw == Dimension::TooLarge || dh == Dimension::TooLarge || w > 16384 || h > 16384) {
    *error = "size '" + text + "' is larger than 16384 in a dimension";
    return false;
  }
  *width = static_cast<uint32_t>(w);
  *height = static_cast<uint32_t>(h);
  return true;
}

}  // namespace parity::harness
