#include "techniques/frame.h"

#include <memory>

#include "platforms/platform_device.h"
#include "scene/scene_gpu.h"
#include "techniques/technique.h"

namespace parity::techniques {

FrameResult renderFrameTexels(rhi::Device& host, const FrameRequest& request) {
  FrameResult result;
  // The technique draws through the platform's conventions (x360: D3D9 pixel centres).
  platforms::PlatformDevice device(host, request.platform, request.platformParams);
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
  std::unique_ptr<Technique> technique = createTechnique(request.technique);
  if (!technique) {
    result.error = "unknown technique '" + request.technique + "'";
    return result;
  }
  try {
    scene::SceneGpu gpu(device, scene);
    RenderSettings settings;
    settings.width = request.width;
    settings.height = request.height;
    settings.colorFormat = request.colorFormat;
    settings.shaderOptions = request.shaderOptions;
    settings.platform = request.platform;
    settings.platformParams = request.platformParams;
    settings.diagnostics = request.diagnostics;
    settings.capabilities = device.info().caps;
    technique->prepare(device, settings);
    for (const PortPath& p : technique->portPaths(settings.capabilities))
      result.portPaths.push_back(describePortPath(p, request.platform));
    rhi::TextureHandle color = technique->render(device, gpu, *camera);
    device.submit();
    result.diagnostics = device.diagnostics().all();
    result.unplannedTargets.assign(device.unplannedAttachments().begin(), device.unplannedAttachments().end());
    result.texels = device.readTexture(color);
    if (request.readTargets) {
      for (const NamedTarget& t : technique->targets()) {
        const rhi::TextureDesc* desc = device.describe(t.texture);
        if (!desc) continue;
        TargetTexels tt;
        tt.name = t.name;
        tt.format = desc->format;
        tt.width = desc->width;
        tt.height = desc->height;
        rhi::ReadbackRegion region;
        if (rhi::isDepthFormat(desc->format)) region.aspect = rhi::TextureAspect::Depth;  // one float per texel
        tt.texels = device.readTexture(t.texture, region);
        size_t texelBytes = rhi::isDepthFormat(desc->format) ? 4 : rhi::formatInfo(desc->format).bytesPerTexel;
        if (tt.texels.size() != static_cast<size_t>(tt.width) * tt.height * texelBytes) {
          result.error = "target '" + t.name + "' could not be read back";
          break;
        }
        result.targets.push_back(std::move(tt));
      }
    }
    technique->release(device);
    device.submit();
    if (!result.error.empty()) return result;
  } catch (const TechniqueError& e) {
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
  result.ok = true;
  return result;
}

}  // namespace parity::techniques
