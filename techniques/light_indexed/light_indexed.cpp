#include "techniques/light_indexed/light_indexed.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace parity::techniques {

namespace {

// Light colours are intensities up to 2 (scene::placeLights); the RGBA8 colour table stores
// them divided by this (a power of two: the scaling back is exact).
constexpr float kColorScale = 2.0f;

float byteToUnorm(uint8_t b) { return static_cast<float>(b) / 255.0f; }

float opacityOf(const scene::Scene& s, int material) {
  return material >= 0 && size_t(material) < s.materials.size() ? s.materials[size_t(material)].opacity : 1.0f;
}

}  // namespace

LightIndexedDeferred::LightIndexedDeferred(LidrPacking packing, BitPackingLayout layout, LidrVolumes volumes)
    : packing_(packing), layout_(layout), volumes_mode_(volumes) {}

std::string LightIndexedDeferred::name() const {
  if (msaa()) {
    LightIndexedDeferred single(packing_, layout_);
    return packing_ == LidrPacking::Bits && layout_.label() == "8x255" ? "lidr-msaa" : "lidr-msaa-" + single.name().substr(5);
  }
  switch (packing_) {
    case LidrPacking::Sort:
      return "lidr-sort";
    case LidrPacking::Max:
      return "lidr-max";
    case LidrPacking::Bits:
      break;
  }
  return layout_.label() == "4x255" ? "lidr-bits" : "lidr-bits-" + layout_.label();
}

uint32_t LightIndexedDeferred::maxLights() const { return packing_ == LidrPacking::Bits ? layout_.maxLights() : 255; }

uint32_t LightIndexedDeferred::capacity() const { return packing_ == LidrPacking::Bits ? layout_.overlaps() : 4; }

std::vector<PassInfo> LightIndexedDeferred::passes() const {
  std::string packingPass;
  switch (packing_) {
    case LidrPacking::Sort:
      packingPass = "light volumes of four CPU-sorted non-overlapping arrays, each into its own channel";
      break;
    case LidrPacking::Max:
      packingPass = "light volumes twice with MAX blending, (index, 1 - index) into red/green for the first two "
                    "lights and blue/alpha for the rest, the stencil limiting writes";
      break;
    case LidrPacking::Bits:
      packingPass = "light volumes with blend ONE, CONSTANT_COLOR " + std::to_string(layout_.blendConstant()) +
                    ": each index split into " + std::to_string(layout_.chunkBits()) + "-bit chunks over " +
                    std::to_string(layout_.channels) + " channels, the stencil keeping the first " +
                    std::to_string(layout_.overlaps());
      break;
  }
  std::vector<std::string> indexTargets = {"lidr.index"};
  if (packing_ == LidrPacking::Bits && layout_.targets() == 2) indexTargets.push_back("lidr.index2");
  indexTargets.push_back("depth");
  if (msaa())
    return {{"depth pre-pass", "opaque meshes, depth only, 4x MSAA", {"depth"}},
            {"farthest sample", "per pixel the farthest of the 4 samples' depths, into the single-sample depth buffer",
             {"prepass.depth", "depth"}},
            {"overlap count", "light volume front faces in front of the farthest sample (back faces where the camera "
                              "is inside), adding 1/255: lights crossing the eye rays", {"lidr.count"}},
            {"light index", packingPass + "; front faces, depth test LESS, single-sample", indexTargets},
            {"forward", "4x MSAA: opaque geometry (depth EQUAL), then translucent meshes back to front blended with "
                        "their opacity, all lit from the same light index texture; resolved",
             {"color", "lidr.dropped"}}};
  return {{"depth pre-pass", "render depth only (and keep it readable for the light volume test)",
           {"prepass.depth", "depth"}},
          {"overlap count", "light volumes adding 1/255 where they reach the surface: lights per pixel",
           {"lidr.count"}},
          {"light index", packingPass, indexTargets},
          {"forward", "geometry with forward lighting over the lights looked up by index in the light tables",
           {"color", "lidr.dropped"}}};
}

std::vector<platforms::LogicalTarget> LightIndexedDeferred::logicalTargets(const RenderSettings& settings) const {
  using platforms::LogicalFormat;
  using platforms::TargetRole;
  // The light volumes test against the single-sample depth and read its copy as colour (the
  // farthest sample's, multisampled); the light index is single-sample either way, its bits the
  // packed indices. Multisampled, the frame colour and the lost-light count are 4x and resolved.
  const std::string depthPass = msaa() ? "farthest sample" : "depth pre-pass";
  const uint32_t samples = msaa() ? kMsaaSamples : 1;
  std::vector<platforms::LogicalTarget> t = {sceneDepthTarget(depthPass, false, true),
                                             {kSurfaceDepth, LogicalFormat::R32Float, true, TargetRole::Plain, depthPass},
                                             {kOverlapCount, LogicalFormat::R8Unorm, true, TargetRole::Plain, "overlap count"},
                                             {kLightIndex, LogicalFormat::Rgba8Bits, true, TargetRole::Plain, "light index"}};
  if (packing_ == LidrPacking::Bits && layout_.targets() == 2)
    t.push_back({kLightIndex2, LogicalFormat::Rgba8Bits, true, TargetRole::Plain, "light index"});
  platforms::LogicalTarget color = outputColorTarget(settings, "forward");
  color.samples = samples;
  t.push_back(color);
  // Beside the colour: one surface format for both on ps3 (P1); its bits are the count k / 255.
  t.push_back({kDropped, LogicalFormat::Rgba8Bits, true, TargetRole::Plain, "forward", samples});
  if (msaa()) {
    platforms::LogicalTarget depth = sceneDepthTarget("depth pre-pass");
    depth.name = kMsaaDepth;
    depth.samples = kMsaaSamples;
    // Its contents survive every pass between the pre-pass that writes them and the forward pass
    // that tests against them: on x360 no target of those passes may take its EDRAM tiles.
    depth.livePasses = {"depth pre-pass", "farthest sample", "overlap count", "light index", "forward"};
    t.push_back(depth);
    platforms::LogicalTarget surface{kMsaaSurfaceDepth, LogicalFormat::R32Float, true, TargetRole::Plain, "depth pre-pass",
                                     kMsaaSamples};
    surface.readSamples = true;  // the farthest-sample pass reads every sample
    t.push_back(surface);
  }
  return t;
}

std::vector<NamedTarget> LightIndexedDeferred::targets() const {
  if (!targets_) return {};
  std::vector<NamedTarget> t = {{kSurfaceDepth, targets_->readTexture(kSurfaceDepth)},
                                {kOverlapCount, targets_->readTexture(kOverlapCount)}};
  for (const char* index : {kLightIndex, kLightIndex2})
    if (targets_->attachment(index)) t.push_back({index, targets_->attachment(index)});
  t.push_back({kOutputColor, targets_->readTexture(kOutputColor)});
  t.push_back({kDropped, targets_->readTexture(kDropped)});
  t.push_back({kSceneDepth, targets_->attachment(kSceneDepth)});
  return t;
}

rhi::PipelineHandle LightIndexedDeferred::volumePipeline(rhi::Device& device, const std::string& label,
                                                         uint8_t writeMask, const rhi::BlendState& blend, bool stencil,
                                                         const rhi::StencilFaceState& face, rhi::Format format,
                                                         uint32_t targetCount, bool cameraInside) {
  rhi::ShaderCompileOptions options = settings_.shaderOptions;
  if (targetCount == 2) options.defines.push_back({"LIDR_SECOND_TARGET", "1"});
  if (msaa()) options.defines.push_back({"LIDR_FRONT_FACES", "1"});
  rhi::PipelineDesc p;
  p.vertexShader = shaders_->load("light_indexed/light_volume.vert", settings_.shaderOptions);
  p.fragmentShader = shaders_->load("light_indexed/light_volume.frag", options);
  LightVolumes::describeVertexLayout(p);
  // Back faces with GREATER_EQUAL: a surface inside the volume is in front of its back faces,
  // whether or not the camera is inside the volume (front faces may be clipped by the near
  // plane). The fragment shader then keeps exactly the surfaces the light reaches.
  p.raster.cull = rhi::CullMode::Front;
  p.depthStencil.depthCompare = rhi::CompareOp::GreaterEqual;
  if (msaa()) {
    // MSAA technique 2: front faces nearer than the farthest sample, so every light volume the
    // eye ray crosses before the opaque surface counts (no test of the surface: a translucent
    // surface in front of it may be lit where the opaque one is not). With the camera inside the
    // volume every ray starts inside it: back faces, no depth test.
    p.raster.cull = cameraInside ? rhi::CullMode::Front : rhi::CullMode::Back;
    p.depthStencil.depthCompare = cameraInside ? rhi::CompareOp::Always : rhi::CompareOp::Less;
  }
  p.depthStencil.depthWrite = false;
  p.depthStencil.stencilEnabled = stencil;
  p.depthStencil.front = p.depthStencil.back = face;
  for (uint32_t i = 0; i < targetCount; ++i) {
    p.colorTargets[i].format = format;
    p.colorTargets[i].blend = blend;
    p.colorTargets[i].writeMask = writeMask;
  }
  p.colorTargetCount = targetCount;
  p.depthStencilFormat = targets_->format(kSceneDepth);
  p.label = name() + " " + label + (cameraInside ? " (camera inside)" : "");
  rhi::PipelineHandle h = device.createPipeline(p);
  if (!h) throw TechniqueError(name() + ": the device rejected the " + label + " pipeline");
  return h;
}

LightIndexedDeferred::VolumePipelines LightIndexedDeferred::volumePipelines(
    rhi::Device& device, const std::string& label, uint8_t writeMask, const rhi::BlendState& blend, bool stencil,
    const rhi::StencilFaceState& face, rhi::Format format, uint32_t targetCount) {
  VolumePipelines pair{};
  pair[0] = volumePipeline(device, label, writeMask, blend, stencil, face, format, targetCount, false);
  // The single-sample technique's back-face test already holds with the camera inside.
  pair[1] = msaa() ? volumePipeline(device, label, writeMask, blend, stencil, face, format, targetCount, true) : pair[0];
  return pair;
}

uint32_t LightIndexedDeferred::tableRow(size_t mesh) const {
  if (mesh >= surfaceTables_.meshTable.size()) return 0;
  uint32_t t = surfaceTables_.meshTable[mesh];
  return t < surfaceTables_.excluded.size() ? t + 1 : 0;  // row 0: every light
}

void LightIndexedDeferred::prepare(rhi::Device& device, const RenderSettings& settings) {
  if (packing_ == LidrPacking::Bits && (layout_.groups != 1 || layout_.indexBits > 8))
    throw TechniqueError(name() + ": the " + layout_.label() + " row is unpacked (lidrUnpackBitsRows) but not rendered");
  settings_ = settings;
  shaders_ = std::make_unique<ShaderLibrary>(device);
  volumes_ = std::make_unique<LightVolumes>(device);
  targets_ = std::make_unique<PlannedTargets>(device, settings, logicalTargets(settings), name());
  settings_.shaderOptions = targets_->shaderOptions(settings);
  const rhi::Format depthFormat = targets_->format(kSceneDepth);

  rhi::PipelineDesc p;
  p.vertexShader = shaders_->load("forward/forward.vert", settings_.shaderOptions);
  p.fragmentShader = shaders_->load("light_indexed/depth_prepass.frag", settings_.shaderOptions);
  scene::SceneGpu::describeVertexLayout(p);
  p.raster.cull = rhi::CullMode::Back;
  p.depthStencil.depthCompare = rhi::CompareOp::Less;
  p.depthStencil.depthWrite = true;
  p.colorTargets[0].format = targets_->format(msaa() ? kMsaaSurfaceDepth : kSurfaceDepth);
  p.colorTargetCount = 1;
  p.depthStencilFormat = targets_->format(msaa() ? kMsaaDepth : kSceneDepth);
  p.samples = msaa() ? kMsaaSamples : 1;
  p.label = name() + " depth pre-pass";
  prepassPipeline_ = device.createPipeline(p);

  // The forward pass: same vertex shader and depth format as the pre-pass, so EQUAL keeps
  // exactly the visible surface.
  rhi::ShaderCompileOptions shade = settings_.shaderOptions;
  switch (packing_) {
    case LidrPacking::Sort:
      shade.defines.push_back({"LIDR_PACKING_SORT", "1"});
      break;
    case LidrPacking::Max:
      shade.defines.push_back({"LIDR_PACKING_MAX", "1"});
      break;
    case LidrPacking::Bits:
      shade.defines.push_back({"LIDR_PACKING_BITS", "1"});
      shade.defines.push_back({"LIDR_CHANNELS", std::to_string(layout_.channels)});
      shade.defines.push_back({"LIDR_INDEX_BITS", std::to_string(layout_.indexBits)});
      break;
  }
  shade.defines.push_back({"LIDR_COLOR_SCALE", "2.0"});
  if (shadeEveryLight_) shade.defines.push_back({"LIDR_EVERY_LIGHT", "1"});
  // Multisampled, each sample writes its count times the samples: the averaging resolve keeps the
  // samples' total exactly (k / 255) instead of rounding one lost light on one sample away.
  shade.defines.push_back({"LIDR_DROPPED_SCALE", msaa() ? std::to_string(kMsaaSamples) + ".0" : "1.0"});
  p.fragmentShader = shaders_->load("light_indexed/lidr_shade.frag", shade);
  p.depthStencil.depthCompare = rhi::CompareOp::Equal;
  p.depthStencil.depthWrite = false;
  p.colorTargets[0].format = targets_->format(kOutputColor);
  p.colorTargets[1].format = targets_->format(kDropped);
  p.colorTargetCount = 2;
  p.label = name() + " forward";
  shadePipeline_ = device.createPipeline(p);
  if (!prepassPipeline_ || !shadePipeline_) throw TechniqueError(name() + ": the device rejected a pipeline");
  if (msaa()) {
    // Translucent meshes: both faces, in front of the opaque surface, blended with the mesh's
    // opacity (the blend constant, set per mesh).
    p.raster.cull = rhi::CullMode::None;
    p.depthStencil.depthCompare = rhi::CompareOp::Less;
    p.colorTargets[0].blend.enabled = true;
    p.colorTargets[0].blend.srcColor = p.colorTargets[0].blend.srcAlpha = rhi::BlendFactor::ConstantColor;
    p.colorTargets[0].blend.dstColor = p.colorTargets[0].blend.dstAlpha = rhi::BlendFactor::OneMinusConstantColor;
    p.label = name() + " forward translucent";
    translucentPipeline_ = device.createPipeline(p);

    rhi::PipelineDesc f;
    f.vertexShader = shaders_->load("platforms/fullscreen.vert", settings_.shaderOptions);
    f.fragmentShader = shaders_->load("light_indexed/farthest_sample.frag", settings_.shaderOptions);
    f.depthStencil.depthCompare = rhi::CompareOp::Always;
    f.depthStencil.depthWrite = true;
    f.colorTargets[0].format = targets_->format(kSurfaceDepth);
    f.colorTargetCount = 1;
    f.depthStencilFormat = depthFormat;
    f.label = name() + " farthest sample";
    farthestPipeline_ = device.createPipeline(f);
    if (!translucentPipeline_ || !farthestPipeline_) throw TechniqueError(name() + ": the device rejected a pipeline");
  }

  rhi::BlendState add;
  add.enabled = true;
  add.srcColor = add.dstColor = add.srcAlpha = add.dstAlpha = rhi::BlendFactor::One;
  countPipeline_ =
      volumePipelines(device, "overlap count", rhi::ColorMask_R, add, false, {}, targets_->format(kOverlapCount), 1);

  switch (packing_) {
    case LidrPacking::Sort:
      for (uint8_t c = 0; c < 4; ++c)
        indexPipelines_.push_back(volumePipelines(device, "light index channel " + std::to_string(c),
                                                 static_cast<uint8_t>(1u << c), {}, false, {}, targets_->format(kLightIndex), 1));
      break;
    case LidrPacking::Max: {
      rhi::BlendState max;
      max.enabled = true;
      max.colorOp = max.alphaOp = rhi::BlendOp::Max;
      // Pass 1: stencil counts the writes and passes while fewer than two (reference 2 > stencil).
      rhi::StencilFaceState first;
      first.compare = rhi::CompareOp::Greater;
      first.pass = rhi::StencilOp::IncrementClamp;
      indexPipelines_.push_back(volumePipelines(device, "light index red/green", rhi::ColorMask_R | rhi::ColorMask_G,
                                               max, true, first, targets_->format(kLightIndex), 1));
      // Pass 2: the lights pass 1 took fail and decrement; once back at 0 the rest pass.
      rhi::StencilFaceState second;
      second.compare = rhi::CompareOp::Equal;
      second.fail = rhi::StencilOp::DecrementClamp;
      indexPipelines_.push_back(volumePipelines(device, "light index blue/alpha", rhi::ColorMask_B | rhi::ColorMask_A,
                                               max, true, second, targets_->format(kLightIndex), 1));
      break;
    }
    case LidrPacking::Bits: {
      rhi::BlendState shiftIn;
      shiftIn.enabled = true;
      shiftIn.srcColor = shiftIn.srcAlpha = rhi::BlendFactor::One;
      shiftIn.dstColor = shiftIn.dstAlpha = rhi::BlendFactor::ConstantColor;
      // The stencil lets the first overlaps() lights in: a further write would shift the
      // oldest chunk out, and the blender rounds (not truncates) what it shifts (mesa-facts Q3),
      // which would corrupt the indices kept. The first ones stay exact.
      rhi::StencilFaceState limit;
      limit.compare = rhi::CompareOp::Greater;
      limit.pass = rhi::StencilOp::IncrementClamp;
      uint8_t mask = layout_.channels >= 4 ? static_cast<uint8_t>(rhi::ColorMask_All)
                     : layout_.channels == 2 ? static_cast<uint8_t>(rhi::ColorMask_R | rhi::ColorMask_G)
                                             : static_cast<uint8_t>(rhi::ColorMask_R);
      indexPipelines_.push_back(volumePipelines(device, "light index", mask, shiftIn, true, limit, targets_->format(kLightIndex),
                                               layout_.targets()));
      break;
    }
  }
}

void LightIndexedDeferred::releaseFrameResources(rhi::Device& device) {
  if (lightColors_) device.destroy(lightColors_);
  if (lightData_) device.destroy(lightData_);
  if (volumeModels_) device.destroy(volumeModels_);
  lightColors_ = {};
  lightData_ = {};
  volumeModels_ = {};
}

void LightIndexedDeferred::drawVolumes(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera,
                                       const VolumePipelines& pipelines, const std::vector<rhi::ResourceBinding>& bindings,
                                       const std::vector<uint32_t>& lights,
                                       const std::vector<scene::GpuMaterial>& outputs) {
  const scene::Scene& s = scene.scene();
  const float aspect = static_cast<float>(settings_.width) / static_cast<float>(settings_.height);
  // In draw order, switching pipeline only where the camera-inside variant differs.
  rhi::PipelineHandle bound{};
  for (size_t i = 0; i < lights.size(); ++i) {
    const scene::Light& light = s.lights[lights[i]];
    rhi::PipelineHandle want = pipelines[msaa() && cameraInsideLightVolume(light, camera, aspect) ? 1 : 0];
    if (want.id != bound.id) {
      device.setPipeline(want);
      device.setBindings(bindings);
      bound = want;
    }
    scene::GpuMaterial m = outputs[i];
    m.flags.y = lights[i];
    device.pushConstants(&m, sizeof(m));
    volumes_->draw(light);
  }
}

rhi::TextureHandle LightIndexedDeferred::render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) {
  const float aspect = static_cast<float>(settings_.width) / static_cast<float>(settings_.height);
  scene.setCamera(camera, aspect);
  const scene::Scene& s = scene.scene();
  const uint32_t lightCount = static_cast<uint32_t>(s.lights.size());
  const uint32_t tableLights = maxLights();
  const uint32_t indexed = std::min(lightCount, tableLights);

  // Light tables: column i + 1 is scene light i; column 0 the null light (all zero: black). The
  // colour table's row 0 holds every light, row t + 1 surface table t, its excluded lights black.
  releaseFrameResources(device);
  const uint32_t colorRows = 1 + static_cast<uint32_t>(surfaceTables_.excluded.size());
  std::vector<uint8_t> colors(static_cast<size_t>(tableLights + 1) * 4 * colorRows, 0);
  std::vector<float> data(static_cast<size_t>(tableLights + 1) * 4 * 3, 0.0f);
  const size_t row = static_cast<size_t>(tableLights + 1) * 4;
  for (uint32_t l = 0; l < indexed; ++l) {
    const scene::Light& light = s.lights[l];
    size_t c = static_cast<size_t>(l + 1) * 4;
    for (int k = 0; k < 3; ++k)
      colors[c + k] = static_cast<uint8_t>(std::lround(std::clamp(light.color[k] / kColorScale, 0.0f, 1.0f) * 255.0f));
    colors[c + 3] = 255;
    glm::vec3 dir = glm::normalize(light.direction);
    uint32_t type = static_cast<uint32_t>(light.type);
    float typeBits;
    std::memcpy(&typeBits, &type, sizeof(typeBits));
    float row0[4] = {light.position.x, light.position.y, light.position.z, 1.0f / light.radius};
    float row1[4] = {dir.x, dir.y, dir.z, light.cosOuter};
    float row2[4] = {light.cosInner, typeBits, light.radius, 0.0f};
    std::copy(row0, row0 + 4, data.begin() + c);
    std::copy(row1, row1 + 4, data.begin() + row + c);
    std::copy(row2, row2 + 4, data.begin() + 2 * row + c);
  }
  for (uint32_t t = 1; t < colorRows; ++t) {
    std::copy(colors.begin(), colors.begin() + static_cast<std::ptrdiff_t>(row), colors.begin() + t * row);
    for (uint32_t l : surfaceTables_.excluded[t - 1])
      if (l < indexed) std::fill_n(colors.begin() + t * row + (l + 1) * 4, 3, uint8_t{0});
  }
  rhi::TextureDesc td;
  td.format = rhi::Format::RGBA8;
  td.width = tableLights + 1;
  td.height = colorRows;
  td.usage = rhi::TextureUsage_Sampled;
  td.initialData = colors.data();
  td.label = name() + " light colours";
  lightColors_ = device.createTexture(td);
  td.format = rhi::Format::RGBA32F;
  td.height = 3;
  td.initialData = data.data();
  td.label = name() + " light data";
  lightData_ = device.createTexture(td);

  std::vector<glm::mat4> models(std::max<uint32_t>(lightCount, 1), glm::mat4(1.0f));
  for (uint32_t l = 0; l < lightCount; ++l) models[l] = LightVolumes::model(s.lights[l]);
  rhi::BufferDesc bd;
  bd.size = models.size() * sizeof(glm::mat4);
  bd.usage = rhi::BufferUsage_Storage;
  bd.initialData = models.data();
  bd.label = name() + " light volume models";
  volumeModels_ = device.createBuffer(bd);
  if (!lightColors_ || !lightData_ || !volumeModels_) throw TechniqueError(name() + ": cannot create light tables");

  // 1. Depth pre-pass (also clears the stencil the packing passes count in). Multisampled, of
  // the opaque meshes only; then the farthest sample per pixel into the single-sample buffers.
  rhi::PassDesc pre;
  pre.colors[0].texture = targets_->attachment(msaa() ? kMsaaSurfaceDepth : kSurfaceDepth);
  pre.colors[0].clearColor = {1.0f, 0.0f, 0.0f, 0.0f};
  pre.depthStencil.texture = targets_->attachment(msaa() ? kMsaaDepth : kSceneDepth);
  pre.label = "depth pre-pass";
  device.beginPass(pre);
  device.setPipeline(prepassPipeline_);
  for (const scene::Mesh& mesh : s.meshes)
    if (!msaa() || opacityOf(s, mesh.material) >= 1.0f) scene.drawMesh(mesh);
  device.endPass();
  if (msaa()) {
    targets_->resolve(kMsaaSurfaceDepth);  // x360: each sample into its own layer
    rhi::PassDesc farthest;
    farthest.colors[0].texture = targets_->attachment(kSurfaceDepth);
    farthest.depthStencil.texture = targets_->attachment(kSceneDepth);
    farthest.label = "farthest sample";
    device.beginPass(farthest);
    device.setPipeline(farthestPipeline_);
    rhi::ResourceBinding sampleDepths;
    sampleDepths.binding = 4;
    sampleDepths.kind = rhi::BindingKind::SampledTexture;
    sampleDepths.texture = targets_->readTexture(kMsaaSurfaceDepth);
    device.setBindings({&sampleDepths, 1});
    device.draw(3);
    device.endPass();
  }

  std::vector<rhi::ResourceBinding> volumeBindings(4);
  volumeBindings[0].binding = 0;
  volumeBindings[0].kind = rhi::BindingKind::UniformBuffer;
  volumeBindings[0].buffer = scene.frameBuffer();
  volumeBindings[1].binding = 1;
  volumeBindings[1].kind = rhi::BindingKind::StorageBuffer;
  volumeBindings[1].buffer = scene.lightBuffer();
  volumeBindings[2].binding = 3;
  volumeBindings[2].kind = rhi::BindingKind::StorageBuffer;
  volumeBindings[2].buffer = volumeModels_;
  volumeBindings[3].binding = 4;
  volumeBindings[3].kind = rhi::BindingKind::SampledTexture;
  targets_->resolve(kSurfaceDepth);
  volumeBindings[3].texture = targets_->readTexture(kSurfaceDepth);

  // 2. Overlap count: every light, including those beyond the index range. A diagnostic of the
  // harness, not a pass of the paper: without RenderSettings::diagnostics it only clears.
  std::vector<uint32_t> all(lightCount);
  for (uint32_t l = 0; l < lightCount; ++l) all[l] = l;
  const std::vector<uint32_t> counted = settings_.diagnostics ? all : std::vector<uint32_t>{};
  scene::GpuMaterial one{};
  one.diffuse = glm::vec4(1.0f / 255.0f, 0.0f, 0.0f, 0.0f);
  rhi::PassDesc count;
  count.colors[0].texture = targets_->attachment(kOverlapCount);
  count.depthStencil.texture = targets_->attachment(kSceneDepth);
  count.depthStencil.load = rhi::LoadOp::Load;
  count.label = "overlap count";
  device.beginPass(count);
  drawVolumes(device, scene, camera, countPipeline_, volumeBindings, counted,
              std::vector<scene::GpuMaterial>(counted.size(), one));
  device.endPass();
  targets_->resolve(kOverlapCount);

  // 3. Light index pass(es).
  rhi::PassDesc index;
  index.colors[0].texture = targets_->attachment(kLightIndex);
  index.colors[1].texture = targets_->attachment(kLightIndex2);  // none unless two targets
  index.depthStencil.texture = targets_->attachment(kSceneDepth);
  index.depthStencil.load = rhi::LoadOp::Load;
  index.label = "light index";
  device.beginPass(index);
  std::vector<uint32_t> drawn(all.begin(), all.begin() + indexed);
  auto plainIndex = [](uint32_t sceneLight) {
    scene::GpuMaterial m{};
    // The same index in every channel; the pipeline's write mask picks the array's channel.
    m.diffuse = glm::vec4(byteToUnorm(static_cast<uint8_t>(sceneLight + 1)));
    return m;
  };
  switch (packing_) {
    case LidrPacking::Sort: {
      sort_ = sortLightsIntoChannels(s.lights, tableLights);
      for (uint32_t c = 0; c < 4; ++c) {
        std::vector<scene::GpuMaterial> outputs;
        for (uint32_t l : sort_.channels[c]) outputs.push_back(plainIndex(l));
        drawVolumes(device, scene, camera, indexPipelines_[c], volumeBindings, sort_.channels[c], outputs);
      }
      break;
    }
    case LidrPacking::Max: {
      sort_ = {};
      std::vector<scene::GpuMaterial> outputs;
      for (uint32_t l : drawn) {
        // (index, 1 - index) as bytes: 255 - index is exact where 1 - index / 255 might round.
        scene::GpuMaterial m{};
        float v = byteToUnorm(static_cast<uint8_t>(l + 1)), inv = byteToUnorm(static_cast<uint8_t>(254 - l));
        m.diffuse = glm::vec4(v, inv, v, inv);
        outputs.push_back(m);
      }
      device.setStencilReference(2);
      drawVolumes(device, scene, camera, indexPipelines_[0], volumeBindings, drawn, outputs);
      device.setStencilReference(0);
      drawVolumes(device, scene, camera, indexPipelines_[1], volumeBindings, drawn, outputs);
      break;
    }
    case LidrPacking::Bits: {
      sort_ = {};
      std::vector<scene::GpuMaterial> outputs;
      for (uint32_t l : drawn) {
        ChannelBytes chunks = bitPackingChunks(layout_, l + 1);
        scene::GpuMaterial m{};
        m.diffuse = glm::vec4(byteToUnorm(chunks[0]), byteToUnorm(chunks[1]), byteToUnorm(chunks[2]), byteToUnorm(chunks[3]));
        m.specular = glm::vec4(byteToUnorm(chunks[4]), byteToUnorm(chunks[5]), byteToUnorm(chunks[6]), byteToUnorm(chunks[7]));
        outputs.push_back(m);
      }
      float k = layout_.blendConstant();
      device.setBlendConstant({k, k, k, k});
      device.setStencilReference(static_cast<uint8_t>(layout_.overlaps()));
      drawVolumes(device, scene, camera, indexPipelines_[0], volumeBindings, drawn, outputs);
      break;
    }
  }
  device.endPass();
  // On x360 out of EDRAM into the textures the forward pass reads (a bit copy of k_8_8_8_8).
  targets_->resolve(kLightIndex);
  if (targets_->attachment(kLightIndex2)) targets_->resolve(kLightIndex2);

  // 4. Forward pass over the light tables.
  rhi::PassDesc forward;
  forward.colors[0].texture = targets_->attachment(kOutputColor);
  forward.colors[0].clearColor = {0.0f, 0.0f, 0.0f, 1.0f};
  forward.colors[1].texture = targets_->attachment(kDropped);
  forward.depthStencil.texture = targets_->attachment(msaa() ? kMsaaDepth : kSceneDepth);
  forward.depthStencil.load = rhi::LoadOp::Load;
  forward.label = "forward";
  device.beginPass(forward);
  device.setPipeline(shadePipeline_);
  std::vector<rhi::ResourceBinding> tables;
  auto sampled = [&](uint32_t binding, rhi::TextureHandle t) {
    rhi::ResourceBinding b;
    b.binding = binding;
    b.kind = rhi::BindingKind::SampledTexture;
    b.texture = t;
    tables.push_back(b);
  };
  sampled(3, targets_->readTexture(kLightIndex));
  if (targets_->attachment(kLightIndex2)) sampled(4, targets_->readTexture(kLightIndex2));
  sampled(5, lightColors_);
  sampled(6, lightData_);
  sampled(7, targets_->readTexture(kOverlapCount));
  device.setBindings(tables);
  std::vector<size_t> translucent;
  for (size_t m = 0; m < s.meshes.size(); ++m) {
    if (msaa() && opacityOf(s, s.meshes[m].material) < 1.0f)
      translucent.push_back(m);
    else
      scene.drawMesh(s.meshes[m], tableRow(m));  // flags.y: the mesh's light table row
  }
  if (!translucent.empty()) {
    // Back to front by the distance of the bounds' centres.
    auto distance = [&](size_t m) {
      glm::vec3 centre = 0.5f * (s.meshes[m].boundsMin + s.meshes[m].boundsMax);
      return glm::length(centre - camera.position);
    };
    std::stable_sort(translucent.begin(), translucent.end(), [&](size_t a, size_t b) { return distance(a) > distance(b); });
    device.setPipeline(translucentPipeline_);
    device.setBindings(tables);
    for (size_t m : translucent) {
      float opacity = opacityOf(s, s.meshes[m].material);
      device.setBlendConstant({opacity, opacity, opacity, opacity});
      scene.drawMesh(s.meshes[m], tableRow(m));
    }
  }
  device.endPass();
  targets_->resolve(kDropped);  // multisampled: the samples' total (see LIDR_DROPPED_SCALE)
  return targets_->present();
}

uint64_t LightIndexedDeferred::pixelsThatLostLight(rhi::Device& device) const {
  // The resolved count in the red of RGBA8 texels, on every platform.
  const std::vector<uint8_t> texels = device.readTexture(targets_->readTexture(kDropped));
  uint64_t lost = 0;
  for (size_t i = 0; i + 4 <= texels.size(); i += 4) lost += texels[i] != 0;
  return lost;
}

void LightIndexedDeferred::release(rhi::Device& device) {
  releaseFrameResources(device);
  auto destroyPair = [&](const VolumePipelines& pair) {
    if (pair[0]) device.destroy(pair[0]);
    if (pair[1] && pair[1].id != pair[0].id) device.destroy(pair[1]);
  };
  for (const VolumePipelines& pair : indexPipelines_) destroyPair(pair);
  indexPipelines_.clear();
  destroyPair(countPipeline_);
  countPipeline_ = {};
  for (rhi::PipelineHandle p : {prepassPipeline_, shadePipeline_, farthestPipeline_, translucentPipeline_})
    if (p) device.destroy(p);
  farthestPipeline_ = translucentPipeline_ = {};
  targets_.reset();
  volumes_.reset();
  shaders_.reset();
}

}  // namespace parity::techniques
