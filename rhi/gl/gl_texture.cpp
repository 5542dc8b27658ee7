// GL backend: the format table, textures (immutable storage), views (glTextureView), samplers,
// texel upload, readback and copies.
#include <algorithm>
#include <cstring>

#include "rhi/gl/gl_device.h"

namespace parity::rhi::gl {

// The one table mapping rhi formats to GL. The transfer format/type move raw texels: GL does
// not convert between them and the internal format (sRGB stays encoded, halfs stay halfs).
const GlFormat& glFormat(Format f) {
  static const GlFormat kTable[] = {
      /* Undefined  */ {GL_NONE, GL_NONE, GL_NONE},
      /* RGBA8      */ {GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE},
      /* RGBA8_SRGB */ {GL_SRGB8_ALPHA8, GL_RGBA, GL_UNSIGNED_BYTE},
      /* RGBA8_UINT */ {GL_RGBA8UI, GL_RGBA_INTEGER, GL_UNSIGNED_BYTE},
      /* R8         */ {GL_R8, GL_RED, GL_UNSIGNED_BYTE},
      /* RG16_UNORM */ {GL_RG16, GL_RG, GL_UNSIGNED_SHORT},
      /* RG16_SNORM */ {GL_RG16_SNORM, GL_RG, GL_SHORT},
      /* RG16_FLOAT */ {GL_RG16F, GL_RG, GL_HALF_FLOAT},
      /* RG16_UINT  */ {GL_RG16UI, GL_RG_INTEGER, GL_UNSIGNED_SHORT},
      /* R32_UINT   */ {GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT},
      /* R32F       */ {GL_R32F, GL_RED, GL_FLOAT},
      /* RGBA16F    */ {GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT},
      /* RG32F      */ {GL_RG32F, GL_RG, GL_FLOAT},
      /* RGBA32F    */ {GL_RGBA32F, GL_RGBA, GL_FLOAT},
      // Depth-stencil upload: packed 32-bit words, depth in the high 24 bits, stencil in the low 8.
      /* D24S8      */ {GL_DEPTH24_STENCIL8, GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8},
      /* D32F       */ {GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT},
      /* D16        */ {GL_DEPTH_COMPONENT16, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT},
      /* RG8_UINT   */ {GL_RG8UI, GL_RG_INTEGER, GL_UNSIGNED_BYTE},
      /* RG8_SNORM  */ {GL_RG8_SNORM, GL_RG, GL_BYTE},
      /* R16_SNORM  */ {GL_R16_SNORM, GL_RED, GL_SHORT},
      /* RGBA8_SNORM */ {GL_RGBA8_SNORM, GL_RGBA, GL_BYTE},
      /* RGBA16_SNORM */ {GL_RGBA16_SNORM, GL_RGBA, GL_SHORT},
      // The _REV packing puts R in the low bits, as Vulkan's B10G11R11_UFLOAT_PACK32.
      /* B10G11R11_UFLOAT */ {GL_R11F_G11F_B10F, GL_RGB, GL_UNSIGNED_INT_10F_11F_11F_REV},
      /* R32_SINT   */ {GL_R32I, GL_RED_INTEGER, GL_INT},
      /* RGBA32_UINT */ {GL_RGBA32UI, GL_RGBA_INTEGER, GL_UNSIGNED_INT},
      /* RGBA32_SINT */ {GL_RGBA32I, GL_RGBA_INTEGER, GL_INT},
  };
  static_assert(sizeof(kTable) / sizeof(kTable[0]) == static_cast<size_t>(Format::Count));
  const size_t i = static_cast<size_t>(f);
  return kTable[i < static_cast<size_t>(Format::Count) ? i : 0];
}

namespace {

uint32_t mipExtent(uint32_t size, uint32_t mip) { return std::max(1u, size >> mip); }

// Targets whose layers (array layers, cube faces, 3D slices) the DSA calls address as z.
bool isLayered(GLenum target) {
  return target == GL_TEXTURE_2D_ARRAY || target == GL_TEXTURE_CUBE_MAP || target == GL_TEXTURE_3D;
}

// A 1D array texture's layers are its rows: the DSA calls address them as y.
GLint layerAsY(GLenum target, uint32_t layer) { return target == GL_TEXTURE_1D_ARRAY ? static_cast<GLint>(layer) : 0; }

GLenum glFilter(Filter filter, MipFilter mip) {
  const bool linear = filter == Filter::Linear;
  switch (mip) {
    case MipFilter::None: return linear ? GL_LINEAR : GL_NEAREST;
    case MipFilter::Nearest: return linear ? GL_LINEAR_MIPMAP_NEAREST : GL_NEAREST_MIPMAP_NEAREST;
    case MipFilter::Linear: return linear ? GL_LINEAR_MIPMAP_LINEAR : GL_NEAREST_MIPMAP_LINEAR;
  }
  return GL_NEAREST;
}

GLenum glAddress(AddressMode mode) {
  switch (mode) {
    case AddressMode::ClampToEdge: return GL_CLAMP_TO_EDGE;
    case AddressMode::Repeat: return GL_REPEAT;
    case AddressMode::MirroredRepeat: return GL_MIRRORED_REPEAT;
    case AddressMode::ClampToBorder: return GL_CLAMP_TO_BORDER;  // border (0,0,0,0) as in Vulkan's transparent black
  }
  return GL_CLAMP_TO_EDGE;
}

GLenum glCompare(CompareOp op) {
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

// Uploads one layer/mip of tightly packed texels (unpack alignment is 1 device-wide).
void upload(const GlFunctions& gl, const GlTexture& t, uint32_t layer, uint32_t mip, const void* data) {
  const GlFormat& f = glFormat(t.desc.format);
  const GLsizei w = static_cast<GLsizei>(mipExtent(t.desc.width, mip));
  const GLsizei h = static_cast<GLsizei>(mipExtent(t.desc.height, mip));
  if (isLayered(t.target)) {
    // Cube faces are layers 0..5 (+X, -X, +Y, -Y, +Z, -Z) for the DSA calls, as in Vulkan.
    gl.TextureSubImage3D(t.name, static_cast<GLint>(mip), 0, 0, static_cast<GLint>(layer), w, h, 1, f.format,
                         f.type, data);
  } else if (t.target == GL_TEXTURE_1D) {
    gl.TextureSubImage1D(t.name, static_cast<GLint>(mip), 0, w, f.format, f.type, data);
  } else if (t.target == GL_TEXTURE_1D_ARRAY) {
    gl.TextureSubImage2D(t.name, static_cast<GLint>(mip), 0, layerAsY(t.target, layer), w, 1, f.format, f.type, data);
  } else {
    gl.TextureSubImage2D(t.name, static_cast<GLint>(mip), 0, 0, w, h, f.format, f.type, data);
  }
}

}  // namespace

TextureHandle GlDevice::createTexture(const TextureDesc& desc) {
  auto texture = std::make_unique<GlTexture>();
  texture->desc = desc;
  texture->desc.initialData = nullptr;  // not owned past this call
  const GlFormat& f = glFormat(desc.format);
  const auto w = static_cast<GLsizei>(desc.width), h = static_cast<GLsizei>(desc.height);
  const auto mips = static_cast<GLsizei>(std::max(1u, desc.mipLevels));
  if (desc.samples > 1) {
    texture->target = GL_TEXTURE_2D_MULTISAMPLE;
    gl.CreateTextures(texture->target, 1, &texture->name);
    // Fixed sample locations: Vulkan's standard locations are fixed per sample count.
    gl.TextureStorage2DMultisample(texture->name, static_cast<GLsizei>(desc.samples), f.internalFormat, w, h,
                                   GL_TRUE);
  } else if (desc.type == TextureType::Cube) {
    texture->target = GL_TEXTURE_CUBE_MAP;
    gl.CreateTextures(texture->target, 1, &texture->name);
    gl.TextureStorage2D(texture->name, mips, f.internalFormat, w, h);
  } else if (desc.type == TextureType::Tex2DArray) {
    texture->target = GL_TEXTURE_2D_ARRAY;
    gl.CreateTextures(texture->target, 1, &texture->name);
    gl.TextureStorage3D(texture->name, mips, f.internalFormat, w, h, static_cast<GLsizei>(desc.layers));
  } else if (desc.type == TextureType::Tex1D && desc.layers > 1) {
    texture->target = GL_TEXTURE_1D_ARRAY;
    gl.CreateTextures(texture->target, 1, &texture->name);
    gl.TextureStorage2D(texture->name, mips, f.internalFormat, w, static_cast<GLsizei>(desc.layers));
  } else if (desc.type == TextureType::Tex1D) {
    texture->target = GL_TEXTURE_1D;
    gl.CreateTextures(texture->target, 1, &texture->name);
    gl.TextureStorage1D(texture->name, mips, f.internalFormat, w);
  } else if (desc.type == TextureType::Tex3D) {
    texture->target = GL_TEXTURE_3D;
    gl.CreateTextures(texture->target, 1, &texture->name);
    gl.TextureStorage3D(texture->name, mips, f.internalFormat, w, h, static_cast<GLsizei>(desc.depth));
  } else {
    texture->target = GL_TEXTURE_2D;
    gl.CreateTextures(texture->target, 1, &texture->name);
    gl.TextureStorage2D(texture->name, mips, f.internalFormat, w, h);
  }
  label(GL_TEXTURE, texture->name, desc.label);
  if (desc.initialData && desc.samples <= 1) {
    const size_t layerBytes = size_t(desc.width) * desc.height * formatInfo(desc.format).bytesPerTexel;
    const auto* bytes = static_cast<const uint8_t*>(desc.initialData);
    const uint32_t layers = texture->target == GL_TEXTURE_3D                                      ? desc.depth
                            : isLayered(texture->target) || texture->target == GL_TEXTURE_1D_ARRAY ? desc.layers
                                                                                                  : 1;
    for (uint32_t layer = 0; layer < layers; ++layer) upload(gl, *texture, layer, 0, bytes + layer * layerBytes);
  }
  return textures_.add(std::move(texture));
}

// OpenGL's TEXTURE_SWIZZLE_R..A of a texture object (its defaults are the identity). A view
// does not take its parent's, so every texture object made for a view is given the view's.
static void applySwizzle(const GlFunctions& gl, GLuint texture, const ComponentMapping& mapping) {
  if (mapping.isIdentity()) return;
  auto source = [](Swizzle s, GLint own) -> GLint {
    switch (s) {
      case Swizzle::Zero: return GL_ZERO;
      case Swizzle::One: return GL_ONE;
      case Swizzle::Red: return GL_RED;
      case Swizzle::Green: return GL_GREEN;
      case Swizzle::Blue: return GL_BLUE;
      case Swizzle::Alpha: return GL_ALPHA;
      case Swizzle::Identity: break;
    }
    return own;
  };
  gl.TextureParameteri(texture, GL_TEXTURE_SWIZZLE_R, source(mapping.r, GL_RED));
  gl.TextureParameteri(texture, GL_TEXTURE_SWIZZLE_G, source(mapping.g, GL_GREEN));
  gl.TextureParameteri(texture, GL_TEXTURE_SWIZZLE_B, source(mapping.b, GL_BLUE));
  gl.TextureParameteri(texture, GL_TEXTURE_SWIZZLE_A, source(mapping.a, GL_ALPHA));
}

TextureHandle GlDevice::createTextureView(const TextureViewDesc& desc) {
  std::unique_ptr<GlTexture>* parentBox = textures_.get(desc.parent);
  if (!parentBox) return {};
  const GlTexture& parent = **parentBox;
  const TextureDesc& p = parent.desc;
  const Format format = desc.format == Format::Undefined ? p.format : desc.format;
  const uint32_t layerCount = desc.layerCount ? desc.layerCount : p.layers - desc.baseLayer;
  const uint32_t mipCount = desc.mipCount ? desc.mipCount : p.mipLevels - desc.baseMip;

  auto view = std::make_unique<GlTexture>();
  view->isView = true;
  view->desc = p;
  view->desc.format = format;
  view->desc.width = mipExtent(p.width, desc.baseMip);
  view->desc.height = mipExtent(p.height, desc.baseMip);
  view->desc.layers = layerCount;
  view->desc.mipLevels = mipCount;
  view->desc.initialData = nullptr;
  view->desc.label = desc.label;
  // rhi describes a view with its parent's texture type. The GL target is what a shader would
  // naturally sample it as: a single layer is a 2D texture, a whole cube a cube, other layer
  // ranges an array (samplingTexture() adapts it when a shader declares otherwise).
  if (p.samples > 1)
    view->target = GL_TEXTURE_2D_MULTISAMPLE;
  else if (p.type == TextureType::Tex1D || p.type == TextureType::Tex3D)
    view->target = parent.target;  // glTextureView keeps 1D and 3D textures what they are
  else if (p.type == TextureType::Cube && desc.baseLayer == 0 && layerCount == 6)
    view->target = GL_TEXTURE_CUBE_MAP;
  else if (layerCount == 1)
    view->target = GL_TEXTURE_2D;
  else
    view->target = GL_TEXTURE_2D_ARRAY;
  // glTextureView needs a name that was generated but never bound, so not glCreateTextures.
  gl.GenTextures(1, &view->name);
  gl.TextureView(view->name, view->target, parent.name, glFormat(format).internalFormat, desc.baseMip, mipCount,
                 desc.baseLayer, layerCount);
  view->swizzle = desc.swizzle;
  applySwizzle(gl, view->name, desc.swizzle);
  label(GL_TEXTURE, view->name, desc.label);
  return textures_.add(std::move(view));
}

void GlDevice::deleteTextureObjects(GlTexture& texture) {
  for (GlSamplingView& v : texture.samplingViews) gl.DeleteTextures(1, &v.name);
  texture.samplingViews.clear();
  gl.DeleteTextures(1, &texture.name);
  texture.name = 0;
}

void GlDevice::destroy(TextureHandle h) {
  std::optional<std::unique_ptr<GlTexture>> texture = textures_.remove(h);
  if (!texture) return;
  forgetFramebuffersOf(h);
  deleteTextureObjects(**texture);
}

const TextureDesc* GlDevice::describe(TextureHandle h) const {
  const std::unique_ptr<GlTexture>* texture = textures_.get(h);
  return texture ? &(*texture)->desc : nullptr;
}

// The texture object a shader resource should sample: the texture itself, or a view of it when
// the shader's sampler type needs another GL target (GL binds by target; Vulkan's image view
// type plays this role there) or reads the stencil of a D24S8 texture (GL selects depth or
// stencil per texture object with DEPTH_STENCIL_TEXTURE_MODE; Vulkan by the view's aspect).
GLuint GlDevice::samplingTexture(GlTexture& texture, const ShaderResource& use) {
  const GLenum want = use.multisampled      ? GL_TEXTURE_2D_MULTISAMPLE
                      : use.dimensions == 1 ? (use.arrayed ? GL_TEXTURE_1D_ARRAY : GL_TEXTURE_1D)
                      : use.dimensions == 3 ? GL_TEXTURE_3D
                      : use.cube            ? GL_TEXTURE_CUBE_MAP
                      : use.arrayed    ? GL_TEXTURE_2D_ARRAY
                                       : GL_TEXTURE_2D;
  const bool stencil = use.integer && hasStencil(texture.desc.format);
  if (want == texture.target && !stencil) return texture.name;

  // Targets glTextureView can derive from the texture's own; anything else is bound unchanged
  // (a mismatch validation reports).
  GLuint layers = 0;
  switch (want) {
    case GL_TEXTURE_2D:
      if (texture.target == GL_TEXTURE_2D_MULTISAMPLE) return texture.name;
      layers = 1;
      break;
    case GL_TEXTURE_2D_ARRAY:
      if (texture.target == GL_TEXTURE_2D_MULTISAMPLE) return texture.name;
      layers = texture.target == GL_TEXTURE_2D ? 1 : texture.desc.layers;
      break;
    case GL_TEXTURE_CUBE_MAP:
      if (texture.target == GL_TEXTURE_2D || texture.target == GL_TEXTURE_2D_MULTISAMPLE ||
          texture.desc.layers < 6 || texture.desc.width != texture.desc.height)
        return texture.name;
      layers = 6;
      break;
    case GL_TEXTURE_2D_MULTISAMPLE:
      if (texture.target != GL_TEXTURE_2D_MULTISAMPLE) return texture.name;
      layers = 1;
      break;
    case GL_TEXTURE_1D:
      if (texture.target != GL_TEXTURE_1D_ARRAY) return texture.name;
      layers = 1;
      break;
    case GL_TEXTURE_1D_ARRAY:
      if (texture.target != GL_TEXTURE_1D) return texture.name;
      layers = 1;
      break;
    default: return texture.name;
  }
  for (const GlSamplingView& v : texture.samplingViews)
    if (v.target == want && v.stencil == stencil) return v.name;

  GlSamplingView view{want, stencil, 0};
  gl.GenTextures(1, &view.name);
  gl.TextureView(view.name, want, texture.name, glFormat(texture.desc.format).internalFormat, 0,
                 texture.desc.mipLevels, 0, layers);
  if (stencil) gl.TextureParameteri(view.name, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_STENCIL_INDEX);
  applySwizzle(gl, view.name, texture.swizzle);
  texture.samplingViews.push_back(view);
  return view.name;
}

SamplerHandle GlDevice::createSampler(const SamplerDesc& desc) {
  GlSampler sampler;
  sampler.desc = desc;
  gl.CreateSamplers(1, &sampler.name);
  gl.SamplerParameteri(sampler.name, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(glFilter(desc.minFilter, desc.mipFilter)));
  gl.SamplerParameteri(sampler.name, GL_TEXTURE_MAG_FILTER, desc.magFilter == Filter::Linear ? GL_LINEAR : GL_NEAREST);
  gl.SamplerParameteri(sampler.name, GL_TEXTURE_WRAP_S, static_cast<GLint>(glAddress(desc.addressU)));
  gl.SamplerParameteri(sampler.name, GL_TEXTURE_WRAP_T, static_cast<GLint>(glAddress(desc.addressV)));
  gl.SamplerParameteri(sampler.name, GL_TEXTURE_WRAP_R, static_cast<GLint>(glAddress(desc.addressW)));
  // GL's initial border colour is (0, 0, 0, 0) as floats, BorderColor::FloatTransparentBlack.
  // Integer textures read the border colour as integers when it is set with the I variant.
  switch (desc.borderColor) {
    case BorderColor::FloatTransparentBlack: break;
    case BorderColor::FloatOpaqueBlack:
    case BorderColor::FloatOpaqueWhite: {
      const float white = desc.borderColor == BorderColor::FloatOpaqueWhite ? 1.0f : 0.0f;
      const GLfloat color[4] = {white, white, white, 1.0f};
      gl.SamplerParameterfv(sampler.name, GL_TEXTURE_BORDER_COLOR, color);
      break;
    }
    case BorderColor::IntTransparentBlack:
    case BorderColor::IntOpaqueBlack:
    case BorderColor::IntOpaqueWhite: {
      const GLint white = desc.borderColor == BorderColor::IntOpaqueWhite ? 1 : 0;
      const GLint alpha = desc.borderColor == BorderColor::IntTransparentBlack ? 0 : 1;
      const GLint color[4] = {white, white, white, alpha};
      gl.SamplerParameterIiv(sampler.name, GL_TEXTURE_BORDER_COLOR, color);
      break;
    }
  }
  gl.SamplerParameterf(sampler.name, GL_TEXTURE_MIN_LOD, desc.minLod);
  gl.SamplerParameterf(sampler.name, GL_TEXTURE_MAX_LOD, desc.maxLod);
  gl.SamplerParameterf(sampler.name, GL_TEXTURE_LOD_BIAS, desc.mipLodBias);
  if (desc.compareEnabled) {
    gl.SamplerParameteri(sampler.name, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    gl.SamplerParameteri(sampler.name, GL_TEXTURE_COMPARE_FUNC, static_cast<GLint>(glCompare(desc.compare)));
  }
  label(GL_SAMPLER, sampler.name, desc.label);
  return samplers_.add(std::move(sampler));
}

void GlDevice::destroy(SamplerHandle h) {
  std::optional<GlSampler> sampler = samplers_.remove(h);
  if (sampler) gl.DeleteSamplers(1, &sampler->name);
}

void GlDevice::writeTexture(TextureHandle h, uint32_t layer, uint32_t mip, const void* data) {
  std::unique_ptr<GlTexture>* texture = textures_.get(h);
  if (!texture || (*texture)->desc.samples > 1) return;
  upload(gl, **texture, layer, mip, data);
}

std::vector<uint8_t> GlDevice::readTexture(TextureHandle h, const ReadbackRegion& region) {
  std::unique_ptr<GlTexture>* box = textures_.get(h);
  if (!box) return {};
  const GlTexture& t = **box;
  if (t.desc.samples > 1) return {};  // resolve first (rhi.h)
  const uint32_t w = mipExtent(t.desc.width, region.mip), h2 = mipExtent(t.desc.height, region.mip);
  GLenum format, type;
  size_t texelBytes;
  TextureAspect aspect = region.aspect;
  if (isDepthFormat(t.desc.format) && aspect == TextureAspect::Color) aspect = TextureAspect::Depth;
  const bool d16 = aspect == TextureAspect::Depth && t.desc.format == Format::D16;
  if (d16) {
    // Read as stored and converted below: GL's own unorm16-to-float conversion is not
    // guaranteed to round correctly.
    format = GL_DEPTH_COMPONENT, type = GL_UNSIGNED_SHORT, texelBytes = 2;
  } else if (aspect == TextureAspect::Depth) {
    // GL converts D24 to float correctly rounded here (q / 16777215), as rhi.h asks.
    format = GL_DEPTH_COMPONENT, type = GL_FLOAT, texelBytes = 4;
  } else if (aspect == TextureAspect::Stencil) {
    format = GL_STENCIL_INDEX, type = GL_UNSIGNED_BYTE, texelBytes = 1;
  } else {
    const GlFormat& f = glFormat(t.desc.format);
    format = f.format, type = f.type, texelBytes = formatInfo(t.desc.format).bytesPerTexel;
  }
  std::vector<uint8_t> out(size_t(w) * h2 * texelBytes);
  // Memory row 0 first: with the device's clip control, row 0 is what rhi calls row 0.
  // Cube faces, array layers and 3D slices are addressed as z; pack alignment is 1 device-wide.
  const GLint z = isLayered(t.target) ? static_cast<GLint>(region.layer) : 0;
  gl.GetTextureSubImage(t.name, static_cast<GLint>(region.mip), 0, layerAsY(t.target, region.layer), z, static_cast<GLsizei>(w),
                        static_cast<GLsizei>(h2), 1, format, type, static_cast<GLsizei>(out.size()), out.data());
  if (d16) return unorm16DepthToFloat(out);
  return out;
}

void GlDevice::copyTexture(TextureHandle src, TextureHandle dst, const ReadbackRegion& srcRegion,
                           const ReadbackRegion& dstRegion) {
  std::unique_ptr<GlTexture>* s = textures_.get(src);
  std::unique_ptr<GlTexture>* d = textures_.get(dst);
  if (!s || !d) return;
  const GlTexture& a = **s;
  const GlTexture& b = **d;
  const auto w = static_cast<GLsizei>(mipExtent(a.desc.width, srcRegion.mip));
  const auto h = static_cast<GLsizei>(mipExtent(a.desc.height, srcRegion.mip));
  gl.CopyImageSubData(a.name, a.target, static_cast<GLint>(srcRegion.mip), 0, layerAsY(a.target, srcRegion.layer),
                      isLayered(a.target) ? static_cast<GLint>(srcRegion.layer) : 0, b.name, b.target,
                      static_cast<GLint>(dstRegion.mip), 0, layerAsY(b.target, dstRegion.layer),
                      isLayered(b.target) ? static_cast<GLint>(dstRegion.layer) : 0, w, h, 1);
}

}  // namespace parity::rhi::gl
