// What a console can run at all (platforms/common/capabilities.h): one real pipeline per row of
// the capability tables and per format use, created and drawn or dispatched through a
// PlatformDevice over the host on every platform and both backends. Each raises its row's code
// on the platforms that lack it (W_CAP_OPTIONAL where the platform only allows it) and nothing
// on the reference platform, nor on the platforms that have it.
//
// Two rows cannot be exceeded through the RHI, whose own limits are within every console's:
// colour targets (rhi::kMaxColorTargets, 4, is ps3's and x360's limit) and samples (1 or 4, the
// most every console has). For them the test checks that the RHI's limit is within the row, so
// that a technique cannot need more than the row allows, and their rule still runs on every
// pipeline (dx10's optional multisampling is its warning).
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "platforms/common/capabilities.h"
#include "platforms/platform_device.h"
#include "test_support.h"

using namespace parity;
using namespace parity::platforms;

namespace {

using Codes = std::set<std::string>;
constexpr PlatformId kRef = PlatformId::Reference, kDx10 = PlatformId::Dx10, kPs3 = PlatformId::Ps3,
                     kX360 = PlatformId::X360;

const char* kFullScreenVs = R"(#version 450
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
})";

std::string computeShader(const std::string& localSize, const std::string& declarations, const std::string& body) {
  return "#version 450\nlayout(" + localSize + ") in;\nlayout(std430, binding = 0) buffer A { uint a[]; };\n" +
         declarations + "\nvoid main() {\n  a[gl_LocalInvocationIndex] = gl_LocalInvocationIndex;\n" + body + "\n}\n";
}

// One dispatch of `glsl`, its storage buffers at bindings 0 and (when `second`) 1, a storage
// image at 2 (when `image`).
void dispatch(rhi::Device& dev, const std::string& glsl, bool second = false, bool image = false) {
  rhi::ComputePipelineDesc d;
  d.computeShader = test::makeShader(dev, rhi::ShaderStage::Compute, glsl);
  d.label = "needs";
  rhi::ComputePipelineHandle pipeline = dev.createComputePipeline(d);
  rhi::BufferDesc bd;
  bd.size = 8192;
  rhi::BufferHandle a = dev.createBuffer(bd), b = dev.createBuffer(bd);
  rhi::TextureDesc td;
  td.width = td.height = 8;
  td.usage = rhi::TextureUsage_Storage | rhi::TextureUsage_Sampled;
  td.label = "storage image";
  rhi::TextureHandle img = dev.createTexture(td);
  std::vector<rhi::ResourceBinding> bindings;
  bindings.push_back({.binding = 0, .kind = rhi::BindingKind::StorageBuffer, .buffer = a});
  if (second) bindings.push_back({.binding = 1, .kind = rhi::BindingKind::StorageBuffer, .buffer = b});
  if (image) bindings.push_back({.binding = 2, .kind = rhi::BindingKind::StorageTexture, .texture = img});
  dev.setComputePipeline(pipeline);
  dev.setBindings(bindings);
  dev.dispatch(1);
  dev.submit();
  dev.destroy(pipeline);
  dev.destroy(d.computeShader);
  dev.destroy(a);
  dev.destroy(b);
  dev.destroy(img);
}

// One full-screen draw. Everything a row needs is a field; the defaults draw a plain RGBA8
// target with nothing else.
struct Draw {
  std::string vertex = kFullScreenVs, fragment;
  std::string geometry, tessControl, tessEvaluation;
  std::vector<rhi::Format> colors = {rhi::Format::RGBA8};
  uint32_t width = 80, height = 48, samples = 1;
  rhi::Format depth = rhi::Format::Undefined;
  bool blend = false;
  // Textures read by the shaders: binding 0 an array of `textureArray`, binding 1 one more when
  // `extraTexture`; their format, and whether their sampler filters.
  uint32_t textureArray = 0;
  bool extraTexture = false;
  rhi::Format textureFormat = rhi::Format::RGBA8;
  bool linear = false;
  bool storageBuffer = false;  // a storage buffer at binding 2
};

void draw(rhi::Device& dev, const Draw& d) {
  std::vector<rhi::ShaderHandle> shaders;
  auto shader = [&](rhi::ShaderStage stage, const std::string& glsl) {
    if (glsl.empty()) return rhi::ShaderHandle{};
    shaders.push_back(test::makeShader(dev, stage, glsl));
    return shaders.back();
  };
  rhi::PipelineDesc p;
  p.vertexShader = shader(rhi::ShaderStage::Vertex, d.vertex);
  p.fragmentShader = shader(rhi::ShaderStage::Fragment, d.fragment);
  p.geometryShader = shader(rhi::ShaderStage::Geometry, d.geometry);
  p.tessControlShader = shader(rhi::ShaderStage::TessControl, d.tessControl);
  p.tessEvaluationShader = shader(rhi::ShaderStage::TessEvaluation, d.tessEvaluation);
  if (!d.tessControl.empty()) {
    p.topology = rhi::PrimitiveTopology::Patches;
    p.patchControlPoints = 3;
  }
  std::vector<rhi::TextureHandle> textures;
  rhi::PassDesc pass;
  pass.label = "needs";
  for (size_t i = 0; i < d.colors.size(); ++i) {
    rhi::TextureDesc td;
    td.format = d.colors[i];
    td.width = d.width;
    td.height = d.height;
    td.samples = d.samples;
    td.label = "target" + std::to_string(i);
    textures.push_back(dev.createTexture(td));
    pass.colors[i].texture = textures.back();
    p.colorTargets[i].format = d.colors[i];
    if (d.blend) {
      p.colorTargets[i].blend.enabled = true;
      p.colorTargets[i].blend.srcColor = p.colorTargets[i].blend.dstColor = rhi::BlendFactor::One;
    }
  }
  p.colorTargetCount = uint32_t(d.colors.size());
  if (d.depth != rhi::Format::Undefined) {
    rhi::TextureDesc td;
    td.format = d.depth;
    td.width = d.width;
    td.height = d.height;
    td.samples = d.samples;
    td.label = "depth";
    textures.push_back(dev.createTexture(td));
    pass.depthStencil.texture = textures.back();
    p.depthStencilFormat = d.depth;
    p.depthStencil.depthCompare = rhi::CompareOp::Less;
    p.depthStencil.depthWrite = true;
  }
  p.samples = d.samples;
  p.label = "needs";
  rhi::PipelineHandle pipeline = dev.createPipeline(p);
  std::vector<rhi::ResourceBinding> bindings;
  rhi::SamplerDesc sd;
  if (d.linear) sd.minFilter = sd.magFilter = rhi::Filter::Linear;
  rhi::SamplerHandle sampler = dev.createSampler(sd);
  for (uint32_t i = 0; i < d.textureArray + (d.extraTexture ? 1 : 0); ++i) {
    rhi::TextureDesc td;
    td.format = d.textureFormat;
    td.width = td.height = 4;
    td.usage = rhi::TextureUsage_Sampled;
    td.label = "texture" + std::to_string(i);
    textures.push_back(dev.createTexture(td));
    const bool extra = i == d.textureArray;
    bindings.push_back({.binding = extra ? 1u : 0u, .arrayElement = extra ? 0u : i,
                        .kind = rhi::BindingKind::SampledTexture, .texture = textures.back(), .sampler = sampler});
  }
  rhi::BufferDesc bd;
  bd.size = 256;
  rhi::BufferHandle buffer = dev.createBuffer(bd);
  if (d.storageBuffer) bindings.push_back({.binding = 2, .kind = rhi::BindingKind::StorageBuffer, .buffer = buffer});
  dev.beginPass(pass);
  dev.setPipeline(pipeline);
  if (!bindings.empty()) dev.setBindings(bindings);
  dev.draw(3);
  dev.endPass();
  dev.submit();
  dev.destroy(pipeline);
  dev.destroy(sampler);
  dev.destroy(buffer);
  for (rhi::TextureHandle t : textures) dev.destroy(t);
  for (rhi::ShaderHandle s : shaders) dev.destroy(s);
}

const char* kOut = "layout(location = 0) out vec4 o;\n";

std::string fragment(const std::string& declarations, const std::string& value) {
  return std::string("#version 450\n") + kOut + declarations + "\nvoid main() { o = " + value + "; }\n";
}

// A vertex shader reading `count` textures of binding 0 into its position.
std::string vertexReading(uint32_t count) {
  return "#version 450\nlayout(binding = 0) uniform sampler2D t[" + std::to_string(count) +
         "];\nvoid main() {\n  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);\n  float s = 0.0;\n"
         "  for (int i = 0; i < " + std::to_string(count) + "; ++i) s += textureLod(t[i], vec2(0.5), 0.0).x;\n"
         "  gl_Position = vec4(p * 2.0 - 1.0, s * 0.0, 1.0);\n}\n";
}

struct Need {
  std::string name;
  std::string feature;  // a DeviceInfo feature the host needs for it ("" none)
  std::function<void(rhi::Device&)> calls;
  std::map<PlatformId, Codes> codes;  // the E_CAP_ and W_CAP_ codes per platform (absent: none)
};

const Codes kNoCompute = {"E_CAP_COMPUTE"};

std::vector<Need> needs() {
  auto dx10Compute = [](const std::string& code) { return Codes{"W_CAP_OPTIONAL", code}; };
  return {
      {"compute", "",
       [](rhi::Device& d) { dispatch(d, computeShader("local_size_x = 64", "", "")); },
       {{kPs3, kNoCompute}, {kX360, kNoCompute}, {kDx10, {"W_CAP_OPTIONAL"}}}},
      {"compute invocations", "",
       [](rhi::Device& d) { dispatch(d, computeShader("local_size_x = 1024", "", "")); },
       {{kPs3, kNoCompute}, {kX360, kNoCompute}, {kDx10, dx10Compute("E_CAP_COMPUTE_INVOCATIONS")}}},
      {"compute workgroup depth", "",
       [](rhi::Device& d) { dispatch(d, computeShader("local_size_x = 8, local_size_y = 8, local_size_z = 2", "", "")); },
       {{kPs3, kNoCompute}, {kX360, kNoCompute}, {kDx10, dx10Compute("E_CAP_COMPUTE_WORKGROUP_DEPTH")}}},
      {"compute shared memory", "",
       [](rhi::Device& d) {
         dispatch(d, computeShader("local_size_x = 64", "shared float s[5000];",
                                   "  s[gl_LocalInvocationIndex * 64u] = 1.0;\n  barrier();\n  a[0] = uint(s[64]);"));
       },
       {{kPs3, kNoCompute}, {kX360, kNoCompute}, {kDx10, dx10Compute("E_CAP_COMPUTE_SHARED_MEMORY")}}},
      {"compute atomics", "",
       [](rhi::Device& d) { dispatch(d, computeShader("local_size_x = 64", "", "  atomicAdd(a[1000], 1u);")); },
       {{kPs3, kNoCompute}, {kX360, kNoCompute}, {kDx10, dx10Compute("E_CAP_COMPUTE_ATOMICS")}}},
      {"compute storage buffers", "",
       [](rhi::Device& d) {
         dispatch(d,
                  computeShader("local_size_x = 64", "layout(std430, binding = 1) buffer B { uint b[]; };",
                                "  b[gl_LocalInvocationIndex] = 1u;"),
                  true);
       },
       {{kPs3, kNoCompute}, {kX360, kNoCompute}, {kDx10, dx10Compute("E_CAP_COMPUTE_STORAGE_BUFFERS")}}},
      {"compute storage images", "",
       [](rhi::Device& d) {
         dispatch(d,
                  computeShader("local_size_x = 64", "layout(binding = 2, rgba8) uniform writeonly image2D img;",
                                "  imageStore(img, ivec2(gl_LocalInvocationIndex % 8u, 0), vec4(1.0));"),
                  false, true);
       },
       {{kPs3, kNoCompute}, {kX360, kNoCompute}, {kDx10, dx10Compute("E_CAP_COMPUTE_STORAGE_IMAGES")}}},
      // RHI limit 4 = the consoles' (see the comment at the top): four targets pass everywhere.
      {"colour targets", "",
       [](rhi::Device& d) {
         Draw w;
         w.colors.assign(rhi::kMaxColorTargets, rhi::Format::RGBA8);
         w.fragment = "#version 450\nlayout(location = 0) out vec4 o0;\nlayout(location = 1) out vec4 o1;\n"
                      "layout(location = 2) out vec4 o2;\nlayout(location = 3) out vec4 o3;\n"
                      "void main() { o0 = o1 = o2 = o3 = vec4(0.5); }\n";
         draw(d, w);
       },
       {}},
      {"fragment textures", "",
       [](rhi::Device& d) {
         Draw w;
         w.textureArray = 16;
         w.extraTexture = true;
         w.fragment = fragment(
             "layout(binding = 0) uniform sampler2D t[16];\nlayout(binding = 1) uniform sampler2D u;\n"
             "vec4 sum() { vec4 s = texture(u, vec2(0.5)); for (int i = 0; i < 16; ++i) s += texture(t[i], vec2(0.5)); "
             "return s; }",
             "sum()");
         draw(d, w);
       },
       {{kPs3, {"E_CAP_FRAGMENT_TEXTURES"}}, {kX360, {"E_CAP_FRAGMENT_TEXTURES"}}}},
      // R32F: every console fetches it in a vertex shader, so only the count is wrong.
      {"vertex textures", "",
       [](rhi::Device& d) {
         Draw w;
         w.textureArray = 5;
         w.textureFormat = rhi::Format::R32F;
         w.vertex = vertexReading(5);
         w.fragment = fragment("", "vec4(1.0)");
         draw(d, w);
       },
       {{kPs3, {"E_CAP_VERTEX_TEXTURES"}}, {kX360, {"E_CAP_VERTEX_TEXTURES"}}}},
      {"interpolators", "",
       [](rhi::Device& d) {
         Draw w;
         w.vertex = "#version 450\nlayout(location = 0) out vec4 v[17];\nvoid main() {\n"
                    "  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);\n"
                    "  for (int i = 0; i < 17; ++i) v[i] = vec4(p, float(i), 1.0);\n"
                    "  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);\n}\n";
         w.fragment = fragment("layout(location = 0) in vec4 v[17];\n"
                               "vec4 sum() { vec4 s = vec4(0.0); for (int i = 0; i < 17; ++i) s += v[i]; return s; }",
                               "sum()");
         draw(d, w);
       },
       {{kPs3, {"E_CAP_INTERPOLATORS"}}, {kX360, {"E_CAP_INTERPOLATORS"}}, {kDx10, {"E_CAP_INTERPOLATORS"}}}},
      // 4x is the most the RHI draws and every console has it; dx10 only allows it.
      {"multisampling", "",
       [](rhi::Device& d) {
         Draw w;
         w.samples = 4;
         w.fragment = fragment("", "vec4(0.5)");
         draw(d, w);
       },
       {{kDx10, {"W_CAP_OPTIONAL"}}}},
      {"geometry shaders", "geometryShader",
       [](rhi::Device& d) {
         Draw w;
         w.geometry = "#version 450\nlayout(triangles) in;\nlayout(triangle_strip, max_vertices = 3) out;\n"
                      "void main() { for (int i = 0; i < 3; ++i) { gl_Position = gl_in[i].gl_Position; EmitVertex(); } "
                      "EndPrimitive(); }\n";
         w.fragment = fragment("", "vec4(0.5)");
         draw(d, w);
       },
       {{kPs3, {"E_CAP_GEOMETRY_SHADERS"}}, {kX360, {"E_CAP_GEOMETRY_SHADERS"}}}},
      {"tessellation shaders", "tessellationShader",
       [](rhi::Device& d) {
         Draw w;
         w.tessControl = "#version 450\nlayout(vertices = 3) out;\nvoid main() {\n"
                         "  gl_out[gl_InvocationID].gl_Position = gl_in[gl_InvocationID].gl_Position;\n"
                         "  gl_TessLevelInner[0] = 1.0;\n  gl_TessLevelOuter[0] = gl_TessLevelOuter[1] = "
                         "gl_TessLevelOuter[2] = 1.0;\n}\n";
         w.tessEvaluation = "#version 450\nlayout(triangles) in;\nvoid main() {\n"
                            "  gl_Position = gl_TessCoord.x * gl_in[0].gl_Position + gl_TessCoord.y * "
                            "gl_in[1].gl_Position + gl_TessCoord.z * gl_in[2].gl_Position;\n}\n";
         w.fragment = fragment("", "vec4(0.5)");
         draw(d, w);
       },
       {{kPs3, {"E_CAP_TESSELLATION_SHADERS"}},
        {kX360, {"E_CAP_TESSELLATION_SHADERS"}},
        {kDx10, {"E_CAP_TESSELLATION_SHADERS"}}}},
      {"graphics storage writes", "fragmentStoresAndAtomics",
       [](rhi::Device& d) {
         Draw w;
         w.storageBuffer = true;
         w.fragment = "#version 450\nlayout(location = 0) out vec4 o;\n"
                      "layout(std430, binding = 2) buffer B { uint b[]; };\n"
                      "void main() { b[0] = 1u; o = vec4(0.5); }\n";
         draw(d, w);
       },
       {{kPs3, {"E_CAP_GRAPHICS_STORAGE_WRITES"}},
        {kX360, {"E_CAP_GRAPHICS_STORAGE_WRITES"}},
        {kDx10, {"E_CAP_GRAPHICS_STORAGE_WRITES"}}}},
      // Four RGBA8 targets of 1280x720: 4 x 3.5 MiB (in 80x16 tiles) bound at once, beyond EDRAM.
      {"EDRAM bytes", "",
       [](rhi::Device& d) {
         Draw w;
         w.colors.assign(4, rhi::Format::RGBA8);
         w.width = 1280;
         w.height = 720;
         w.fragment = "#version 450\nlayout(location = 0) out vec4 o0;\nlayout(location = 1) out vec4 o1;\n"
                      "layout(location = 2) out vec4 o2;\nlayout(location = 3) out vec4 o3;\n"
                      "void main() { o0 = o1 = o2 = o3 = vec4(0.5); }\n";
         draw(d, w);
       },
       {{kX360, {"E_CAP_EDRAM_BYTES"}}}},
      // Formats, per use.
      {"render format", "",
       [](rhi::Device& d) {
         Draw w;
         w.colors = {rhi::Format::R8};
         w.depth = rhi::Format::D32F;
         w.fragment = fragment("", "vec4(0.5)");
         draw(d, w);
       },
       {{kPs3, {"E_CAP_RENDER_FORMAT"}}, {kX360, {"E_CAP_RENDER_FORMAT"}}}},
      {"blend format", "",
       [](rhi::Device& d) {
         Draw w;
         w.colors = {rhi::Format::RGBA16F};
         w.blend = true;
         w.fragment = fragment("", "vec4(0.5)");
         draw(d, w);
       },
       {{kX360, {"E_CAP_BLEND_FORMAT"}}}},
      {"filter format", "",
       [](rhi::Device& d) {
         Draw w;
         w.textureArray = 1;
         w.textureFormat = rhi::Format::R32F;
         w.linear = true;
         w.fragment = fragment("layout(binding = 0) uniform sampler2D t[1];", "texture(t[0], vec2(0.5))");
         draw(d, w);
       },
       {{kPs3, {"E_CAP_FILTER_FORMAT"}}, {kX360, {"E_CAP_FILTER_FORMAT"}}, {kDx10, {"W_CAP_OPTIONAL"}}}},
      {"vertex fetch format", "",
       [](rhi::Device& d) {
         Draw w;
         w.textureArray = 1;
         w.vertex = vertexReading(1);
         w.fragment = fragment("", "vec4(1.0)");
         draw(d, w);
       },
       {{kPs3, {"E_CAP_VERTEX_FETCH_FORMAT"}}, {kX360, {"E_CAP_VERTEX_FETCH_FORMAT"}}}},
      {"multisample format", "",
       [](rhi::Device& d) {
         Draw w;
         w.colors = {rhi::Format::R8};
         w.samples = 4;
         w.fragment = fragment("", "vec4(0.5)");
         draw(d, w);
       },
       {{kX360, {"E_CAP_RENDER_FORMAT", "E_CAP_MULTISAMPLE_FORMAT"}}, {kDx10, {"W_CAP_OPTIONAL"}}}},
  };
}

Codes capabilityCodes(const DiagnosticList& list) {
  Codes codes;
  for (const Diagnostic& d : list.all())
    if (d.code.rfind("E_CAP_", 0) == 0 || d.code.rfind("W_CAP_", 0) == 0) codes.insert(d.code);
  return codes;
}

class PlatformCapabilities : public ::testing::TestWithParam<std::string> {};

TEST_P(PlatformCapabilities, EachRowFiresWhereThePlatformLacksItAndNeverOnTheReference) {
  auto host = test::makeDevice(GetParam());
  if (!host) return;
  const std::vector<std::string>& features = host->info().features;
  for (const Need& need : needs()) {
    SCOPED_TRACE(need.name);
    if (!need.feature.empty() && std::find(features.begin(), features.end(), need.feature) == features.end()) {
      ADD_FAILURE() << "the host lacks " << need.feature << ": the row is not tested";
      continue;
    }
    for (PlatformId platform : {kRef, kDx10, kPs3, kX360}) {
      PlatformDevice device(*host, platform, {});
      need.calls(device);
      const DiagnosticList found = device.diagnostics();
      auto want = need.codes.find(platform);
      EXPECT_EQ(capabilityCodes(found), want == need.codes.end() ? Codes{} : want->second)
          << platformName(platform) << ":\n" << found.format();
      // The error names the capability and where it fired.
      for (const Diagnostic& d : found.all())
        if (d.code.rfind("E_CAP_", 0) == 0) {
          // A pass's budget fires as it begins, before any pipeline; a dispatch is in no pass.
          if (d.code != "E_CAP_EDRAM_BYTES") {
            EXPECT_EQ(d.pipeline, "needs") << d.code;
          }
          if (d.code.find("COMPUTE") == std::string::npos) {
            EXPECT_EQ(d.pass, "needs") << d.code;
          }
        }
    }
  }
}

// The rows the RHI cannot exceed (see the top): its own limits are within every platform's, so a
// technique cannot need more of them than a console has.
TEST(PlatformCapabilityTables, RowsBeyondTheRhiLimitsCannotBeExceeded) {
  for (PlatformId platform : {kRef, kDx10, kPs3, kX360}) {
    const platforms::PlatformCapabilities& caps = platformCapabilities(platform);
    EXPECT_TRUE(hasOneRowPerCapability(caps.rows));
    const CapabilityRow& mrt = caps.row(Capability::ColorTargets);
    EXPECT_TRUE(mrt.support == Support::Guaranteed && (mrt.limit == 0 || mrt.limit >= rhi::kMaxColorTargets))
        << platformName(platform);
    const CapabilityRow& msaa = caps.row(Capability::Multisampling);
    EXPECT_TRUE(msaa.support != Support::None && (msaa.limit == 0 || msaa.limit >= 4)) << platformName(platform);
  }
}

// What a technique on a platform branches on: compute only where guaranteed, samples only as many
// as guaranteed.
TEST(PlatformCapabilityTables, PublishedCapabilitiesAreTheGuaranteedPart) {
  rhi::Capabilities host;
  host.compute = true;
  host.maxSamples = 4;
  EXPECT_TRUE(publishedCapabilities(kRef, host).compute);
  EXPECT_EQ(publishedCapabilities(kRef, host).maxSamples, 4u);
  for (PlatformId console : {kDx10, kPs3, kX360}) EXPECT_FALSE(publishedCapabilities(console, host).compute);
  EXPECT_EQ(publishedCapabilities(kDx10, host).maxSamples, 1u) << "dx10's multisampling is optional";
  EXPECT_EQ(publishedCapabilities(kPs3, host).maxSamples, 4u);
  EXPECT_EQ(publishedCapabilities(kX360, host).maxSamples, 4u);
  host.compute = false;
  EXPECT_FALSE(publishedCapabilities(kRef, host).compute) << "never more than the host has";
}

INSTANTIATE_TEST_SUITE_P(Backends, PlatformCapabilities, ::testing::ValuesIn(test::allBackends()),
                         test::BackendName());

}  // namespace
