// Descriptor arrays (rhi.h's binding model: an array of resources at one binding, each element
// bound by ResourceBinding::arrayElement) on every backend. Each shader reads or writes every
// element with a constant index and one element with a dynamically uniform index (a push
// constant), and puts a binding after the array, which on GL moves to the next free point
// (gl_pipeline.cpp). The results are exact integers.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "tests/test_support.h"

namespace parity::rhi {
namespace {

using parity::test::allBackends;
using parity::test::BackendName;

class RhiDescriptorArraysTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    dev = parity::test::makeDevice(GetParam());
    if (!dev) GTEST_SKIP() << "backend " << GetParam() << " unavailable";
  }

  BufferHandle buffer(size_t size, const void* data = nullptr) {
    BufferDesc d;
    d.size = size;
    d.initialData = data;
    d.label = "descriptor arrays";
    BufferHandle b = dev->createBuffer(d);
    EXPECT_TRUE(b);
    return b;
  }
  TextureHandle texture(Format format, const void* texel, uint32_t usage) {
    TextureDesc d;
    d.format = format;
    d.usage = usage;
    d.initialData = texel;
    d.label = "descriptor arrays";
    TextureHandle t = dev->createTexture(d);
    EXPECT_TRUE(t);
    return t;
  }
  static ResourceBinding bound(uint32_t binding, uint32_t element, BindingKind kind) {
    ResourceBinding r;
    r.binding = binding;
    r.arrayElement = element;
    r.kind = kind;
    return r;
  }
  // Runs `cs` once (one invocation) with `bindings`, `index` pushed as its dynamic index, and
  // returns the first `count` words of `out`.
  std::vector<uint32_t> run(const char* cs, const std::vector<ResourceBinding>& bindings, uint32_t index,
                            BufferHandle out, size_t count) {
    ComputePipelineDesc d;
    d.computeShader = parity::test::makeShader(*dev, ShaderStage::Compute, cs);
    d.label = "descriptor arrays";
    ComputePipelineHandle p = dev->createComputePipeline(d);
    EXPECT_TRUE(p);
    dev->setComputePipeline(p);
    dev->setBindings(bindings);
    dev->pushConstants(&index, sizeof index);
    dev->dispatch(1);
    std::vector<uint8_t> bytes = dev->readBuffer(out, 0, count * 4);
    std::vector<uint32_t> words(count);
    if (bytes.size() == count * 4) std::memcpy(words.data(), bytes.data(), bytes.size());
    return words;
  }

  std::unique_ptr<Device> dev;
};

// Two blocks declared at one binding alias one buffer (VkRunner's two-ubo files): each reads
// its own members of the same bytes (blocks of different kinds at one binding: E_SHADER_REFLECTION).
TEST_P(RhiDescriptorArraysTest, BlocksAtOneBindingAliasOneBuffer) {
  const char* cs = R"(#version 450
layout(local_size_x = 1) in;
layout(set = 0, binding = 0, std140) uniform A { uvec4 first; } a;
layout(set = 0, binding = 0, std140) uniform B { layout(offset = 16) uvec4 second; } b;
layout(set = 0, binding = 1) buffer Out { uint o[2]; } out_;
void main() { out_.o[0] = a.first.y; out_.o[1] = b.second.z; })";
  const uint32_t data[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  BufferHandle u = buffer(sizeof data, data), out = buffer(8);
  ResourceBinding ub = bound(0, 0, BindingKind::UniformBuffer), ob = bound(1, 0, BindingKind::StorageBuffer);
  ub.buffer = u;
  ob.buffer = out;
  EXPECT_EQ(run(cs, {ub, ob}, 0, out, 2), (std::vector<uint32_t>{2, 7}));
}

TEST_P(RhiDescriptorArraysTest, UniformBufferArray) {
  const char* cs = R"(#version 450
layout(local_size_x = 1) in;
layout(push_constant) uniform PC { uint index; } pc;
layout(set = 0, binding = 0) uniform U { uvec4 v; } u[3];
layout(set = 0, binding = 1) uniform V { uint w; } v;
layout(set = 0, binding = 2) buffer Out { uint o[5]; } out_;
void main() {
  out_.o[0] = u[0].v.x;
  out_.o[1] = u[1].v.x;
  out_.o[2] = u[2].v.x;
  out_.o[3] = u[pc.index].v.y;
  out_.o[4] = v.w;
})";
  BufferHandle out = buffer(20);
  std::vector<ResourceBinding> bindings;
  for (uint32_t e = 0; e < 3; ++e) {
    const uint32_t v[4] = {10 + e, 20 + e, 0, 0};
    ResourceBinding r = bound(0, e, BindingKind::UniformBuffer);
    r.buffer = buffer(sizeof v, v);
    bindings.push_back(r);
  }
  const uint32_t w[4] = {55, 0, 0, 0};
  ResourceBinding plain = bound(1, 0, BindingKind::UniformBuffer);  // on GL at point 3, after u's 0..2
  plain.buffer = buffer(sizeof w, w);
  bindings.push_back(plain);
  ResourceBinding o = bound(2, 0, BindingKind::StorageBuffer);
  o.buffer = out;
  bindings.push_back(o);
  EXPECT_EQ(run(cs, bindings, 2, out, 5), (std::vector<uint32_t>{10, 11, 12, 22, 55}));
  // Elements are bound one by one: replacing element 1 keeps 0 and 2.
  const uint32_t replaced[4] = {77, 88, 0, 0};
  ResourceBinding r = bound(0, 1, BindingKind::UniformBuffer);
  r.buffer = buffer(sizeof replaced, replaced);
  dev->setBindings({&r, 1});
  dev->dispatch(1);
  std::vector<uint8_t> bytes = dev->readBuffer(out, 0, 20);
  std::vector<uint32_t> words(5);
  if (bytes.size() == 20) std::memcpy(words.data(), bytes.data(), 20);
  EXPECT_EQ(words, (std::vector<uint32_t>{10, 77, 12, 22, 55}));
}

TEST_P(RhiDescriptorArraysTest, StorageBufferArray) {
  // Two arrays next to each other, then a plain binding: on GL their points are 0-1, 2-4, 5.
  const char* cs = R"(#version 450
layout(local_size_x = 1) in;
layout(push_constant) uniform PC { uint index; } pc;
layout(set = 0, binding = 0) buffer A { uint v; } a[2];
layout(set = 0, binding = 1) buffer B { uint v; } b[3];
layout(set = 0, binding = 2) buffer Out { uint o[3]; } out_;
void main() {
  a[0].v = 1u;
  a[1].v = 2u;
  for (uint i = 0u; i < 3u; ++i) b[i].v = 100u + i;
  b[pc.index].v += 1000u;
  out_.o[0] = 7u;
  out_.o[1] = a[pc.index - 1u].v;
})";
  std::vector<BufferHandle> buffers;
  std::vector<ResourceBinding> bindings;
  for (uint32_t e = 0; e < 5; ++e) {
    buffers.push_back(buffer(4));
    ResourceBinding r = bound(e < 2 ? 0 : 1, e < 2 ? e : e - 2, BindingKind::StorageBuffer);
    r.buffer = buffers.back();
    bindings.push_back(r);
  }
  BufferHandle out = buffer(12);
  ResourceBinding o = bound(2, 0, BindingKind::StorageBuffer);
  o.buffer = out;
  bindings.push_back(o);
  EXPECT_EQ(run(cs, bindings, 1, out, 2), (std::vector<uint32_t>{7, 1}));
  const uint32_t expected[5] = {1, 2, 100, 1101, 102};
  for (uint32_t e = 0; e < 5; ++e) {
    std::vector<uint8_t> bytes = dev->readBuffer(buffers[e], 0, 4);
    uint32_t v = 0;
    if (bytes.size() == 4) std::memcpy(&v, bytes.data(), 4);
    EXPECT_EQ(v, expected[e]) << "buffer " << e;
  }
}

TEST_P(RhiDescriptorArraysTest, SampledTextureArrays) {
  // Combined samplers s[3] and separate textures t[2] sampled with one sampler (on GL a pair whose
  // texture is an array: one combined unit per element), then a uniform buffer after both. The
  // dynamic read is a shader of its own: Mesa 22.3's llvmpipe and lavapipe return 0 for texel
  // fetches of a sampler array that one shader indexes both dynamically and with constants.
  const std::string declarations = R"(#version 450
layout(local_size_x = 1) in;
layout(push_constant) uniform PC { uint index; } pc;
layout(set = 0, binding = 0) uniform usampler2D s[3];
layout(set = 0, binding = 1) uniform usampler2D single;
layout(set = 0, binding = 2) uniform utexture2D t[2];
layout(set = 0, binding = 3) uniform sampler smp;
layout(set = 0, binding = 4) uniform U { uint v; } u;
layout(set = 0, binding = 5) buffer Out { uint o[7]; } out_;
)";
  const std::string constant = declarations + R"(void main() {
  for (int i = 0; i < 3; ++i) out_.o[i] = texelFetch(s[i], ivec2(0), 0).r;
  out_.o[3] = texture(usampler2D(t[0], smp), vec2(0.5)).r;
  out_.o[4] = texture(usampler2D(t[1], smp), vec2(0.5)).r;
  out_.o[5] = u.v;
  out_.o[6] = texelFetch(single, ivec2(0), 0).r;
})";
  const std::string dynamic = declarations + R"(void main() {
  out_.o[0] = texelFetch(s[pc.index], ivec2(0), 0).r;
  out_.o[1] = texture(usampler2D(t[pc.index - 1u], smp), vec2(0.5)).r;
})";
  std::vector<ResourceBinding> bindings;
  for (uint32_t e = 0; e < 5; ++e) {
    const uint32_t texel = 40 + e;
    ResourceBinding r = bound(e < 3 ? 0 : 2, e < 3 ? e : e - 3, e < 3 ? BindingKind::SampledTexture : BindingKind::SeparateTexture);
    r.texture = texture(Format::R32_UINT, &texel, TextureUsage_Sampled);
    bindings.push_back(r);
  }
  const uint32_t texel = 50;
  ResourceBinding single = bound(1, 0, BindingKind::SampledTexture);  // on GL unit 3, after s's 0..2
  single.texture = texture(Format::R32_UINT, &texel, TextureUsage_Sampled);
  bindings.push_back(single);
  bindings.push_back(bound(3, 0, BindingKind::SeparateSampler));
  const uint32_t uniform[4] = {99, 0, 0, 0};
  ResourceBinding u = bound(4, 0, BindingKind::UniformBuffer);
  u.buffer = buffer(sizeof uniform, uniform);
  bindings.push_back(u);
  BufferHandle out = buffer(28);
  ResourceBinding o = bound(5, 0, BindingKind::StorageBuffer);
  o.buffer = out;
  bindings.push_back(o);
  EXPECT_EQ(run(constant.c_str(), bindings, 0, out, 7), (std::vector<uint32_t>{40, 41, 42, 43, 44, 99, 50}));
  EXPECT_EQ(run(dynamic.c_str(), bindings, 2, out, 2), (std::vector<uint32_t>{42, 44}));
}

TEST_P(RhiDescriptorArraysTest, StorageTextureArray) {
  const char* cs = R"(#version 450
layout(local_size_x = 1) in;
layout(push_constant) uniform PC { uint index; } pc;
layout(set = 0, binding = 0, r32ui) uniform uimage2D images[2];
layout(set = 0, binding = 1, r32ui) uniform uimage2D single;
layout(set = 0, binding = 2) buffer Out { uint o[1]; } out_;
void main() {
  imageStore(images[0], ivec2(0), uvec4(5u));
  imageStore(images[1], ivec2(0), uvec4(6u));
  imageStore(single, ivec2(0), uvec4(7u));
  out_.o[0] = imageLoad(images[pc.index], ivec2(0)).r;
})";
  const uint32_t zero = 0;
  std::vector<TextureHandle> images;
  std::vector<ResourceBinding> bindings;
  for (uint32_t e = 0; e < 3; ++e) {  // images[0], images[1], single (on GL image unit 2)
    images.push_back(texture(Format::R32_UINT, &zero, TextureUsage_Sampled | TextureUsage_Storage));
    ResourceBinding r = bound(e < 2 ? 0 : 1, e < 2 ? e : 0, BindingKind::StorageTexture);
    r.texture = images.back();
    bindings.push_back(r);
  }
  BufferHandle out = buffer(4);
  ResourceBinding o = bound(2, 0, BindingKind::StorageBuffer);
  o.buffer = out;
  bindings.push_back(o);
  EXPECT_EQ(run(cs, bindings, 1, out, 1), (std::vector<uint32_t>{6}));
  for (uint32_t e = 0; e < 3; ++e) {
    std::vector<uint8_t> texel = dev->readTexture(images[e]);
    uint32_t v = 0;
    if (texel.size() == 4) std::memcpy(&v, texel.data(), 4);
    EXPECT_EQ(v, 5 + e) << "image " << e;
  }
}

INSTANTIATE_TEST_SUITE_P(Rhi, RhiDescriptorArraysTest, ::testing::ValuesIn(allBackends()), BackendName());

}  // namespace
}  // namespace parity::rhi
