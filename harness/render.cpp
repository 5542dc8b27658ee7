#include "harness/render.h"

#include <exception>
#include <memory>

#include "harness/image_io.h"
#include "scene/scene_gpu.h"
#include "techniques/technique.h"

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
  if (request.colorFormat != rhi::Format::RGBA8 && request.colorFormat != rhi::Format::RGBA32F) {
    result.error = "colour format must be RGBA8 or RGBA32F";
    return result;
  }
  scene::Scene scene;
  if (!scene::makeScene(request.scene, request.sceneParams, &scene, &result.error)) return result;
  const scene::Camera* camera = scene.camera(request.camera);
  if (!camera) {
    result.error = "scene '" + request.scene + "' has no camera '" + request.camera + "'";
    return result;
  }
  std::unique_ptr<techniques::Technique> technique = techniques::createTechnique(request.technique);
  if (!technique) {
    result.error = "unknown technique '" + request.technique + "'";
    return result;
  }
  try {
    scene::SceneGpu gpu(device, scene);
    techniques::RenderSettings settings;
    settings.width = request.width;
    settings.height = request.height;
    settings.colorFormat = request.colorFormat;
    settings.shaderOptions = request.shaderOptions;
    technique->prepare(device, settings);
    rhi::TextureHandle color = technique->render(device, gpu, *camera);
    device.submit();
    result.texels = device.readTexture(color);
    technique->release(device);
    device.submit();
  } catch (const techniques::TechniqueError& e) {
    result.error = e.what();
    while (!result.error.empty() && result.error.back() == '\n') result.error.pop_back();
    return result;
  }
  size_t expected = static_cast<size_t>(request.width) * request.height * rhi::formatInfo(request.colorFormat).bytesPerTexel;
  if (result.texels.size() != expected) {
    result.error = "readback returned " + std::to_string(result.texels.size()) + " bytes, expected " +
                   std::to_string(expected);
    return result;
  }
  result.image = imageFromTexels(result.texels, request.colorFormat, request.width, request.height);
  result.ok = true;
  return result;
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
