// Script resources: BUFFER and IMAGE objects, their contents, COPY, sampled views, and LOGICAL
// images planned by the platform layer.
#include "harness/scripts/runner/steps.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

namespace parity::harness::script::runner {

namespace {

// Bytes of a whole mip chain of `levels` levels from width x height.
size_t chainBytes(uint32_t width, uint32_t height, uint32_t levels, uint32_t bytesPerTexel) {
  size_t bytes = 0;
  for (uint32_t mip = 0; mip < levels; ++mip) bytes += size_t(std::max(width >> mip, 1u)) * std::max(height >> mip, 1u) * bytesPerTexel;
  return bytes;
}

}  // namespace

// The platform layer: parameters, the plan of every LOGICAL image, the shader defines and
// include folders that let a script's GLSL `#include "platform.glsl"` (and any project shader).
void ResourceSteps::setupPlatform() {
  auto id = platforms::platformFromName(opts_.platform);
  if (!id) throw Failure{"unknown platform '" + opts_.platform + "'"};
  platform_ = *id;
  for (const auto& [name, value] : script_.platformParams) {
    std::string why;
    if (!platforms::setParameter(params_, name, value, &why)) throw Failure{"SET PLATFORM_PARAM " + name + ": " + why};
  }
  std::vector<platforms::LogicalTarget> logical;
  uint32_t width = 0, height = 0;
  for (const Buffer& b : script_.buffers) {
    if (b.logical.empty()) continue;
    platforms::LogicalTarget t;
    t.name = b.name;
    for (auto f : {platforms::LogicalFormat::Rgba8Unorm, platforms::LogicalFormat::Rg16Unorm,
                   platforms::LogicalFormat::Rgba16Hdr, platforms::LogicalFormat::Depth24Stencil8})
      if (platforms::logicalFormatName(f) == b.logical) t.format = f;
    uint32_t w = b.width, h = b.height;
    for (const Pipeline& p : script_.pipelines)
      for (const Bind& bb : p.binds)
        if (bb.buffer == b.name && (bb.kind == BindKind::Color || bb.kind == BindKind::DepthStencil)) {
          if (t.pass.empty()) t.pass = p.name;
          if (!b.width) w = p.fbWidth, h = p.fbHeight;
        }
    if (!w || !h) throw Failure{"LOGICAL image '" + b.name + "' has no size (give WIDTH and HEIGHT or bind it as an attachment)"};
    if (width && (w != width || h != height))
      throw Unsupported{"LOGICAL images of different sizes (the platform plans one size per frame)"};
    width = w, height = h;
    logical.push_back(t);
  }
  platforms::TargetPlan plan = platforms::planTargets(platform_, logical, std::max(width, 1u), std::max(height, 1u), params_);
  compileOptions_ = platforms::platformShaderOptions(plan);
  compileOptions_.includeDirs.push_back(rhi::shaderDirectory());
  if (logical.empty()) return;
  targets_ = std::make_unique<platforms::GpuTargets>(dev_, plan);
  for (const platforms::PhysicalTarget& t : plan.targets) {
    Resource r;
    r.def = script_.findBuffer(t.logical.name);
    r.logical = true;
    r.texture = targets_->attachment(t.logical.name);
    r.readTexture = targets_->readTexture(t.logical.name);
    r.format.format = t.attachmentFormat;
    r.width = width, r.height = height;
    if (!r.texture || !r.readTexture) throw Failure{"cannot create the " + opts_.platform + " targets of LOGICAL image '" + t.logical.name + "'"};
    res_[t.logical.name] = r;
  }
}

void ResourceSteps::createResources() {
  // Which buffers live in textures: those bound as attachments or images anywhere.
  std::map<std::string, std::pair<uint32_t, uint32_t>> textureSize;
  std::set<std::string> isTexture;
  for (const Pipeline& p : script_.pipelines)
    for (const Bind& b : p.binds) {
      bool attachment = b.kind == BindKind::Color || b.kind == BindKind::DepthStencil || b.kind == BindKind::Resolve;
      if (attachment || b.kind == BindKind::CombinedImageSampler || b.kind == BindKind::SampledImage ||
          b.kind == BindKind::StorageImage)
        isTexture.insert(b.buffer);
      // An attachment at BASE_MIP_LEVEL m is the framebuffer's size at that level.
      if (attachment && !textureSize.count(b.buffer))
        textureSize[b.buffer] = {p.fbWidth << b.baseMipLevel, p.fbHeight << b.baseMipLevel};
    }
  for (const Buffer& b : script_.buffers) {
    if (!b.viewOf.empty()) isTexture.insert(b.viewOf);
    if (b.textureUnit >= 0) isTexture.insert(b.name);
  }
  for (const Buffer& b : script_.buffers) {
    if (!b.logical.empty()) continue;  // created by setupPlatform()
    Resource r;
    r.def = &b;
    if (!b.viewOf.empty()) {
      const Resource& parent = res_.at(b.viewOf);
      r.format = textureFormat(b.type);
      r.width = parent.width, r.height = parent.height, r.samples = parent.samples, r.depth = parent.depth;
      rhi::TextureViewDesc vd;
      vd.parent = parent.texture;
      vd.format = r.format.format;
      vd.label = b.name;
      r.texture = dev_.createTextureView(vd);
      if (!r.texture) throw Failure{"cannot create view '" + b.name + "' of '" + b.viewOf + "'"};
      res_[b.name] = r;
      continue;
    }
    if (isTexture.count(b.name)) {
      r.format = textureFormat(b.type);
      if (b.isImage && b.dim == "DIM_2D" && textureSize.count(b.name)) {
        // As in Amber, an IMAGE bound as an attachment takes its pipeline's framebuffer size.
        r.width = textureSize[b.name].first, r.height = textureSize[b.name].second, r.samples = b.samples;
      } else if (b.isImage || b.width > 0) {  // IMAGE, or a BUFFER loaded from a PNG
        r.width = b.width, r.height = b.height, r.samples = b.samples, r.depth = b.depth;
      } else if (textureSize.count(b.name)) {
        r.width = textureSize[b.name].first, r.height = textureSize[b.name].second;
      } else {
        throw Unsupported{"BUFFER '" + b.name + "' sampled as an image without being rendered to"};
      }
      rhi::TextureDesc td;
      td.format = r.format.format;
      td.width = r.width, td.height = r.height, td.samples = r.samples;
      if (b.dim == "DIM_1D") td.type = rhi::TextureType::Tex1D;
      if (b.dim == "DIM_3D") td.type = rhi::TextureType::Tex3D, td.depth = r.depth;
      if (b.dim == "DIM_3D" && b.mipLevels > 1) throw Unsupported{"IMAGE DIM_3D with MIP_LEVELS"};
      if (b.layers > 1 || b.arrayTexture) td.type = b.dim == "DIM_1D" ? rhi::TextureType::Tex1D : rhi::TextureType::Tex2DArray, td.layers = b.layers;
      td.mipLevels = b.mipLevels;
      td.usage = rhi::TextureUsage_Sampled | rhi::TextureUsage_RenderTarget;
      for (const Pipeline& p : script_.pipelines)
        for (const Bind& bb : p.binds)
          if (bb.buffer == b.name && bb.kind == BindKind::StorageImage) td.usage |= rhi::TextureUsage_Storage;
      if (b.imageUnit >= 0) td.usage |= rhi::TextureUsage_Storage;  // shader_test: bound to an image unit
      if (r.samples > 1 && (td.usage & rhi::TextureUsage_Storage) && !dev_.info().caps.storageMultisample)
        throw Unsupported{"IMAGE '" + b.name + "' of " + std::to_string(r.samples) + " samples as a storage image (" +
                          dev_.info().renderer + " has no multisample storage images)"};
      td.label = b.name;
      std::vector<uint8_t> init;
      const rhi::FormatInfo& fi = rhi::formatInfo(td.format);
      size_t texels = size_t(r.width) * r.height * r.depth * b.layers;
      const size_t scriptTexel = r.format.scriptBytesPerTexel();
      const bool depthData = td.format != rhi::Format::D24S8 && b.sized && b.bytes.size() == texels * fi.bytesPerTexel;
      if (rhi::isDepthFormat(td.format) && !depthData) {
        // No data (or D24S8's, whose packing is not read): the depth an attachment starts at.
        if (td.format == rhi::Format::D24S8) {
          init.assign(texels * 4, 0xFF);  // words 0xFFFFFF00: depth 1.0, stencil 0
          for (size_t i = 0; i < texels; ++i) init[i * 4] = 0;
        } else if (td.format == rhi::Format::D16) {
          init.assign(texels * 2, 0xFF);  // 0xFFFF: depth 1.0
        } else {
          std::vector<float> ones(texels, 1.0f);
          init.assign(reinterpret_cast<uint8_t*>(ones.data()), reinterpret_cast<uint8_t*>(ones.data()) + texels * 4);
        }
      } else if (b.sized && b.bytes.size() == texels * scriptTexel) {
        init = toTextureBytes(r, b.bytes);
      } else if (b.sized && b.mipLevels > 1 && b.bytes.size() == chainBytes(r.width, r.height, b.mipLevels, scriptTexel)) {
        init = toTextureBytes(r, b.bytes);  // every level, level 0 first (shader_test's miptree)
      } else {
        init.assign(texels * fi.bytesPerTexel, 0);
      }
      if (r.samples == 1) td.initialData = init.data();
      r.texture = dev_.createTexture(td);
      if (!r.texture) throw Failure{"cannot create image '" + b.name + "' (" + fi.name + " " + std::to_string(r.width) + "x" +
                                    std::to_string(r.height) + " x" + std::to_string(r.samples) + ", " +
                                    std::to_string(b.mipLevels) + " mips)"};
      // Initial data fills mip 0 (or every level, when it holds the whole chain); the other
      // levels start as the attachments do (zero, or depth 1.0), not undefined.
      const bool wholeChain = init.size() > texels * fi.bytesPerTexel;
      for (uint32_t mip = 1, at = 0; mip < b.mipLevels && r.samples == 1; ++mip) {
        at += std::max(r.width >> (mip - 1), 1u) * std::max(r.height >> (mip - 1), 1u) * fi.bytesPerTexel;
        const size_t mipTexels = size_t(std::max(r.width >> mip, 1u)) * std::max(r.height >> mip, 1u);
        const auto from = init.begin() + (wholeChain ? at : 0);
        std::vector<uint8_t> level(from, from + static_cast<long>(mipTexels * fi.bytesPerTexel));
        if (!wholeChain && !rhi::isDepthFormat(td.format)) std::fill(level.begin(), level.end(), 0);
        dev_.writeTexture(r.texture, 0, mip, level.data());
      }
    } else if (b.sized && !b.bytes.empty()) {
      rhi::BufferDesc bd;
      bd.size = b.bytes.size();
      bd.initialData = b.bytes.data();
      bd.label = b.name;
      r.buffer = dev_.createBuffer(bd);
      if (!r.buffer) throw Failure{"cannot create buffer '" + b.name + "'"};
    }
    res_[b.name] = r;
  }
  for (const Sampler& s : script_.samplers) {
    rhi::SamplerHandle h = makeSampler(s);
    samplers_.push_back(h);
    samplerByName_[s.name] = h;
  }
}

rhi::SamplerHandle ResourceSteps::makeSampler(const Sampler& s) {
  rhi::SamplerDesc sd;
  sd.magFilter = s.linearMag ? rhi::Filter::Linear : rhi::Filter::Nearest;
  sd.minFilter = s.linearMin ? rhi::Filter::Linear : rhi::Filter::Nearest;
  sd.addressU = addressMode(s.addressMode[0]);
  sd.addressV = addressMode(s.addressMode[1]);
  sd.addressW = addressMode(s.addressMode[2]);
  sd.borderColor = borderColor(s.borderColor);
  // Amber's MIPMAP_MODE (default nearest) selects among the bound view's levels.
  sd.mipFilter = s.mipmapMode == "linear"  ? rhi::MipFilter::Linear
                 : s.mipmapMode == "none" ? rhi::MipFilter::None  // shader_test: GL's nearest/linear min filter
                                          : rhi::MipFilter::Nearest;
  sd.compareEnabled = s.compare;
  if (s.compare) sd.compare = compareOp(s.compareOp);
  sd.minLod = static_cast<float>(s.minLod);
  sd.maxLod = static_cast<float>(s.maxLod);
  sd.mipLodBias = static_cast<float>(s.lodBias);
  sd.label = s.name;
  rhi::SamplerHandle h = dev_.createSampler(sd);
  if (!h) throw Failure{"cannot create sampler '" + s.name + "'"};
  return h;
}

std::vector<uint8_t> ResourceSteps::toTextureBytes(const Resource& r, std::vector<uint8_t> bytes) {
  if (r.format.alphaFill) {
    std::vector<uint8_t> texels;
    for (size_t i = 0; i + 2 < bytes.size(); i += 3)
      texels.insert(texels.end(), {bytes[i + (r.format.bgra ? 2 : 0)], bytes[i + 1], bytes[i + (r.format.bgra ? 0 : 2)], r.format.alphaFill});
    return texels;
  }
  if (r.format.bgra)
    for (size_t i = 0; i + 3 < bytes.size(); i += 4) std::swap(bytes[i], bytes[i + 2]);
  return bytes;
}

std::vector<uint8_t> ResourceSteps::fromTextureBytes(const Resource& r, std::vector<uint8_t> bytes) {
  if (!r.format.alphaFill) return toTextureBytes(r, std::move(bytes));  // a swap is its own inverse
  std::vector<uint8_t> script;
  for (size_t i = 0; i + 3 < bytes.size(); i += 4)
    script.insert(script.end(), {bytes[i + (r.format.bgra ? 2 : 0)], bytes[i + 1], bytes[i + (r.format.bgra ? 0 : 2)]});
  return script;
}

// Current contents of a script buffer in the script's own layout.
std::vector<uint8_t> ResourceSteps::contents(const std::string& name) {
  Resource& r = res_.at(name);
  if (r.logical)
    throw Failure{"LOGICAL image '" + name + "' has platform-specific texels: read it in a shader or EXPECT " + name + " MEMORY BYTES"};
  if (r.texture) {
    if (r.samples > 1) throw Failure{"'" + name + "' is multisampled and cannot be read (bind a resolve target)"};
    rhi::ReadbackRegion region;
    if (rhi::isDepthFormat(r.format.format)) region.aspect = rhi::TextureAspect::Depth;
    std::vector<uint8_t> bytes;
    for (region.layer = 0; region.layer < r.depth; ++region.layer) {  // a 3D image slice by slice
      std::vector<uint8_t> slice = dev_.readTexture(r.texture, region);
      bytes.insert(bytes.end(), slice.begin(), slice.end());
    }
    return fromTextureBytes(r, std::move(bytes));
  }
  if (r.buffer) return dev_.readBuffer(r.buffer, 0, r.def->bytes.size());
  if (r.cpu) return *r.cpu;
  return r.def->bytes;
}

// COPY a TO b: whole contents, in the script's layout.
void ResourceSteps::copy(const Command& c) {
  Resource& src = res_.at(c.buffer);
  Resource& dst = res_.at(c.other);
  std::vector<uint8_t> bytes = contents(c.buffer);
  if (dst.texture) {
    if (dst.width != src.width || dst.height != src.height || dst.format.format != src.format.format)
      throw Unsupported{"COPY between images of different size or format"};
    if (dst.depth > 1) throw Unsupported{"COPY into a DIM_3D image"};
    dev_.writeTexture(dst.texture, 0, 0, toTextureBytes(dst, bytes).data());
  } else if (dst.buffer) {
    size_t n = std::min(bytes.size(), dst.def->bytes.size());
    dev_.writeBuffer(dst.buffer, 0, bytes.data(), n);
  } else {
    dst.cpu = bytes;
    dst.width = src.width, dst.height = src.height;
  }
}

rhi::BufferHandle ResourceSteps::gpuBuffer(const std::string& name, const Location& loc) {
  Resource& r = res_.at(name);
  if (!r.buffer) throw Failure{lineOf(loc) + ": buffer '" + name + "' has no contents (give SIZE or DATA)"};
  return r.buffer;
}

rhi::BufferHandle ResourceSteps::zeroBuffer() {
  if (!zeroBuffer_) {
    std::vector<uint8_t> zeros(16384, 0);  // within every uniform buffer range limit
    zeroBuffer_ = tempBuffer(zeros.data(), zeros.size(), "unbound binding (zeroed)");
  }
  return zeroBuffer_;
}

std::string ResourceSteps::incompleteTextureStandIn(const SamplerVariable& shape) {
  // SPIR-V's Dim: 0 1D, 1 2D, 2 3D, 3 Cube. A shadow sampler's result is undefined for an incomplete texture.
  if (shape.depth || shape.multisampled || shape.dim > 3 || (shape.arrayed && shape.dim != 1)) return {};
  rhi::TextureDesc td;
  td.type = shape.dim == 0 ? rhi::TextureType::Tex1D : shape.dim == 2 ? rhi::TextureType::Tex3D : shape.dim == 3 ? rhi::TextureType::Cube
          : shape.arrayed ? rhi::TextureType::Tex2DArray : rhi::TextureType::Tex2D;
  td.layers = td.type == rhi::TextureType::Cube ? 6 : 1;
  td.usage = rhi::TextureUsage_Sampled;
  const char* texel = "float";
  std::vector<uint8_t> bytes;
  if (shape.texel == SamplerVariable::Texel::Float) {
    td.format = rhi::Format::RGBA8;
    for (uint32_t l = 0; l < td.layers; ++l) bytes.insert(bytes.end(), {0, 0, 0, 255});
  } else {
    td.format = shape.texel == SamplerVariable::Texel::Int ? rhi::Format::RGBA32_SINT : rhi::Format::RGBA32_UINT;
    texel = shape.texel == SamplerVariable::Texel::Int ? "int" : "uint";
    const uint32_t one = 1;
    for (uint32_t l = 0; l < td.layers; ++l) {
      bytes.resize(bytes.size() + 12, 0);
      bytes.insert(bytes.end(), reinterpret_cast<const uint8_t*>(&one), reinterpret_cast<const uint8_t*>(&one) + 4);
    }
  }
  const std::string key = std::string("a unit without a texture (") + texel + ", dim " + std::to_string(shape.dim) +
                          (shape.arrayed ? ", array" : "") + ")";
  if (res_.count(key)) return key;
  td.initialData = bytes.data();
  td.label = key;
  Resource r;
  r.texture = dev_.createTexture(td);
  if (!r.texture) return {};
  r.width = r.height = 1;
  res_[key] = r;
  return key;
}

// piglit's swizzle source names (texparameter swizzle_*) as the RHI's.
static rhi::ComponentMapping componentMapping(const std::array<std::string, 4>& swizzle) {
  static const std::map<std::string, rhi::Swizzle> kSources = {
      {"red", rhi::Swizzle::Red},   {"green", rhi::Swizzle::Green}, {"blue", rhi::Swizzle::Blue},
      {"alpha", rhi::Swizzle::Alpha}, {"zero", rhi::Swizzle::Zero}, {"one", rhi::Swizzle::One}};
  auto source = [&](const std::string& name) {
    auto it = kSources.find(name);
    return it == kSources.end() ? rhi::Swizzle::Identity : it->second;
  };
  return {source(swizzle[0]), source(swizzle[1]), source(swizzle[2]), source(swizzle[3])};
}

// What a combined_image_sampler or sampled_image binding samples: the texture, or from
// BASE_MIP_LEVEL m (or piglit's base_level) a view of levels m and up, to max_level where piglit
// sets one, through piglit's swizzle where it sets one (created once per image, levels and
// swizzle).
rhi::TextureHandle ResourceSteps::sampledTexture(const Bind& b, const Sampler* state) {
  Resource& r = res_.at(b.buffer);
  if (r.logical) return r.readTexture;
  const uint32_t mips = r.def ? std::max(r.def->mipLevels, 1u) : 1;
  const uint32_t base = state ? state->baseLevel : b.baseMipLevel;
  const uint32_t last = state ? std::min(state->maxLevel, mips - 1) : mips - 1;
  const rhi::ComponentMapping swizzle = state ? componentMapping(state->swizzle) : rhi::ComponentMapping{};
  if (base == 0 && last == mips - 1 && swizzle.isIdentity()) return r.texture;
  std::string what = "'" + b.buffer + "' from level " + std::to_string(base) + " to " + std::to_string(last);
  if (base > last) throw Unsupported{"sampling " + what + " (an incomplete texture in OpenGL)"};
  if (!swizzle.isIdentity()) what += " swizzled " + state->swizzle[0] + "," + state->swizzle[1] + "," + state->swizzle[2] + "," + state->swizzle[3];
  rhi::TextureHandle& view = mipViews_[{b.buffer, base, last - base + 1, what}];
  if (!view) {
    rhi::TextureViewDesc vd;
    vd.parent = r.texture;
    vd.baseMip = base;
    vd.mipCount = last - base + 1;
    vd.swizzle = swizzle;
    vd.label = what;
    view = dev_.createTextureView(vd);
    if (!view) throw Failure{lineOf(b.loc) + ": cannot bind " + what};
  }
  return view;
}

rhi::BufferHandle ResourceSteps::tempBuffer(const void* data, size_t size, const char* label) {
  rhi::BufferDesc bd;
  bd.size = size;
  bd.initialData = data;
  bd.label = label;
  rhi::BufferHandle h = dev_.createBuffer(bd);
  if (!h) throw Failure{std::string("cannot create ") + label};
  tempBuffers_.push_back(h);
  return h;
}

}  // namespace parity::harness::script::runner
