// piglit's and VkRunner's .shader_test files (harness/scripts/shader_test_parser.h): what each command
// becomes in the script model, errors naming the line, unsupported constructs named. Running
// them is covered by tests/scripts/shader_test (the library) and by the peer-suite floors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "harness/scripts/runner.h"
#include "harness/scripts/script.h"
#include "harness/scripts/shader_test_parser.h"

using namespace parity::harness::script;

namespace {

const Command* findCommand(const Script& s, Command::Kind kind, size_t nth = 0) {
  for (const Command& c : s.commands)
    if (c.kind == kind && nth-- == 0) return &c;
  return nullptr;
}

bool hasUnsupported(const Script& s, const std::string& feature) {
  return std::any_of(s.unsupported.begin(), s.unsupported.end(),
                     [&](const Unsupported& u) { return u.feature.find(feature) != std::string::npos; });
}

const char* kPiglit = R"([require]
GLSL >= 1.50
GL_ARB_gpu_shader5
SIZE 100 50

[vertex shader passthrough]

[fragment shader]
uniform vec4 color;
void main() { gl_FragColor = color; }

[test]
clear color 0.0 1.0 0.0 1.0
clear
uniform vec4 color 0.25 0.5 0.75 1.0
draw rect -1 -1 2 2
probe all rgba 0.25 0.5 0.75 1.0
relative probe rgb (0.5, 1.0) (0.25, 0.5, 0.75)
draw rect ortho 10 20 30 40
)";

TEST(ShaderTestParser, PiglitCommandsBecomeScriptCommands) {
  ParseResult r = parseShaderTest(kPiglit, "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  const Script& s = r.script;
  EXPECT_TRUE(s.unsupported.empty()) << s.unsupported.front().feature;
  ASSERT_EQ(s.shaders.size(), 2u);
  EXPECT_TRUE(s.shaders[0].passthrough);
  EXPECT_TRUE(s.shaders[1].openGl);  // piglit's GLSL is OpenGL GLSL
  EXPECT_EQ(s.shaders[1].glslVersion, 150);
  const Pipeline* p = s.findPipeline("rect");
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->fbWidth, 100u);
  EXPECT_EQ(p->fbHeight, 50u);

  const Command* clear = findCommand(s, Command::Kind::ClearColor);
  ASSERT_NE(clear, nullptr);
  EXPECT_DOUBLE_EQ(clear->color[1], 255.0);  // 0..1 as Amber's 0..255
  const Command* uniform = findCommand(s, Command::Kind::SetUniform);
  ASSERT_NE(uniform, nullptr);
  EXPECT_EQ(uniform->uniform, "color");
  ASSERT_EQ(uniform->values.size(), 4u);
  EXPECT_DOUBLE_EQ(uniform->values[2].d, 0.75);

  const Command* ndc = findCommand(s, Command::Kind::DrawRect, 0);
  ASSERT_NE(ndc, nullptr);
  EXPECT_TRUE(ndc->ndc);
  EXPECT_FLOAT_EQ(ndc->w, 2.0f);
  const Command* ortho = findCommand(s, Command::Kind::DrawRect, 1);
  ASSERT_NE(ortho, nullptr);
  EXPECT_FALSE(ortho->ndc);  // window pixels
  EXPECT_FLOAT_EQ(ortho->y, 20.0f);

  const Command* all = findCommand(s, Command::Kind::ExpectProbe, 0);
  ASSERT_NE(all, nullptr);
  EXPECT_EQ(all->pw, 100u);
  EXPECT_EQ(all->ph, 50u);
  EXPECT_TRUE(all->rgba);
  EXPECT_DOUBLE_EQ(all->color[0], 0.25 * 255.0);
  ASSERT_EQ(all->tolerances.size(), 1u);
  EXPECT_NEAR(all->tolerances[0].value, 3.0 / 256.0 * 255.0, 1e-9);  // piglit's 8-bit default
  const Command* relative = findCommand(s, Command::Kind::ExpectProbe, 1);
  ASSERT_NE(relative, nullptr);
  EXPECT_FALSE(relative->rgba);
  EXPECT_EQ(relative->px, 50u);
  EXPECT_EQ(relative->py, 49u);  // 1.0 of the height: the last row
}

const char* kVkRunner = R"([require]
shaderFloat64
VK_KHR_16bit_storage

[compute shader]
#version 450
layout(local_size_x = 1) in;
void main() {}

[test]
ssbo 2:3 subdata vec2 8 1.5 2.5
push uint 4 7
uniform float 8 2.0
compute 1 2 3
probe ssbo vec2 2:3 8 ~= 1.5 2.5
tolerance 1%
probe ssbo uint 2:3 8 != 0
)";

TEST(ShaderTestParser, VkRunnerBuffersAndPushConstantsByOffset) {
  ParseResult r = parseShaderTest(kVkRunner, "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  const Script& s = r.script;
  EXPECT_FALSE(s.shaders[0].openGl);  // VkRunner's GLSL is Vulkan GLSL
  int features = 0, extensions = 0;
  for (const Requirement& q : s.requirements) {
    features += q.what == "device_feature" && q.value == "shaderFloat64";
    extensions += q.what == "device_extension" && q.value == "VK_KHR_16bit_storage";
  }
  EXPECT_EQ(features, 1);
  EXPECT_EQ(extensions, 1);

  const Buffer* ssbo = s.findBuffer("ssbo_2_3");
  ASSERT_NE(ssbo, nullptr);
  EXPECT_GE(ssbo->bytes.size(), 16u);  // sized by the write's extent
  const Pipeline* compute = s.findPipeline("compute");
  ASSERT_NE(compute, nullptr);
  bool storage = false, push = false;
  for (const Bind& b : compute->binds) {
    storage |= b.kind == BindKind::Storage && b.buffer == "ssbo_2_3" && b.set == 2 && b.binding == 3;
    push |= b.kind == BindKind::PushConstant && b.buffer == "push_constants";
  }
  EXPECT_TRUE(storage);
  EXPECT_TRUE(push);

  const Command* write = findCommand(s, Command::Kind::WriteBuffer, 0);
  ASSERT_NE(write, nullptr);
  EXPECT_EQ(write->px, 8u);
  EXPECT_EQ(write->bytes.size(), 8u);  // two floats
  const Command* pushWrite = findCommand(s, Command::Kind::WriteBuffer, 1);
  ASSERT_NE(pushWrite, nullptr);
  EXPECT_EQ(pushWrite->buffer, "push_constants");
  EXPECT_EQ(pushWrite->px, 4u);
  const Command* oldUniform = findCommand(s, Command::Kind::WriteBuffer, 2);  // VkRunner's older spelling
  ASSERT_NE(oldUniform, nullptr);
  EXPECT_EQ(oldUniform->buffer, "push_constants");

  const Command* dispatch = findCommand(s, Command::Kind::Compute);
  ASSERT_NE(dispatch, nullptr);
  EXPECT_EQ(dispatch->groups[2], 3u);
  const Command* fuzzy = findCommand(s, Command::Kind::ExpectValues, 0);
  ASSERT_NE(fuzzy, nullptr);
  EXPECT_TRUE(fuzzy->valueTypeGiven);
  EXPECT_EQ(fuzzy->valueType.layout.fields.size(), 2u);
  EXPECT_EQ(fuzzy->comparator, Comparator::FuzzyEq);
  EXPECT_DOUBLE_EQ(fuzzy->tolerances[0].value, 0.01);  // VkRunner's default
  const Command* ne = findCommand(s, Command::Kind::ExpectValues, 1);
  ASSERT_NE(ne, nullptr);
  EXPECT_EQ(ne->comparator, Comparator::Ne);
}

TEST(ShaderTestParser, DescriptorArrayElements) {
  // VkRunner's SET:BINDING:ELEMENT binds a buffer of its own to one element; piglit's
  // `ubo array index` picks the element of an array of blocks that `uniform` lines set.
  ParseResult r = parseShaderTest(R"([vertex shader passthrough]
[fragment shader]
void main() {}
[test]
uniform ubo 0:5:1 vec4 0 1 2 3 4
uniform ubo 0:5 vec4 0 5 6 7 8
ubo array index 2
uniform vec4 block.color 1 1 1 1
)",
                                  "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.script.unsupported.empty()) << r.script.unsupported.front().feature;
  const Pipeline* p = r.script.findPipeline("rect");
  ASSERT_NE(p, nullptr);
  std::vector<std::pair<std::string, uint32_t>> ubos;
  for (const Bind& b : p->binds)
    if (b.kind == BindKind::Uniform && b.binding == 5) ubos.push_back({b.buffer, b.arrayElement});
  EXPECT_EQ(ubos, (std::vector<std::pair<std::string, uint32_t>>{{"ubo_0_5_1", 1}, {"ubo_0_5", 0}}));
  const Command* uniform = findCommand(r.script, Command::Kind::SetUniform);
  ASSERT_NE(uniform, nullptr);
  EXPECT_EQ(uniform->arrayElement, 2u);
}

TEST(ShaderTestParser, MalformedLinesAreErrorsNamingFileAndLine) {
  ParseResult r = parseShaderTest("[vertex shader passthrough]\n[fragment shader]\nvoid main() {}\n[test]\nclear\nprobe all rgba 1 0\n",
                                  "bad.shader_test");
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.error.rfind("bad.shader_test:6: error: ", 0), 0u) << r.error;
  r = parseShaderTest("[test]\ndraw arrays GL_QUADS_AND_MORE 0 4\n", "bad.shader_test");
  EXPECT_EQ(r.error.rfind("bad.shader_test:2: error: unknown primitive mode", 0), 0u) << r.error;
  r = parseShaderTest("no section at all\n", "bad.shader_test");
  EXPECT_FALSE(r.ok);
}

TEST(ShaderTestParser, ConstructsTheRunnerLacksAreNamedNotErrors) {
  ParseResult r = parseShaderTest(R"([require]
GLSL >= 1.50
GL COMPAT >= 3.1
[vertex shader passthrough]
[fragment shader]
void main() {}
[test]
texture junk 2DArray 0 (4, 4, 2)
fb tex layered 0
subuniform GL_FRAGMENT_SHADER f g
texture junk 0 (32, 32)
draw arrays GL_QUADS 0 4
)",
                                  "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(hasUnsupported(r.script, "GL COMPAT 3.1"));
  EXPECT_TRUE(hasUnsupported(r.script, "fb tex layered"));
  EXPECT_TRUE(hasUnsupported(r.script, "subuniform"));
  EXPECT_TRUE(hasUnsupported(r.script, "texture junk"));
  EXPECT_TRUE(hasUnsupported(r.script, "draw arrays GL_QUADS"));
}

// GLSL extensions glslang compiles for both backends are requirements met; other GL_* extensions
// (vendor ones, API-only ones) are named.
// A [require]d OpenGL extension is the device's to offer: a device whose driver compiles OpenGL
// GLSL answers from its context's extensions, another runs the port, which exists for extensions
// core in GL 4.5 and for GLSL built-ins glslang knows.
TEST(ShaderTestParser, RequiredGlExtensionsAreCheckedAgainstTheDevice) {
  ParseResult r = parseShaderTest(R"([require]
GLSL >= 1.50
GL_ARB_tessellation_shader
GL_EXT_shader_integer_mix
GL_AMD_vertex_shader_layer
[vertex shader passthrough]
[fragment shader]
void main() {}
[test]
enable GL_CLIP_PLANE0
enable GL_CLIP_DISTANCE7
)",
                                  "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.script.unsupported.empty()) << r.script.unsupported.front().feature;
  parity::rhi::DeviceInfo driver;
  driver.backend = "gl";
  driver.renderer = "test renderer";
  driver.features = {"openGlGlsl"};
  driver.openGlExtensions = {"GL_ARB_tessellation_shader", "GL_EXT_shader_integer_mix"};
  EXPECT_EQ(deviceRequirementMissing(r.script, driver), "[require] GL_AMD_vertex_shader_layer (line 5) not offered by gl on test renderer");
  driver.openGlExtensions.push_back("GL_AMD_vertex_shader_layer");
  EXPECT_EQ(deviceRequirementMissing(r.script, driver), "");
  driver.openGlExtensions = {"GL_EXT_shader_integer_mix", "GL_AMD_vertex_shader_layer"};
  EXPECT_EQ(deviceRequirementMissing(r.script, driver), "[require] GL_ARB_tessellation_shader (line 3) not offered by gl on test renderer");
  parity::rhi::DeviceInfo port;
  port.backend = "vk";
  EXPECT_EQ(deviceRequirementMissing(r.script, port), "[require] GL_AMD_vertex_shader_layer (line 5): no port of its shaders for vk");
}

TEST(ShaderTestParser, TypedLimitsOfPreRasterisationAtomicCountersNeedTheirStoresAndAtomics) {
  ParseResult r = parseShaderTest(R"([require]
GLSL >= 1.40
INT GL_MAX_VERTEX_ATOMIC_COUNTER_BUFFERS >= 1
INT GL_MAX_FRAGMENT_ATOMIC_COUNTERS >= 2
GL_MAX_GEOMETRY_ATOMIC_COUNTERS >= 1
[vertex shader passthrough]
[fragment shader]
void main() {}
[test]
draw rect -1 -1 2 2
)",
                                  "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.script.unsupported.empty()) << r.script.unsupported.front().feature;
  std::vector<std::pair<std::string, int>> features;
  for (const auto& q : r.script.requirements) features.push_back({q.what + " " + q.value, q.loc.line});
  EXPECT_EQ(features, (std::vector<std::pair<std::string, int>>{{"device_feature vertexPipelineStoresAndAtomics", 3},
                                                                 {"device_feature vertexPipelineStoresAndAtomics", 5}}));
}

// `image texture N [FORMAT]` binds the texture on unit N to image unit N, in the texture's own
// format; `fb tex 2d N` draws into it. Naming a unit no texture fills is an error of the file.
TEST(ShaderTestParser, ImageUnitsAndTextureFramebuffersNameTheirTexture) {
  const std::string head = R"([require]
GLSL >= 4.30
[vertex shader passthrough]
[fragment shader]
writeonly uniform image2D img;
out vec4 color;
void main() { imageStore(img, ivec2(0), vec4(1.0)); color = vec4(0.0); }
[test]
texture rgbw 0 (8, 8)
texture rgbw 1 (4, 2) GL_RGBA32F
)";
  ParseResult r = parseShaderTest(head + "image texture 1 GL_RGBA32F\nfb tex 2d 0\nclear\nprobe all rgba 0 0 0 0\n", "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.script.unsupported.empty()) << r.script.unsupported.front().feature;
  const Buffer* unit1 = r.script.findBuffer("texture_unit_1");
  ASSERT_NE(unit1, nullptr);
  EXPECT_EQ(unit1->imageUnit, 1);
  EXPECT_EQ(unit1->type.name, "R32G32B32A32_SFLOAT");
  const Pipeline* intoTexture = r.script.findPipeline("rect into texture_unit_0");
  ASSERT_NE(intoTexture, nullptr);
  EXPECT_EQ(intoTexture->fbWidth, 8u);
  ASSERT_FALSE(r.script.commands.empty());
  const Command& probe = r.script.commands.back();
  EXPECT_EQ(probe.buffer, "texture_unit_0");
  EXPECT_EQ(probe.pw, 8u);

  ParseResult otherFormat = parseShaderTest(head + "image texture 0 GL_R32F\n", "t.shader_test");
  ASSERT_TRUE(otherFormat.ok) << otherFormat.error;
  EXPECT_TRUE(hasUnsupported(otherFormat.script, "image texture 0 GL_R32F"));
  ParseResult noTexture = parseShaderTest(head + "image texture 3\n", "t.shader_test");
  EXPECT_FALSE(noTexture.ok);
  EXPECT_EQ(noTexture.error, "t.shader_test:11: error: image texture 3: no texture command filled unit 3");
  ParseResult tooLarge = parseShaderTest(head + "texture rgbw 2DArray 3 (16384, 16384, 2)\n", "t.shader_test");
  EXPECT_FALSE(tooLarge.ok);
  EXPECT_EQ(tooLarge.error, "t.shader_test:11: error: texture of 2147483648 bytes is too large");
  ParseResult noFramebuffer = parseShaderTest(head + "fb tex 2d 2\n", "t.shader_test");
  EXPECT_FALSE(noFramebuffer.ok);
  EXPECT_EQ(noFramebuffer.error, "t.shader_test:11: error: fb tex 2d 2: no texture command filled unit 2");
}

TEST(ShaderTestParser, GeometryAndTessellationStagesJoinThePipeline) {
  ParseResult r = parseShaderTest(R"([require]
GLSL >= 1.50
GL_ARB_tessellation_shader
[vertex shader passthrough]
[tessellation control shader]
layout(vertices = 3) out;
void main() {}
[tessellation evaluation shader]
layout(triangles) in;
void main() {}
[geometry shader]
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
void main() {}
[fragment shader]
void main() {}
[vertex data]
piglit_vertex/float/2
-1 -1
 1 -1
-1  1
[test]
patch parameter vertices 3
draw arrays GL_PATCHES 0 3
)",
                                  "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.script.unsupported.empty()) << r.script.unsupported.front().feature;
  const Pipeline* p = r.script.findPipeline("arrays");
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->shaders.size(), 5u);
  EXPECT_EQ(p->patchControlPoints, 3u);
  const Shader* tcs = r.script.findShader("tessellation_control");
  ASSERT_NE(tcs, nullptr);
  EXPECT_EQ(tcs->stage, Stage::TessControl);
  const Command* draw = findCommand(r.script, Command::Kind::DrawArray);
  ASSERT_NE(draw, nullptr);
  EXPECT_EQ(draw->topology, "PATCH_LIST");
}

TEST(ShaderTestParser, PiglitTexturesAreImagesOnTheirUnit) {
  ParseResult r = parseShaderTest(R"([require]
GLSL >= 1.30
[vertex shader passthrough]
[fragment shader]
void main() {}
[test]
texture rgbw 2 (4, 2)
texparameter 2D mag linear
texture checkerboard 0 0 (4, 4) (1.0, 0.0, 0.0, 1.0) (0.0, 0.0, 1.0, 1.0)
)",
                                  "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  const Buffer* rgbw = r.script.findBuffer("texture_unit_2");
  ASSERT_NE(rgbw, nullptr);
  EXPECT_EQ(rgbw->textureUnit, 2);
  ASSERT_EQ(rgbw->bytes.size(), 4u * 2u * 4u);
  // Row 0 (the bottom in OpenGL): red then green; row 1: blue then white.
  EXPECT_EQ(rgbw->bytes[0], 255);
  EXPECT_EQ(rgbw->bytes[1], 0);
  EXPECT_EQ(rgbw->bytes[2 * 4 + 1], 255);        // (2, 0) green
  EXPECT_EQ(rgbw->bytes[(4 + 0) * 4 + 2], 255);  // (0, 1) blue
  EXPECT_EQ(rgbw->bytes[(4 + 3) * 4 + 0], 255);  // (3, 1) white
  const Sampler* sampler = r.script.findSampler("sampler_unit_2");
  ASSERT_NE(sampler, nullptr);
  EXPECT_TRUE(sampler->linearMag);
  EXPECT_FALSE(sampler->linearMin);
  const Buffer* checker = r.script.findBuffer("texture_unit_0");
  ASSERT_NE(checker, nullptr);
  // 2x2 squares of 2x2 texels: the first colour where row and column square agree.
  EXPECT_EQ(checker->bytes[0], 255);            // (0, 0) colour 0: red
  EXPECT_EQ(checker->bytes[2 * 4 + 2], 255);    // (2, 0) colour 1: blue
  EXPECT_EQ(checker->bytes[(8 + 2) * 4], 255);  // (2, 2) colour 0 again
}

TEST(ShaderTestParser, ParseScriptFilePicksTheFormatByExtension) {
  EXPECT_TRUE(isShaderTestPath("a/b.shader_test"));
  EXPECT_FALSE(isShaderTestPath("a/b.amber"));
  ParseResult missing = parseScriptFile("no/such/file.shader_test");
  EXPECT_FALSE(missing.ok);
}

}  // namespace

namespace {

// piglit's [vertex data] header (piglit-vbo.cpp): NAME[INDEX]/GL_TYPE/GLSL_TYPE[/COLUMN] and
// NAME/GL_TYPE/COUNT. Each column feeds the input at its location plus the locations of the
// array elements and matrix columns before it (two per dvec3 or dvec4 column), in the Vulkan
// format of its stored components, from one interleaved buffer whose columns are aligned to
// their component size.
TEST(ShaderTestParser, VertexDataColumnsOfEveryTypeAndShape) {
  ParseResult r = parseShaderTest(R"([require]
GLSL >= 1.50
[vertex shader passthrough]
[fragment shader]
void main() {}
[vertex data]
p/float/vec3 m[1]/float/mat3x2/2 d/double/dmat2x3/1 i/short/ivec2 u/ubyte/uint h/half/2 c/float/4 v[2]/double/dvec4
1 2 3  4 5  6 7 8  -1 2  200  0.5 0.25  1 2 3 4  1 2 3 4
)",
                                  "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.script.unsupported.empty()) << r.script.unsupported.front().feature;
  const Pipeline* p = r.script.findPipeline("arrays");
  ASSERT_NE(p, nullptr);
  ASSERT_EQ(p->vertexData.size(), 8u);
  struct Want {
    std::string name;
    uint32_t locationOffset, offset;
    std::string format;
  };
  // Offsets: p 0 (12 bytes), m 12 (8), d 24 (aligned to 8; 24), i 48 (4), u 52 (1), h 54 (aligned
  // to 2; 4), c 60 (16), v 80 (aligned to 8; 32): a stride of 112.
  const std::vector<Want> want = {{"p", 0, 0, "R32G32B32_SFLOAT"},     {"m", 3 + 2, 12, "R32G32_SFLOAT"},
                                  {"d", 2, 24, "R64G64B64_SFLOAT"},    {"i", 0, 48, "R16G16_SINT"},
                                  {"u", 0, 52, "R8_UINT"},             {"h", 0, 54, "R16G16_SFLOAT"},
                                  {"c", 0, 60, "R32G32B32A32_SFLOAT"}, {"v", 2 * 2, 80, "R64G64B64A64_SFLOAT"}};
  for (size_t i = 0; i < want.size(); ++i) {
    SCOPED_TRACE(want[i].name);
    const VertexData& v = p->vertexData[i];
    EXPECT_EQ(v.attribute, want[i].name);
    EXPECT_EQ(v.locationOffset, want[i].locationOffset);
    EXPECT_EQ(v.offset, want[i].offset);
    EXPECT_EQ(v.format, want[i].format);
    EXPECT_EQ(v.buffer, "vertex_data");
    EXPECT_EQ(v.stride, 112u);
  }
  const Buffer* b = r.script.findBuffer("vertex_data");
  ASSERT_NE(b, nullptr);
  ASSERT_EQ(b->bytes.size(), 112u);
  double d1;
  std::memcpy(&d1, b->bytes.data() + 24 + 8, 8);
  EXPECT_EQ(d1, 7.0);
  EXPECT_EQ(b->bytes[52], 200);
  int16_t minusOne;
  std::memcpy(&minusOne, b->bytes.data() + 48, 2);
  EXPECT_EQ(minusOne, -1);
}

TEST(ShaderTestParser, VertexDataColumnErrorsAndLimits) {
  auto parse = [](const std::string& header, const std::string& row, const std::string& require = "") {
    return parseShaderTest("[require]\nGLSL >= 1.50\n" + require + "[vertex shader passthrough]\n[fragment shader]\nvoid main() {}\n[vertex data]\n" +
                               header + "\n" + row + "\n",
                           "t.shader_test");
  };
  const std::vector<std::pair<std::string, std::string>> errors = {
      {"m/float/mat2", "a matrix column needs its index, 0 to 1"},
      {"m/float/mat2/2", "a matrix column needs its index, 0 to 1"},
      {"v/float/vec2/0", "a column index on a type that is no matrix"},
      {"v/long/vec2", "unknown type 'long'"},
      {"v/float/vec5", "unknown GLSL type 'vec5'"},
      {"v[x]/float/vec2", "array index is not [N]"},
      {"v/float/dvec2", "double inputs take double values and only they"},
      {"v/float", "not a column header"},
  };
  for (const auto& [header, message] : errors) {
    SCOPED_TRACE(header);
    ParseResult r = parse(header, "1 2");
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("t.shader_test:7: error: [vertex data] column '" + header + "': " + message), std::string::npos)
        << r.error;
  }
  // Integers into a float input need a converting fetch: named, not an error.
  ParseResult r = parse("v/int/vec2", "1 2");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(hasUnsupported(r.script, "a converting fetch"));
  // More attributes than GL and Vulkan guarantee (16): the file is skipped, as piglit skips it.
  r = parse("v/float/vec2", "1 2", "GL_MAX_VERTEX_ATTRIBS >= 17\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(hasUnsupported(r.script, "GL_MAX_VERTEX_ATTRIBS >= 17"));
  r = parse("v/float/vec2", "1 2", "GL_MAX_VERTEX_ATTRIBS >= 16\n");
  EXPECT_FALSE(hasUnsupported(r.script, "GL_MAX_VERTEX_ATTRIBS"));
}

}  // namespace
