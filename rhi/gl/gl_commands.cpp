// GL backend: commands. Passes render to cached framebuffer objects; draws apply the pipeline's
// whole fixed-function state, the vertex input, the bindings and the push constants; every
// pass and dispatch ends with a full memory barrier (the Vulkan backend uses global barriers
// at the same points).
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>

#include "rhi/gl/gl_device.h"

namespace parity::rhi::gl {

namespace {

uint32_t mipExtent(uint32_t size, uint32_t mip) { return std::max(1u, size >> mip); }

GLenum glCompareOp(CompareOp op) {
  switch (op) {
    case CompareOp::Always: return GL_ALWAYS;
    case CompareOp::Never: return GL_NEVER;
    case CompareOp::Less: return GL_LESS;
    case CompareOp::LessEqual: return GL_LEQUAL;
    case CompareOp::Equal: return GL_EQUAL;
    case CompareOp::NotEqual: return GL_NOTEQUAL;
    case CompareOp::Greater: return GL_GREATER;
    case CompareOp::GreaterEqual: return GL_GEQUAL;
  }
  return GL_ALWAYS;
}

GLenum glStencilOp(StencilOp op) {
  switch (op) {
    case StencilOp::Keep: return GL_KEEP;
    case StencilOp::Zero: return GL_ZERO;
    case StencilOp::Replace: return GL_REPLACE;
    case StencilOp::IncrementClamp: return GL_INCR;
    case StencilOp::DecrementClamp: return GL_DECR;
    case StencilOp::Invert: return GL_INVERT;
    case StencilOp::IncrementWrap: return GL_INCR_WRAP;
    case StencilOp::DecrementWrap: return GL_DECR_WRAP;
  }
  return GL_KEEP;
}

GLenum glBlendFactor(BlendFactor f) {
  switch (f) {
    case BlendFactor::One: return GL_ONE;
    case BlendFactor::Zero: return GL_ZERO;
    case BlendFactor::SrcColor: return GL_SRC_COLOR;
    case BlendFactor::OneMinusSrcColor: return GL_ONE_MINUS_SRC_COLOR;
    case BlendFactor::DstColor: return GL_DST_COLOR;
    case BlendFactor::OneMinusDstColor: return GL_ONE_MINUS_DST_COLOR;
    case BlendFactor::SrcAlpha: return GL_SRC_ALPHA;
    case BlendFactor::OneMinusSrcAlpha: return GL_ONE_MINUS_SRC_ALPHA;
    case BlendFactor::DstAlpha: return GL_DST_ALPHA;
    case BlendFactor::OneMinusDstAlpha: return GL_ONE_MINUS_DST_ALPHA;
    case BlendFactor::ConstantColor: return GL_CONSTANT_COLOR;
    case BlendFactor::OneMinusConstantColor: return GL_ONE_MINUS_CONSTANT_COLOR;
  }
  return GL_ONE;
}

GLenum glBlendOp(BlendOp op) {
  switch (op) {
    case BlendOp::Add: return GL_FUNC_ADD;
    case BlendOp::Subtract: return GL_FUNC_SUBTRACT;
    case BlendOp::ReverseSubtract: return GL_FUNC_REVERSE_SUBTRACT;
    case BlendOp::Min: return GL_MIN;
    case BlendOp::Max: return GL_MAX;
  }
  return GL_FUNC_ADD;
}

GLenum glTopology(PrimitiveTopology t) {
  switch (t) {
    case PrimitiveTopology::Triangles: return GL_TRIANGLES;
    case PrimitiveTopology::TriangleStrip: return GL_TRIANGLE_STRIP;
    case PrimitiveTopology::Lines: return GL_LINES;
    case PrimitiveTopology::Points: return GL_POINTS;
    case PrimitiveTopology::LineStrip: return GL_LINE_STRIP;
    case PrimitiveTopology::Patches: return GL_PATCHES;
    case PrimitiveTopology::LinesWithAdjacency: return GL_LINES_ADJACENCY;
    case PrimitiveTopology::LineStripWithAdjacency: return GL_LINE_STRIP_ADJACENCY;
    case PrimitiveTopology::TrianglesWithAdjacency: return GL_TRIANGLES_ADJACENCY;
    case PrimitiveTopology::TriangleStripWithAdjacency: return GL_TRIANGLE_STRIP_ADJACENCY;
  }
  return GL_TRIANGLES;
}

GLenum glPolygonMode(PolygonMode m) {
  switch (m) {
    case PolygonMode::Fill: return GL_FILL;
    case PolygonMode::Line: return GL_LINE;
    case PolygonMode::Point: return GL_POINT;
  }
  return GL_FILL;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Framebuffers
// ---------------------------------------------------------------------------------------------
void GlDevice::attach(GLuint fbo, GLenum attachment, const GlTexture& texture, uint32_t layer, uint32_t mip) {
  if (texture.target == GL_TEXTURE_2D || texture.target == GL_TEXTURE_2D_MULTISAMPLE || texture.target == GL_TEXTURE_1D)
    gl.NamedFramebufferTexture(fbo, attachment, texture.name, static_cast<GLint>(mip));
  else  // array layer, cube face or 3D slice
    gl.NamedFramebufferTextureLayer(fbo, attachment, texture.name, static_cast<GLint>(mip), static_cast<GLint>(layer));
}

GLuint GlDevice::framebuffer(const FramebufferKey& key) {
  auto it = framebuffers_.find(key);
  if (it != framebuffers_.end()) return it->second;
  GLuint fbo = 0;
  gl.CreateFramebuffers(1, &fbo);
  std::array<GLenum, kMaxColorTargets> drawBuffers{};
  for (uint32_t i = 0; i < kMaxColorTargets; ++i) {
    drawBuffers[i] = GL_NONE;
    std::unique_ptr<GlTexture>* t = textures_.get(TextureHandle{key[3 * i]});
    if (!t) continue;
    attach(fbo, GL_COLOR_ATTACHMENT0 + i, **t, key[3 * i + 1], key[3 * i + 2]);
    drawBuffers[i] = GL_COLOR_ATTACHMENT0 + i;  // fragment output location i -> attachment i
  }
  if (std::unique_ptr<GlTexture>* t = textures_.get(TextureHandle{key[3 * kMaxColorTargets]})) {
    const GLenum attachment = hasStencil((*t)->desc.format) ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT;
    attach(fbo, attachment, **t, key[3 * kMaxColorTargets + 1], key[3 * kMaxColorTargets + 2]);
  }
  gl.NamedFramebufferDrawBuffers(fbo, kMaxColorTargets, drawBuffers.data());
  gl.NamedFramebufferReadBuffer(fbo, drawBuffers[0]);
  const GLenum status = gl.CheckNamedFramebufferStatus(fbo, GL_DRAW_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%04X", status);
    log(std::string("framebuffer incomplete (status ") + hex + ")");
  }
  framebuffers_.emplace(key, fbo);
  return fbo;
}

void GlDevice::forgetFramebuffersOf(TextureHandle texture) {
  for (auto it = framebuffers_.begin(); it != framebuffers_.end();) {
    bool uses = false;
    for (uint32_t i = 0; i <= kMaxColorTargets; ++i) uses |= it->first[3 * i] == texture.id;
    if (uses) {
      if (passFramebuffer_ == it->second) passFramebuffer_ = 0;
      gl.DeleteFramebuffers(1, &it->second);
      it = framebuffers_.erase(it);
    } else {
      ++it;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Passes
// ---------------------------------------------------------------------------------------------
void GlDevice::beginPass(const PassDesc& desc) {
  pass_ = desc;
  inPass_ = true;
  passWidth_ = passHeight_ = 0;
  FramebufferKey key{};
  for (uint32_t i = 0; i < kMaxColorTargets; ++i) {
    const ColorAttachment& c = desc.colors[i];
    std::unique_ptr<GlTexture>* t = textures_.get(c.texture);
    if (!t) continue;
    key[3 * i] = c.texture.id, key[3 * i + 1] = c.layer, key[3 * i + 2] = c.mip;
    if (passWidth_ == 0) {
      passWidth_ = mipExtent((*t)->desc.width, c.mip);
      passHeight_ = mipExtent((*t)->desc.height, c.mip);
    }
  }
  if (std::unique_ptr<GlTexture>* t = textures_.get(desc.depthStencil.texture)) {
    key[3 * kMaxColorTargets] = desc.depthStencil.texture.id;
    key[3 * kMaxColorTargets + 1] = desc.depthStencil.layer;
    if (passWidth_ == 0) passWidth_ = (*t)->desc.width, passHeight_ = (*t)->desc.height;
  }
  passFramebuffer_ = framebuffer(key);
  gl.BindFramebuffer(GL_FRAMEBUFFER, passFramebuffer_);
  if (!desc.label.empty())
    gl.PushDebugGroup(GL_DEBUG_SOURCE_APPLICATION, 0, static_cast<GLsizei>(desc.label.size()), desc.label.c_str());

  // Load-op clears. GL clears obey the write masks and the scissor test, Vulkan load-op clears
  // do not: open them up here; the next draw applies its pipeline's state again anyway.
  gl.Disable(GL_SCISSOR_TEST);
  for (uint32_t i = 0; i < kMaxColorTargets; ++i) {
    const ColorAttachment& c = desc.colors[i];
    std::unique_ptr<GlTexture>* t = textures_.get(c.texture);
    if (!t || c.load != LoadOp::Clear) continue;
    gl.ColorMaski(i, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    const auto drawBuffer = static_cast<GLint>(i);
    switch (formatInfo((*t)->desc.format).kind) {
      case FormatKind::Uint: {
        const GLuint v[4] = {static_cast<GLuint>(c.clearColor[0]), static_cast<GLuint>(c.clearColor[1]),
                             static_cast<GLuint>(c.clearColor[2]), static_cast<GLuint>(c.clearColor[3])};
        gl.ClearNamedFramebufferuiv(passFramebuffer_, GL_COLOR, drawBuffer, v);
        break;
      }
      case FormatKind::Sint: {
        const GLint v[4] = {static_cast<GLint>(c.clearColor[0]), static_cast<GLint>(c.clearColor[1]),
                            static_cast<GLint>(c.clearColor[2]), static_cast<GLint>(c.clearColor[3])};
        gl.ClearNamedFramebufferiv(passFramebuffer_, GL_COLOR, drawBuffer, v);
        break;
      }
      default:
        // sRGB targets: the linear clear colour is encoded (GL_FRAMEBUFFER_SRGB), as in Vulkan.
        gl.ClearNamedFramebufferfv(passFramebuffer_, GL_COLOR, drawBuffer, c.clearColor.data());
        break;
    }
  }
  const DepthStencilAttachment& ds = desc.depthStencil;
  if (std::unique_ptr<GlTexture>* t = textures_.get(ds.texture); t && ds.load == LoadOp::Clear) {
    gl.DepthMask(GL_TRUE);
    if (hasStencil((*t)->desc.format)) {
      gl.StencilMaskSeparate(GL_FRONT_AND_BACK, 0xFF);
      gl.ClearNamedFramebufferfi(passFramebuffer_, GL_DEPTH_STENCIL, 0, ds.clearDepth, ds.clearStencil);
    } else {
      gl.ClearNamedFramebufferfv(passFramebuffer_, GL_DEPTH, 0, &ds.clearDepth);
    }
  }
  viewport_ = Viewport{};
  scissor_ = Rect{0, 0, passWidth_, passHeight_};
}

void GlDevice::endPass() {
  if (!inPass_) return;
  // MSAA resolves. Blits obey the scissor test (only), so it is off; same size, so NEAREST
  // averages the samples.
  gl.Disable(GL_SCISSOR_TEST);
  for (uint32_t i = 0; i < kMaxColorTargets; ++i) {
    const ColorAttachment& c = pass_.colors[i];
    std::unique_ptr<GlTexture>* src = textures_.get(c.texture);
    std::unique_ptr<GlTexture>* dst = textures_.get(c.resolveTarget);
    if (!src || !dst || passFramebuffer_ == 0) continue;
    FramebufferKey key{};
    key[0] = c.resolveTarget.id;
    const GLuint resolveFbo = framebuffer(key);
    const auto w = static_cast<GLint>(passWidth_), h = static_cast<GLint>(passHeight_);
    gl.NamedFramebufferReadBuffer(passFramebuffer_, GL_COLOR_ATTACHMENT0 + i);
    gl.BlitNamedFramebuffer(passFramebuffer_, resolveFbo, 0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  if (passFramebuffer_ != 0)
    gl.NamedFramebufferReadBuffer(passFramebuffer_, textures_.get(pass_.colors[0].texture)
                                                        ? GL_COLOR_ATTACHMENT0
                                                        : GL_NONE);
  if (!pass_.label.empty()) gl.PopDebugGroup();
  gl.MemoryBarrier(GL_ALL_BARRIER_BITS);
  inPass_ = false;
}

// ---------------------------------------------------------------------------------------------
// Dynamic state
// ---------------------------------------------------------------------------------------------
void GlDevice::setPipeline(PipelineHandle h) {
  pipeline_ = h;
  viewport_ = Viewport{};
  scissor_ = Rect{0, 0, passWidth_, passHeight_};
}

void GlDevice::setViewport(const Viewport& vp) { viewport_ = vp; }
void GlDevice::setScissor(const Rect& r) { scissor_ = r; }
void GlDevice::setStencilReference(uint8_t ref) { stencilReference_ = ref; }
void GlDevice::setBlendConstant(const std::array<float, 4>& c) { blendConstant_ = c; }

void GlDevice::setVertexBuffer(uint32_t slot, BufferHandle h, size_t offset) {
  if (slot < kMaxVertexBuffers) vertexBuffers_[slot] = {h, offset};
}

void GlDevice::setIndexBuffer(BufferHandle h, IndexType type, size_t offset) {
  indexBuffer_ = h;
  indexType_ = type;
  indexOffset_ = offset;
}

void GlDevice::setBindings(std::span<const ResourceBinding> bindings) {
  // Each entry replaces what was bound at its (binding, element); the others stay.
  for (const ResourceBinding& b : bindings)
    if (b.binding < kMaxBindings && b.arrayElement < kMaxArrayElements) bindings_[b.binding][b.arrayElement] = b;
}

void GlDevice::pushConstants(const void* data, uint32_t size) {
  size = std::min<uint32_t>(size, kMaxPushConstantBytes);
  std::memcpy(pushConstantData_.data(), data, size);
  pushConstantsDirty_ = true;
}

// ---------------------------------------------------------------------------------------------
// State application
// ---------------------------------------------------------------------------------------------
void GlDevice::applyRenderState(const GlPipeline& pipeline) {
  const PipelineDesc& d = pipeline.desc;

  // Vulkan clips by every clip distance the shaders write; GL by those enabled (0..n-1 are).
  for (uint32_t i = pipeline.program.clipDistances; i < enabledClipDistances_; ++i) gl.Disable(GL_CLIP_DISTANCE0 + i);
  for (uint32_t i = enabledClipDistances_; i < pipeline.program.clipDistances; ++i) gl.Enable(GL_CLIP_DISTANCE0 + i);
  enabledClipDistances_ = pipeline.program.clipDistances;

  // Culling and winding. rhi's CounterClockwise is counter-clockwise in the saved image (row 0
  // at the top). GL decides winding in window coordinates with y up; with GL_LOWER_LEFT clip
  // control window y grows with the memory row, so GL sees the image flipped vertically and the
  // winding reversed: rhi CounterClockwise is GL_CW.
  if (d.raster.cull == CullMode::None) {
    gl.Disable(GL_CULL_FACE);
  } else {
    gl.Enable(GL_CULL_FACE);
    gl.CullFace(d.raster.cull == CullMode::Front ? GL_FRONT : GL_BACK);
  }
  gl.FrontFace(d.raster.frontFace == FrontFace::CounterClockwise ? GL_CW : GL_CCW);
  gl.PolygonMode(GL_FRONT_AND_BACK, glPolygonMode(d.raster.polygonMode));
  gl.ProvokingVertex(d.raster.provokingVertex == ProvokingVertex::Last ? GL_LAST_VERTEX_CONVENTION : GL_FIRST_VERTEX_CONVENTION);
  if (d.raster.depthClampEnabled)
    gl.Enable(GL_DEPTH_CLAMP);
  else
    gl.Disable(GL_DEPTH_CLAMP);
  applyDepthBias(d.raster.depthBias);

  // Viewport and scissor: y counted from memory row 0 in rhi and, with GL_LOWER_LEFT, from
  // window y 0 = row 0 in GL, so the rectangles pass through unchanged.
  const float vw = viewport_.width > 0 ? viewport_.width : static_cast<float>(passWidth_);
  const float vh = viewport_.height > 0 ? viewport_.height : static_cast<float>(passHeight_);
  // Every viewport index alike (Capabilities::viewports), as glViewport sets them.
  const GLsizei viewports = static_cast<GLsizei>(info_.caps.viewports);
  std::array<GLfloat, 4 * kMaxViewports> rects;
  std::array<GLdouble, 2 * kMaxViewports> ranges;
  std::array<GLint, 4 * kMaxViewports> scissors;
  for (GLsizei i = 0; i < viewports; ++i) {
    std::copy_n(std::array<GLfloat, 4>{viewport_.x, viewport_.y, vw, vh}.begin(), 4, rects.begin() + 4 * i);
    std::copy_n(std::array<GLdouble, 2>{viewport_.minDepth, viewport_.maxDepth}.begin(), 2, ranges.begin() + 2 * i);
    std::copy_n(std::array<GLint, 4>{scissor_.x, scissor_.y, static_cast<GLint>(scissor_.width), static_cast<GLint>(scissor_.height)}.begin(),
                4, scissors.begin() + 4 * i);
  }
  gl.ViewportArrayv(0, viewports, rects.data());
  gl.DepthRangeArrayv(0, viewports, ranges.data());
  if (d.raster.scissorEnabled) {
    gl.Enable(GL_SCISSOR_TEST);
    gl.ScissorArrayv(0, viewports, scissors.data());
  } else {
    gl.Disable(GL_SCISSOR_TEST);
  }

  // Depth. The default (Always, no write) is the same as no depth test.
  const DepthStencilState& ds = d.depthStencil;
  if (ds.depthCompare == CompareOp::Always && !ds.depthWrite) {
    gl.Disable(GL_DEPTH_TEST);
  } else {
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(glCompareOp(ds.depthCompare));
  }
  gl.DepthMask(ds.depthWrite ? GL_TRUE : GL_FALSE);

  // Stencil, two-sided. GL's front/back follow glFrontFace, which matches rhi's front above.
  if (ds.stencilEnabled) {
    gl.Enable(GL_STENCIL_TEST);
    const StencilFaceState* faces[2] = {&ds.front, &ds.back};
    const GLenum glFaces[2] = {GL_FRONT, GL_BACK};
    for (int f = 0; f < 2; ++f) {
      gl.StencilFuncSeparate(glFaces[f], glCompareOp(faces[f]->compare), stencilReference_, ds.stencilReadMask);
      gl.StencilOpSeparate(glFaces[f], glStencilOp(faces[f]->fail), glStencilOp(faces[f]->depthFail),
                           glStencilOp(faces[f]->pass));
    }
    gl.StencilMaskSeparate(GL_FRONT_AND_BACK, ds.stencilWriteMask);
  } else {
    gl.Disable(GL_STENCIL_TEST);
  }

  // Blending and write masks per colour target; targets the pipeline does not declare are not
  // written.
  for (uint32_t i = 0; i < kMaxColorTargets; ++i) {
    if (i >= d.colorTargetCount) {
      gl.Disablei(GL_BLEND, i);
      gl.ColorMaski(i, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
      continue;
    }
    const ColorTargetState& t = d.colorTargets[i];
    const uint8_t m = t.writeMask;
    gl.ColorMaski(i, (m & ColorMask_R) != 0, (m & ColorMask_G) != 0, (m & ColorMask_B) != 0, (m & ColorMask_A) != 0);
    if (t.blend.enabled) {
      gl.Enablei(GL_BLEND, i);
      gl.BlendFuncSeparatei(i, glBlendFactor(t.blend.srcColor), glBlendFactor(t.blend.dstColor),
                            glBlendFactor(t.blend.srcAlpha), glBlendFactor(t.blend.dstAlpha));
      gl.BlendEquationSeparatei(i, glBlendOp(t.blend.colorOp), glBlendOp(t.blend.alphaOp));
    } else {
      gl.Disablei(GL_BLEND, i);
    }
  }
  gl.BlendColor(blendConstant_[0], blendConstant_[1], blendConstant_[2], blendConstant_[3]);
}

// rhi's depth bias is Vulkan's (rhi.h), normalised here. GL's polygon offset is the same
// formula, factor * m + units * r, and GL 4.5 (14.6.5) defines r as Vulkan does, also for float
// depth (2^(e - 23)); Mesa gives both APIs the same r for D24S8 and D32F
// (tests/rhi_raster_state_test.cpp), so the factors pass through. Vulkan biases every polygon
// mode; GL has one enable per mode.
void GlDevice::applyDepthBias(const DepthBias& bias) {
  const bool enabled = bias.constantFactor != 0 || bias.slopeFactor != 0;
  for (GLenum mode : {GL_POLYGON_OFFSET_FILL, GL_POLYGON_OFFSET_LINE, GL_POLYGON_OFFSET_POINT}) {
    if (enabled)
      gl.Enable(mode);
    else
      gl.Disable(mode);
  }
  if (!enabled) return;
  if (polygonOffsetClamp_)
    polygonOffsetClamp_(bias.slopeFactor, bias.constantFactor, bias.clamp);
  else
    gl.PolygonOffset(bias.slopeFactor, bias.constantFactor);  // validation allows a clamp only with the extension
}

void GlDevice::applyVertexInput(const GlPipeline& pipeline) {
  gl.BindVertexArray(pipeline.vao);
  uint32_t usedSlots = 0;
  for (uint32_t a = 0; a < pipeline.desc.attributeCount; ++a) usedSlots |= 1u << pipeline.desc.attributes[a].bufferSlot;
  for (uint32_t slot = 0; slot < kMaxVertexBuffers; ++slot) {
    // A stride of 0 is a constant attribute on GL's vertex buffer bindings too (no "tightly
    // packed" meaning there, unlike glVertexAttribPointer's).
    const GLsizei stride = static_cast<GLsizei>(pipeline.desc.vertexBuffers[slot].stride);
    std::unique_ptr<GlBuffer>* b = buffers_.get(vertexBuffers_[slot].buffer);
    if (b && (usedSlots & (1u << slot)))
      gl.VertexArrayVertexBuffer(pipeline.vao, slot, (*b)->name, static_cast<GLintptr>(vertexBuffers_[slot].offset),
                                 stride);
    else
      gl.VertexArrayVertexBuffer(pipeline.vao, slot, 0, 0, 16);
  }
}

void GlDevice::applyBindings(const GlProgram& program) {
  for (const ShaderResource& r : program.resources)
    for (uint32_t element = 0; element < r.arraySize; ++element) {
      const std::optional<ResourceBinding>& b = bindings_[r.binding][element];
      const GLuint point = program.points[r.binding] + element;  // rhi.h's binding model (gl_pipeline.cpp)
      if (!b) continue;
      switch (b->kind) {
        case BindingKind::UniformBuffer:
        case BindingKind::StorageBuffer: {
          std::unique_ptr<GlBuffer>* buffer = buffers_.get(b->buffer);
          if (!buffer) break;
          const size_t size = b->size ? b->size : (*buffer)->desc.size - b->offset;
          gl.BindBufferRange(b->kind == BindingKind::UniformBuffer ? GL_UNIFORM_BUFFER : GL_SHADER_STORAGE_BUFFER,
                             point, (*buffer)->name, static_cast<GLintptr>(b->offset),
                             static_cast<GLsizeiptr>(size));
          break;
        }
        case BindingKind::SampledTexture: {
          std::unique_ptr<GlTexture>* texture = textures_.get(b->texture);
          if (!texture) break;
          gl.BindTextureUnit(point, samplingTexture(**texture, r));
          const GlSampler* sampler = samplers_.get(b->sampler);
          // The null sampler is nearest/clamp; for a shadow sampler it also compares (LessEqual),
          // as rhi.h documents and as the Vulkan backend's default does.
          gl.BindSampler(point, sampler ? sampler->name : r.depthCompare ? defaultShadowSampler_ : defaultSampler_);
          break;
        }
        case BindingKind::StorageTexture: {
          std::unique_ptr<GlTexture>* texture = textures_.get(b->texture);
          if (!texture) break;
          const GlTexture& t = **texture;
          // image2DArray / imageCube see every layer, image3D every slice; image2D sees layer 0.
          const bool layered = ((t.target == GL_TEXTURE_2D_ARRAY || t.target == GL_TEXTURE_CUBE_MAP) &&
                                (r.arrayed || r.cube)) ||
                               (t.target == GL_TEXTURE_3D && r.dimensions == 3);
          gl.BindImageTexture(point, t.name, static_cast<GLint>(b->mip), layered ? GL_TRUE : GL_FALSE, 0,
                              GL_READ_WRITE, glFormat(t.desc.format).internalFormat);
          break;
        }
        case BindingKind::UniformTexelBuffer:
        case BindingKind::StorageTexelBuffer: {
          std::unique_ptr<GlBuffer>* buffer = buffers_.get(b->buffer);
          if (!buffer) break;
          const size_t size = b->size ? b->size : (*buffer)->desc.size - b->offset;
          const GLuint view = texelView(**buffer, b->texelFormat, b->offset, size);
          if (b->kind == BindingKind::UniformTexelBuffer)
            gl.BindTextureUnit(point, view);
          else
            gl.BindImageTexture(point, view, 0, GL_FALSE, 0, GL_READ_WRITE, glFormat(b->texelFormat).internalFormat);
          break;
        }
        case BindingKind::SeparateTexture:
        case BindingKind::SeparateSampler:
          break;  // bound per pair below
      }
    }
  // Separate textures and samplers: the pair's texture and sampler object share one unit
  // (gl_device.h), one unit per element of a texture array. A pair without a sampler (texelFetch)
  // gets the default sampler.
  for (size_t k = 0; k < program.separatePairs.size(); ++k) {
    const SeparatePair& pair = program.separatePairs[k];
    auto use = std::find_if(program.resources.begin(), program.resources.end(),
                            [&](const ShaderResource& r) { return r.binding == pair.textureBinding; });
    if (use == program.resources.end()) continue;
    const GlSampler* sampler = nullptr;
    if (pair.samplerBinding != kNoSamplerBinding && bindings_[pair.samplerBinding][0])
      sampler = samplers_.get(bindings_[pair.samplerBinding][0]->sampler);
    for (uint32_t element = 0; element < use->arraySize; ++element) {
      const std::optional<ResourceBinding>& tb = bindings_[pair.textureBinding][element];
      std::unique_ptr<GlTexture>* texture = tb ? textures_.get(tb->texture) : nullptr;
      if (!texture) continue;
      const GLuint unit = program.pairUnits[k] + element;
      gl.BindTextureUnit(unit, samplingTexture(**texture, *use));
      gl.BindSampler(unit, sampler ? sampler->name : pair.depthCompare ? defaultShadowSampler_ : defaultSampler_);
    }
  }
}

void GlDevice::applyPushConstants(const GlProgram& program) {
  if (program.pushConstantSize == 0) return;
  if (pushConstantsDirty_) {
    // A fresh slot: the draws already issued keep reading theirs. A full ring waits for them.
    if (pushConstantNext_ + pushConstantSlotBytes_ > kPushConstantRingBytes) {
      gl.Finish();
      pushConstantNext_ = 0;
    }
    std::memcpy(pushConstantRing_ + pushConstantNext_, pushConstantData_.data(), kMaxPushConstantBytes);
    pushConstantBound_ = pushConstantNext_;
    pushConstantNext_ += pushConstantSlotBytes_;
    pushConstantsDirty_ = false;
  }
  const auto offset = static_cast<GLintptr>(pushConstantBound_);
  if (program.pushConstantsInUniformBlock)
    gl.BindBufferRange(GL_UNIFORM_BUFFER, program.points[kMaxBindings], pushConstantBuffer_, offset, kMaxPushConstantBytes);
  if (program.pushConstantsInStorageBlock)
    gl.BindBufferRange(GL_SHADER_STORAGE_BUFFER, program.points[kMaxBindings], pushConstantBuffer_, offset,
                       kMaxPushConstantBytes);
}

// ---------------------------------------------------------------------------------------------
// Draws and dispatches
// ---------------------------------------------------------------------------------------------
void GlDevice::prepareDraw(uint32_t firstInstance) {
  GlPipeline& p = *pipelines_.get(pipeline_);
  gl.UseProgram(p.program.name);
  bindArbPrograms(p.program);
  applyVertexInput(p);
  applyRenderState(p);
  applyBindings(p.program);
  applyPushConstants(p.program);
  applyOpenGlInterface(p.program);
  if (p.program.openGlClipSpace != openGlClipSpace_) {
    openGlClipSpace_ = p.program.openGlClipSpace;
    gl.ClipControl(GL_LOWER_LEFT, openGlClipSpace_ ? GL_NEGATIVE_ONE_TO_ONE : GL_ZERO_TO_ONE);  // see setConventions
  }
  if (p.desc.topology == PrimitiveTopology::Patches) gl.PatchParameteri(GL_PATCH_VERTICES, static_cast<GLint>(p.desc.patchControlPoints));
  if (p.program.baseInstanceLocation >= 0)
    gl.ProgramUniform1i(p.program.name, p.program.baseInstanceLocation, static_cast<GLint>(firstInstance));
}

void GlDevice::draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) {
  GlPipeline* p = pipelines_.get(pipeline_);
  if (!inPass_ || !p || vertexCount == 0 || instanceCount == 0) return;
  prepareDraw(firstInstance);
  if (p->program.readsBaseVertex && firstVertex != 0) {
    // Vulkan's BaseVertex is firstVertex in a non-indexed draw, GL's gl_BaseVertex 0: the draw
    // becomes an indexed one over indices 0..count-1 with firstVertex as its base vertex, which
    // fetches the same vertices with the same gl_VertexID and gives gl_BaseVertex firstVertex.
    gl.VertexArrayElementBuffer(p->vao, sequentialIndices(vertexCount));
    gl.DrawElementsInstancedBaseVertexBaseInstance(glTopology(p->desc.topology), static_cast<GLsizei>(vertexCount),
                                                   GL_UNSIGNED_INT, nullptr, static_cast<GLsizei>(instanceCount),
                                                   static_cast<GLint>(firstVertex), firstInstance);
    return;
  }
  gl.DrawArraysInstancedBaseInstance(glTopology(p->desc.topology), static_cast<GLint>(firstVertex),
                                     static_cast<GLsizei>(vertexCount), static_cast<GLsizei>(instanceCount),
                                     firstInstance);
}

GLuint GlDevice::sequentialIndices(uint32_t count) {
  if (count > sequentialIndexCount_) {
    std::vector<uint32_t> indices(count);
    for (uint32_t i = 0; i < count; ++i) indices[i] = i;
    if (sequentialIndices_ != 0) gl.DeleteBuffers(1, &sequentialIndices_);
    gl.CreateBuffers(1, &sequentialIndices_);
    gl.NamedBufferStorage(sequentialIndices_, static_cast<GLsizeiptr>(count * sizeof(uint32_t)), indices.data(), 0);
    sequentialIndexCount_ = count;
  }
  return sequentialIndices_;
}

void GlDevice::drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                           uint32_t firstInstance) {
  GlPipeline* p = pipelines_.get(pipeline_);
  std::unique_ptr<GlBuffer>* indices = buffers_.get(indexBuffer_);
  if (!inPass_ || !p || !indices || indexCount == 0 || instanceCount == 0) return;
  prepareDraw(firstInstance);
  gl.VertexArrayElementBuffer(p->vao, (*indices)->name);
  const bool u16 = indexType_ == IndexType::UInt16;
  const size_t offset = indexOffset_ + size_t(firstIndex) * (u16 ? 2 : 4);
  gl.DrawElementsInstancedBaseVertexBaseInstance(glTopology(p->desc.topology), static_cast<GLsizei>(indexCount),
                                                 u16 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT,
                                                 reinterpret_cast<const void*>(offset),
                                                 static_cast<GLsizei>(instanceCount), vertexOffset, firstInstance);
}

void GlDevice::setComputePipeline(ComputePipelineHandle h) { computePipeline_ = h; }

void GlDevice::dispatch(uint32_t x, uint32_t y, uint32_t z) {
  GlComputePipeline* p = computePipelines_.get(computePipeline_);
  if (inPass_ || !p) return;
  gl.UseProgram(p->program.name);
  applyBindings(p->program);
  applyPushConstants(p->program);
  applyOpenGlInterface(p->program);
  gl.DispatchCompute(x, y, z);
  gl.MemoryBarrier(GL_ALL_BARRIER_BITS);
}

// ---------------------------------------------------------------------------------------------
// Timestamps
// ---------------------------------------------------------------------------------------------
TimestampId GlDevice::writeTimestamp() {
  if (timestampsWritten_ == timestampQueries_.size()) {
    GLuint query = 0;
    gl.CreateQueries(GL_TIMESTAMP, 1, &query);
    timestampQueries_.push_back(query);
  }
  const TimestampId id = timestampsWritten_++;
  gl.QueryCounter(timestampQueries_[id], GL_TIMESTAMP);
  // llvmpipe takes the timestamp when the batch reaches the driver's queue: without a flush,
  // all of a frame's timestamps land together at the next flush and the differences say
  // nothing about the work in between.
  gl.Flush();
  return id;
}

std::optional<uint64_t> GlDevice::timestampNs(TimestampId id) {
  if (id >= timestampsWritten_) return std::nullopt;
  GLuint64 value = 0;
  gl.GetQueryObjectui64v(timestampQueries_[id], GL_QUERY_RESULT, &value);  // GL_TIMESTAMP is in ns
  return value;
}

void GlDevice::resetTimestamps() { timestampsWritten_ = 0; }

}  // namespace parity::rhi::gl
