// GL backend: device creation, description, the API conventions (normalised here, once), debug
// output and submission.
#include "rhi/gl/gl_device.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <utility>

#include "rhi/backends.h"

namespace parity::rhi {

std::unique_ptr<Device> createGlDevice(const DeviceDesc& desc, std::string* whyNot) {
  std::string reason;
  std::unique_ptr<Device> device = gl::GlDevice::create(desc, &reason);
  if (!device && whyNot) *whyNot = reason;
  return device;
}

}  // namespace parity::rhi

namespace parity::rhi::gl {

namespace {

std::string glString(const GlFunctions& gl, GLenum name) {
  const GLubyte* s = gl.GetString(name);
  return s ? reinterpret_cast<const char*>(s) : "";
}

const char* debugTypeName(GLenum type) {
  switch (type) {
    case GL_DEBUG_TYPE_ERROR: return "error";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR: return "undefined behaviour";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR: return "deprecated behaviour";
    case GL_DEBUG_TYPE_PORTABILITY: return "portability";
    default: return "other";
  }
}

const char* debugSeverityName(GLenum severity) {
  switch (severity) {
    case GL_DEBUG_SEVERITY_HIGH: return "high";
    case GL_DEBUG_SEVERITY_MEDIUM: return "medium";
    case GL_DEBUG_SEVERITY_LOW: return "low";
    default: return "notification";
  }
}

void APIENTRY onDebugMessage(GLenum /*source*/, GLenum type, GLuint id, GLenum severity, GLsizei length,
                               const GLchar* message, const void* userParam) {
  if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
  if (type != GL_DEBUG_TYPE_ERROR && type != GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR &&
      type != GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR && type != GL_DEBUG_TYPE_PORTABILITY)
    return;
  const auto* log = static_cast<const std::function<void(const std::string&)>*>(userParam);
  std::string text = std::string("GL debug (") + debugTypeName(type) + ", " + debugSeverityName(severity) +
                     ", id " + std::to_string(id) + "): " +
                     (length >= 0 ? std::string(message, static_cast<size_t>(length)) : std::string(message));
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  (*log)(text);
}

void* getProc(const char* name, void* userData) { return static_cast<GlContext*>(userData)->getProcAddress(name); }

}  // namespace

std::unique_ptr<Device> GlDevice::create(const DeviceDesc& desc, std::string* whyNot) {
  std::unique_ptr<GlDevice> device(new GlDevice());
  if (!device->initialise(desc, whyNot)) return nullptr;
  return device;
}

void GlDevice::listShaderFeatures() {
  GLint count = 0;
  gl.GetIntegerv(GL_NUM_EXTENSIONS, &count);
  std::set<std::string> glExtensions;
  for (GLint i = 0; i < count; ++i)
    if (const GLubyte* e = gl.GetStringi(GL_EXTENSIONS, static_cast<GLuint>(i))) glExtensions.insert(reinterpret_cast<const char*>(e));
  // Core in OpenGL 4.5 (the version this device requires).
  info_.features = {"fullDrawIndexUint32", "imageCubeArray", "independentBlend", "geometryShader", "tessellationShader",
                    "sampleRateShading", "dualSrcBlend", "logicOp", "multiDrawIndirect", "drawIndirectFirstInstance",
                    "depthClamp", "provokingVertexLast", "fillModeNonSolid", "largePoints", "multiViewport", "occlusionQueryPrecise",
                    "vertexPipelineStoresAndAtomics", "fragmentStoresAndAtomics", "shaderTessellationAndGeometryPointSize",
                    "shaderImageGatherExtended", "shaderStorageImageExtendedFormats", "shaderStorageImageMultisample",
                    "shaderStorageImageWriteWithoutFormat", "shaderUniformBufferArrayDynamicIndexing",
                    "shaderSampledImageArrayDynamicIndexing", "shaderStorageBufferArrayDynamicIndexing",
                    "shaderStorageImageArrayDynamicIndexing", "shaderClipDistance", "shaderCullDistance", "shaderFloat64",
                    // GLSL's discard ends the invocation, as OpTerminateInvocation does.
                    "shaderTerminateInvocation",
                    // ShaderDesc::openGlGlsl: the driver compiles OpenGL GLSL itself.
                    "openGlGlsl"};
  // OpenGL's primitive restart (core since 3.1) applies to every topology, lists and patches as
  // well: what VK_EXT_primitive_topology_list_restart adds to Vulkan.
  info_.extensions = {"VK_KHR_storage_buffer_storage_class", "VK_KHR_shader_terminate_invocation",
                      "VK_EXT_primitive_topology_list_restart"};
  info_.caps.subgroups = glExtensions.count("GL_KHR_shader_subgroup") > 0;  // SPIRV-Cross's only GLSL form
  // Through an extension of this context.
  const std::pair<const char*, const char*> kByExtension[] = {
      {"GL_ARB_gpu_shader_int64", "shaderInt64"},
      {"GL_EXT_shader_image_load_formatted", "shaderStorageImageReadWithoutFormat"},
      {"GL_ARB_shader_draw_parameters", "shaderDrawParameters"},
      {"GL_EXT_demote_to_helper_invocation", "shaderDemoteToHelperInvocation"},
      {"GL_ARB_polygon_offset_clamp", "depthBiasClamp"}};
  for (const auto& [extension, feature] : kByExtension)
    if (glExtensions.count(extension)) info_.features.push_back(feature);
  if (glExtensions.count("GL_ARB_polygon_offset_clamp"))
    polygonOffsetClamp_ = reinterpret_cast<PFNGLPOLYGONOFFSETCLAMPPROC>(context_->getProcAddress("glPolygonOffsetClamp"));
  info_.openGlExtensions.assign(glExtensions.begin(), glExtensions.end());
  // ShaderDesc::arbProgram: the driver loads ARB assembly programs (compatibility contexts).
  if (loadArbProgramFunctions()) info_.features.push_back("arbAssemblyPrograms");
  if (glExtensions.count("GL_ARB_gpu_shader_int64"))
    for (int n = 1; n <= 4; ++n) {
      const std::string i = "glProgramUniform" + std::to_string(n) + "i64vARB", u = "glProgramUniform" + std::to_string(n) + "ui64vARB";
      programUniformI64_[n - 1] = reinterpret_cast<PFNGLPROGRAMUNIFORM1I64VARBPROC>(context_->getProcAddress(i.c_str()));
      programUniformUI64_[n - 1] = reinterpret_cast<PFNGLPROGRAMUNIFORM1UI64VARBPROC>(context_->getProcAddress(u.c_str()));
    }
  if (glExtensions.count("GL_ARB_gl_spirv"))
    specializeShader_ = reinterpret_cast<PFNGLSPECIALIZESHADERARBPROC>(context_->getProcAddress("glSpecializeShaderARB"));
  if (glExtensions.count("GL_ARB_shader_draw_parameters")) info_.extensions.push_back("VK_KHR_shader_draw_parameters");
  if (glExtensions.count("GL_EXT_demote_to_helper_invocation")) info_.extensions.push_back("VK_EXT_shader_demote_to_helper_invocation");
}

bool GlDevice::initialise(const DeviceDesc& desc, std::string* whyNot) {
  log_ = desc.log;
  if (!log_) log_ = [](const std::string& m) { std::fprintf(stderr, "parity: gl: %s\n", m.c_str()); };

  if (!desc.adapter.empty()) {
    // Read by Mesa's loader when the first display of the process is initialised.
    ::setenv("GALLIUM_DRIVER", desc.adapter.c_str(), 1);
    ::setenv("LIBGL_ALWAYS_SOFTWARE", "1", 1);  // the software loader, where llvmpipe and zink live
  }
  context_ = createGlContext(desc.glContextProvider, desc.debug, desc.glCompatibilityProfile, whyNot);
  if (!context_) {
    if (!desc.adapter.empty()) *whyNot = "GL driver '" + desc.adapter + "': " + *whyNot;
    return false;
  }
  const std::string provider = context_->providerName();
  const std::string prefix = provider == "egl" ? "EGL: " : "OSMesa: ";

  std::string missing;
  if (!loadGlFunctions(&gl, getProc, context_.get(), &missing)) {
    *whyNot = prefix + "OpenGL entry points missing: " + missing;
    context_.reset();
    return false;
  }
  GLint major = 0, minor = 0, profile = 0;
  gl.GetIntegerv(GL_MAJOR_VERSION, &major);
  gl.GetIntegerv(GL_MINOR_VERSION, &minor);
  gl.GetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  const std::string version = glString(gl, GL_VERSION);
  const GLint wanted = desc.glCompatibilityProfile ? GL_CONTEXT_COMPATIBILITY_PROFILE_BIT : GL_CONTEXT_CORE_PROFILE_BIT;
  if (major < 4 || (major == 4 && minor < 5) || !(profile & wanted)) {
    *whyNot = prefix + "context is '" + version + "', not OpenGL 4.5 " + (desc.glCompatibilityProfile ? "compatibility" : "core");
    context_.reset();
    return false;
  }

  info_.backend = "gl";
  info_.api = "OpenGL " + version;
  info_.renderer = glString(gl, GL_RENDERER);
  // "4.5 (Core Profile) Mesa 22.3.6" -> "Mesa 22.3.6"; other drivers: the vendor string.
  const size_t mesa = version.find("Mesa ");
  info_.driver = mesa != std::string::npos ? version.substr(mesa) : glString(gl, GL_VENDOR);
  info_.contextProvider = provider;
  if (!desc.adapter.empty() && info_.renderer.rfind(desc.adapter, 0) != 0) {
    *whyNot = prefix + "GL driver '" + desc.adapter + "' asked for, the context's renderer is '" + info_.renderer +
              "' (the driver is missing, or another GL driver was loaded in this process first)";
    context_.reset();
    return false;
  }

  GLint maxSamples = 0, maxColorSamples = 0, maxDepthSamples = 0, timestampBits = 0;
  gl.GetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  gl.GetIntegerv(GL_MAX_COLOR_TEXTURE_SAMPLES, &maxColorSamples);
  gl.GetIntegerv(GL_MAX_DEPTH_TEXTURE_SAMPLES, &maxDepthSamples);
  gl.GetQueryiv(GL_TIMESTAMP, GL_QUERY_COUNTER_BITS, &timestampBits);
  gl.GetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &maxTextureUnits_);
  GLint maxImageSamples = 0;
  gl.GetIntegerv(GL_MAX_IMAGE_SAMPLES, &maxImageSamples);
  info_.caps.storageMultisample = maxImageSamples >= 4;
  info_.caps.doubleVertexFormats = true;  // glVertexAttribLFormat, core since OpenGL 4.1
  const bool msaa4 = maxSamples >= 4 && maxColorSamples >= 4 && maxDepthSamples >= 4;
  info_.caps.maxSamples = msaa4 ? 4 : 1;  // rhi textures have 1 or 4 samples
  info_.caps.textureViews = true;         // core since 4.3
  info_.caps.compute = true;              // core since 4.3
  info_.caps.timestamps = timestampBits > 0;
  info_.caps.independentBlend = true;     // core since 4.0
  info_.caps.separateSamplerArrays = false;  // SPIRV-Cross combines no sampler arrays into GLSL
  GLint maxViewports = 1;
  gl.GetIntegerv(GL_MAX_VIEWPORTS, &maxViewports);
  info_.caps.viewports = static_cast<uint32_t>(std::clamp<GLint>(maxViewports, 1, static_cast<GLint>(kMaxViewports)));
  GLfloat maxLodBias = 2.0f;
  gl.GetFloatv(GL_MAX_TEXTURE_LOD_BIAS, &maxLodBias);
  info_.caps.maxSamplerLodBias = maxLodBias;
  const std::pair<ShaderStage, GLenum> kOutputComponents[] = {
      {ShaderStage::Vertex, GL_MAX_VERTEX_OUTPUT_COMPONENTS},
      {ShaderStage::Geometry, GL_MAX_GEOMETRY_OUTPUT_COMPONENTS},
      {ShaderStage::TessControl, GL_MAX_TESS_CONTROL_OUTPUT_COMPONENTS},
      {ShaderStage::TessEvaluation, GL_MAX_TESS_EVALUATION_OUTPUT_COMPONENTS}};
  for (const auto& [stage, limit] : kOutputComponents) {
    GLint components = 0;
    gl.GetIntegerv(limit, &components);
    info_.caps.maxOutputLocations[size_t(stage)] = static_cast<uint32_t>(components) / 4;
  }
  listShaderFeatures();

  if (desc.debug) installDebugOutput();
  setConventions();

  // Bound with sampled textures that come without a sampler (rhi: nearest, clamp to edge).
  gl.CreateSamplers(1, &defaultSampler_);
  gl.SamplerParameteri(defaultSampler_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.SamplerParameteri(defaultSampler_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl.SamplerParameteri(defaultSampler_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.SamplerParameteri(defaultSampler_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl.SamplerParameteri(defaultSampler_, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  gl.CreateSamplers(1, &defaultShadowSampler_);
  for (GLenum p : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER}) gl.SamplerParameteri(defaultShadowSampler_, p, GL_NEAREST);
  for (GLenum p : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    gl.SamplerParameteri(defaultShadowSampler_, p, GL_CLAMP_TO_EDGE);
  gl.SamplerParameteri(defaultShadowSampler_, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  gl.SamplerParameteri(defaultShadowSampler_, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);

  GLint uniformAlignment = 1, storageAlignment = 1;
  gl.GetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &uniformAlignment);
  gl.GetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &storageAlignment);
  const size_t alignment = static_cast<size_t>(std::max({uniformAlignment, storageAlignment, GLint(1)}));
  pushConstantSlotBytes_ = (kMaxPushConstantBytes + alignment - 1) / alignment * alignment;
  const GLbitfield persistent = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
  gl.CreateBuffers(1, &pushConstantBuffer_);
  gl.NamedBufferStorage(pushConstantBuffer_, kPushConstantRingBytes, nullptr, persistent);
  pushConstantRing_ = static_cast<uint8_t*>(gl.MapNamedBufferRange(pushConstantBuffer_, 0, kPushConstantRingBytes, persistent));
  if (!pushConstantRing_) {
    if (whyNot) *whyNot = "cannot map the push-constant buffer persistently";
    return false;
  }
  label(GL_BUFFER, pushConstantBuffer_, "push constants");
  return true;
}

// Every convention difference between GL and Vulkan that rhi.h fixes is normalised here or
// noted here with the place that handles it.
void GlDevice::setConventions() {
  // Clip space. GL_LOWER_LEFT maps NDC y = -1 to window y = 0, which for a framebuffer object
  // is memory row 0 -- exactly where Vulkan puts NDC y = -1. GL_ZERO_TO_ONE gives Vulkan's [0, 1]
  // depth range. With this, gl_FragCoord, rasterisation tie rules, texture coordinate t = 0 and
  // readback row order all match Vulkan (GL_UPPER_LEFT would flip ties on horizontal edges).
  // Consequences handled elsewhere:
  //  * viewport and scissor y pass through unchanged (y counted from row 0 = window y 0);
  //  * front face is inverted (GL decides winding with y up, i.e. in the image flipped
  //    vertically), see applyRenderState() in gl_commands.cpp.
  gl.ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  // gl_PointCoord: Vulkan has t = 0 on the point's side nearest row 0. GL measures from the
  // "upper" edge in window coordinates (y up), which is the side away from row 0, unless told
  // the origin is lower left.
  gl.PointParameteri(GL_POINT_SPRITE_COORD_ORIGIN, GL_LOWER_LEFT);
  // Point size comes from gl_PointSize, as in Vulkan (GL would use glPointSize otherwise).
  gl.Enable(GL_PROGRAM_POINT_SIZE);
  // Flat-shaded attributes come from the first vertex in Vulkan, the last by default in GL.
  gl.ProvokingVertex(GL_FIRST_VERTEX_CONVENTION);
  // Vulkan always encodes to (and blends in linear for) sRGB attachments; GL only when this is
  // on. It only affects sRGB attachments, so it stays on.
  gl.Enable(GL_FRAMEBUFFER_SRGB);
  // Vulkan cube maps always filter across faces.
  gl.Enable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
  // Vulkan does not dither; GL enables it by default.
  gl.Disable(GL_DITHER);
  // Vulkan pipelines here never enable primitive restart.
  gl.Disable(GL_PRIMITIVE_RESTART);
  gl.Disable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
  // Multisample rasterisation on MSAA attachments, as in Vulkan.
  gl.Enable(GL_MULTISAMPLE);
  // Texel transfers are tightly packed in rhi (GL pads rows to 4 bytes by default).
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  // A compatibility context sizes points and fills gl_PointCoord only with point sprites on,
  // which a core context always has.
  GLint profile = 0;
  gl.GetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  constexpr GLenum kPointSprite = 0x8861;  // GL_POINT_SPRITE, not in the core header
  if (profile & GL_CONTEXT_COMPATIBILITY_PROFILE_BIT) gl.Enable(kPointSprite);
}

void GlDevice::installDebugOutput() {
  gl.Enable(GL_DEBUG_OUTPUT);
  // Synchronous: the message arrives inside the offending call, so the stack points at it.
  gl.Enable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  gl.DebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
  gl.DebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr, GL_FALSE);
  gl.DebugMessageCallback(onDebugMessage, &log_);
}

void GlDevice::log(const std::string& message) const { log_(message); }

void GlDevice::label(GLenum identifier, GLuint name, const std::string& text) {
  if (!text.empty() && name != 0) gl.ObjectLabel(identifier, name, static_cast<GLsizei>(text.size()), text.c_str());
}

GlDevice::~GlDevice() {
  if (!context_) return;
  context_->makeCurrent();
  computePipelines_.forEach([&](GlComputePipeline& p) { gl.DeleteProgram(p.program.name); });
  pipelines_.forEach([&](GlPipeline& p) {
    gl.DeleteProgram(p.program.name);
    gl.DeleteVertexArrays(1, &p.vao);
  });
  shaders_.forEach([&](GlShader& s) {
    if (s.name != 0) gl.DeleteShader(s.name);
    if (s.spirvName != 0) gl.DeleteShader(s.spirvName);
  });
  samplers_.forEach([&](GlSampler& s) { gl.DeleteSamplers(1, &s.name); });
  for (auto& [key, fbo] : framebuffers_) gl.DeleteFramebuffers(1, &fbo);
  textures_.forEach([&](std::unique_ptr<GlTexture>& t) { deleteTextureObjects(*t); });
  buffers_.forEach([&](std::unique_ptr<GlBuffer>& b) {
    for (const GlTexelView& v : b->texelViews) gl.DeleteTextures(1, &v.name);
    gl.DeleteBuffers(1, &b->name);
  });
  if (!timestampQueries_.empty())
    gl.DeleteQueries(static_cast<GLsizei>(timestampQueries_.size()), timestampQueries_.data());
  gl.DeleteSamplers(1, &defaultSampler_);
  gl.DeleteSamplers(1, &defaultShadowSampler_);
  if (pushConstantRing_) gl.UnmapNamedBuffer(pushConstantBuffer_);
  gl.DeleteBuffers(1, &pushConstantBuffer_);
  if (sequentialIndices_ != 0) gl.DeleteBuffers(1, &sequentialIndices_);
  gl.Finish();
  gl.DebugMessageCallback(nullptr, nullptr);
  context_.reset();
}

void GlDevice::submit() {
  gl.Finish();
  pushConstantNext_ = 0;  // every draw that read the ring has finished
}

}  // namespace parity::rhi::gl
