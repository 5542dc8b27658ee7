// piglit's shader_runner constructs and the OpenGL-GLSL preparation behind them: atomic counter
// commands, uniform initialisers, the glslang faults a piglit file can meet (named for a SKIP),
// and the version raise for located interface blocks. Running them on both backends is covered
// by tests/scripts/shader_test/piglit_* (the library).
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "harness/scripts/opengl_glsl.h"
#include "harness/scripts/script.h"
#include "harness/scripts/shader_test_parser.h"
#include "harness/scripts/spirv_interface.h"
#include "rhi/shader_compiler.h"
#include "tests/test_support.h"

using namespace parity::harness::script;

namespace {

const Command* findCommand(const Script& s, Command::Kind kind, size_t nth = 0) {
  for (const Command& c : s.commands)
    if (c.kind == kind && nth-- == 0) return &c;
  return nullptr;
}

const UniformInitialValue* findValue(const std::vector<UniformInitialValue>& values, const std::string& path) {
  for (const UniformInitialValue& v : values)
    if (v.path == path) return &v;
  return nullptr;
}

TEST(ShaderTestPiglit, AtomicCounterCommandsAreBuffersAtTheirBinding) {
  ParseResult r = parseShaderTest(R"([require]
GLSL >= 4.30
[compute shader]
void main() {}
[test]
atomic counters 3
atomic counter buffer 2 4
atomic counter 2 1 7
compute 1 1 1
probe atomic counter 1 == 5
probe atomic counter buffer 2 4 != 7
)",
                                  "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  const Script& s = r.script;
  EXPECT_TRUE(s.unsupported.empty()) << s.unsupported.front().feature;
  const Buffer* zero = s.findBuffer("atomic_counters_0");
  const Buffer* two = s.findBuffer("atomic_counters_2");
  ASSERT_NE(zero, nullptr);
  ASSERT_NE(two, nullptr);
  EXPECT_EQ(zero->atomicCounterBinding, 0);
  EXPECT_EQ(two->atomicCounterBinding, 2);
  EXPECT_EQ(zero->bytes.size(), 12u);  // 3 counters of 32 bits
  EXPECT_EQ(two->bytes.size(), 16u);

  // `atomic counters N` zeroes the buffer where it stands; `atomic counter B I V` writes one.
  const Command* reset = findCommand(s, Command::Kind::WriteBuffer, 0);
  ASSERT_NE(reset, nullptr);
  EXPECT_EQ(reset->buffer, "atomic_counters_0");
  EXPECT_EQ(reset->bytes, std::vector<uint8_t>(12, 0));
  const Command* set = findCommand(s, Command::Kind::WriteBuffer, 2);
  ASSERT_NE(set, nullptr);
  EXPECT_EQ(set->buffer, "atomic_counters_2");
  EXPECT_EQ(set->px, 4u);  // counter 1
  EXPECT_EQ(set->bytes, (std::vector<uint8_t>{7, 0, 0, 0}));

  // Counter N of binding 0 is byte 4N; `probe atomic counter buffer` gives the byte offset.
  const Command* byIndex = findCommand(s, Command::Kind::ExpectValues, 0);
  ASSERT_NE(byIndex, nullptr);
  EXPECT_EQ(byIndex->buffer, "atomic_counters_0");
  EXPECT_EQ(byIndex->px, 4u);
  EXPECT_EQ(byIndex->comparator, Comparator::Eq);
  ASSERT_EQ(byIndex->values.size(), 1u);
  EXPECT_EQ(byIndex->values[0].i, 5);
  EXPECT_EQ(byIndex->valueType.layout.fields[0].scalar, Scalar::Uint32);
  const Command* byOffset = findCommand(s, Command::Kind::ExpectValues, 1);
  ASSERT_NE(byOffset, nullptr);
  EXPECT_EQ(byOffset->buffer, "atomic_counters_2");
  EXPECT_EQ(byOffset->px, 4u);
  EXPECT_EQ(byOffset->comparator, Comparator::Ne);
}

TEST(ShaderTestPiglit, TextureQuadsArePiglitsPattern) {
  // piglit_quads_texture: 2x1 squares; bl where row and column are even, br at an odd column,
  // tl at an odd row, tr at both (rows and columns from the first).
  ParseResult r = parseShaderTest(R"([require]
GLSL >= 1.50
[test]
texture quads 3 0 (4, 2) (2, 1) (1, 0, 0, 1) (0, 1, 0, 1) (0, 0, 1, 1) (1, 1, 1, 0)
)",
                                  "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  const Buffer* image = r.script.findBuffer("texture_unit_3");
  ASSERT_NE(image, nullptr);
  EXPECT_EQ(image->textureUnit, 3);
  ASSERT_EQ(image->bytes.size(), 4u * 2u * 4u);
  auto texel = [&](size_t x, size_t y) { return std::vector<uint8_t>(image->bytes.begin() + long((y * 4 + x) * 4), image->bytes.begin() + long((y * 4 + x) * 4 + 4)); };
  EXPECT_EQ(texel(1, 0), (std::vector<uint8_t>{255, 0, 0, 255}));      // bl
  EXPECT_EQ(texel(2, 0), (std::vector<uint8_t>{0, 255, 0, 255}));      // br
  EXPECT_EQ(texel(0, 1), (std::vector<uint8_t>{0, 0, 255, 255}));      // tl
  EXPECT_EQ(texel(3, 1), (std::vector<uint8_t>{255, 255, 255, 0}));    // tr
  EXPECT_NE(r.script.findSampler("sampler_unit_3"), nullptr);
}

TEST(ShaderTestPiglit, MalformedAtomicCounterLinesNameTheLine) {
  ParseResult r = parseShaderTest("[require]\nGLSL >= 4.30\n[test]\nprobe atomic counter 0 = 1\n", "t.shader_test");
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find("t.shader_test:4: error: unknown comparison '='"), std::string::npos) << r.error;
  r = parseShaderTest("[require]\nGLSL >= 4.30\n[test]\natomic counters\n", "t.shader_test");
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find("t.shader_test:4: error:"), std::string::npos) << r.error;
}

TEST(ShaderTestPiglit, UniformInitializersOfStructsArraysAndMatrices) {
  const std::string source = R"(
struct S {
  double d;
  dvec4 v;
};
uniform S color = S(2.0lf, dvec4(0.0lf, 0.5lf, 0.0lf, 1.0lf));
uniform vec2 list[] = { vec2(3.0), vec2(-1.0, 1e-1) };
uniform float made[2] = float[2](4.0, 5.0);
uniform mat2 m = mat2(2.0);
uniform int count = 3;
uniform vec4 notLiteral = vec4(someConstant);
const mat2 half = mat2(0.5, 1.0, 1.5, 2.0);
const mat2 alias = half;
uniform mat2 named = alias;
uniform uint64_t wide[] = uint64_t[](0xBADDC0DEDEADBEEFul, 017u);
)";
  std::vector<UniformInitialValue> values = uniformInitializers(source);
  // 64-bit integers keep every bit; a hexadecimal F is a digit, not a float suffix; 0-led is octal.
  const UniformInitialValue* wide = findValue(values, "wide[0]");
  ASSERT_NE(wide, nullptr);
  ASSERT_EQ(wide->values.size(), 1u);
  EXPECT_TRUE(wide->values[0].isInteger);
  EXPECT_EQ(static_cast<uint64_t>(wide->values[0].i), 0xBADDC0DEDEADBEEFull);
  const UniformInitialValue* octal = findValue(values, "wide[1]");
  ASSERT_NE(octal, nullptr);
  EXPECT_EQ(octal->values[0].i, 15);
  const UniformInitialValue* d = findValue(values, "color.d");
  ASSERT_NE(d, nullptr);
  ASSERT_EQ(d->values.size(), 1u);
  EXPECT_DOUBLE_EQ(d->values[0].d, 2.0);
  const UniformInitialValue* v = findValue(values, "color.v");
  ASSERT_NE(v, nullptr);
  ASSERT_EQ(v->values.size(), 4u);
  EXPECT_DOUBLE_EQ(v->values[1].d, 0.5);
  EXPECT_DOUBLE_EQ(v->values[3].d, 1.0);
  const UniformInitialValue* first = findValue(values, "list[0]");
  ASSERT_NE(first, nullptr);
  ASSERT_EQ(first->values.size(), 2u);  // vec2(3.0) fills both components
  EXPECT_DOUBLE_EQ(first->values[1].d, 3.0);
  const UniformInitialValue* second = findValue(values, "list[1]");
  ASSERT_NE(second, nullptr);
  EXPECT_DOUBLE_EQ(second->values[0].d, -1.0);
  EXPECT_DOUBLE_EQ(second->values[1].d, 0.1);
  const UniformInitialValue* made = findValue(values, "made[1]");
  ASSERT_NE(made, nullptr);
  EXPECT_DOUBLE_EQ(made->values[0].d, 5.0);
  const UniformInitialValue* m = findValue(values, "m");
  ASSERT_NE(m, nullptr);
  ASSERT_EQ(m->values.size(), 4u);  // mat2(2.0): a diagonal, column by column
  EXPECT_DOUBLE_EQ(m->values[0].d, 2.0);
  EXPECT_DOUBLE_EQ(m->values[1].d, 0.0);
  EXPECT_DOUBLE_EQ(m->values[3].d, 2.0);
  const UniformInitialValue* count = findValue(values, "count");
  ASSERT_NE(count, nullptr);
  EXPECT_TRUE(count->values[0].isInteger);
  EXPECT_EQ(count->values[0].i, 3);
  EXPECT_EQ(findValue(values, "notLiteral"), nullptr);
  // An initialiser naming a constant (which names another) takes the constant's literal.
  const UniformInitialValue* named = findValue(values, "named");
  ASSERT_NE(named, nullptr);
  ASSERT_EQ(named->values.size(), 4u);
  EXPECT_DOUBLE_EQ(named->values[2].d, 1.5);
}

// piglit reads a [test] line's numbers with strtod and strtol, so a trailing ';' is no error;
// a file whose [require] names only OpenGL extensions and whose shaders are ARB assembly is a
// piglit file too (its unsupported sections are listed, its commands read as piglit's); `ssbo N
// subdata` takes piglit's type names (uint64, int16, ...).
TEST(ShaderTestPiglit, PiglitCommandsAsShaderRunnerReadsThem) {
  ParseResult r = parseShaderTest(R"([require]
GLSL >= 4.30
[compute shader]
layout(local_size_x = 1) in;
uniform float i;
layout(std430, binding = 0) buffer B { uint64_t v; };
void main() { v = uint64_t(i); }
[test]
uniform float i 1.5;
ssbo 0 64
ssbo 0 subdata uint64 8 5
compute 1 1 1
probe ssbo uint64 0 8 == 5;
)",
                                  "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  const Command* set = findCommand(r.script, Command::Kind::SetUniform);
  ASSERT_NE(set, nullptr);
  ASSERT_EQ(set->values.size(), 1u);
  EXPECT_DOUBLE_EQ(set->values[0].d, 1.5);
  const Command* write = findCommand(r.script, Command::Kind::WriteBuffer);
  ASSERT_NE(write, nullptr);
  EXPECT_EQ(write->bytes.size(), 8u);  // one 64-bit value
  EXPECT_EQ(write->px, 8u);

  ParseResult arb = parseShaderTest(R"([require]
GL_ARB_fragment_program
[vertex program]
!!ARBvp1.0
MOV result.position, vertex.position;
END
[fragment program]
!!ARBfp1.0
MOV result.color, fragment.color;
END
[test]
parameter env_fp 2 (0.25, 0.5, 0.75, 1.0)
draw rect -1 -1 1 2
relative probe rgba (0.25, 0.5) (0.2, 0.2, 0.2, 1.0);
)",
                                    "arb.shader_test");
  // ARB assembly programs: shaders of format ARB (rhi::ShaderDesc::arbProgram), and `parameter`.
  ASSERT_TRUE(arb.ok) << arb.error;
  EXPECT_TRUE(arb.script.unsupported.empty()) << arb.script.unsupported.front().feature;
  ASSERT_EQ(arb.script.shaders.size(), 2u);
  for (const Shader& s : arb.script.shaders) EXPECT_EQ(s.format, "ARB") << s.name;
  EXPECT_EQ(arb.script.findShader("vertex")->source, "!!ARBvp1.0\nMOV result.position, vertex.position;\nEND\n");
  const Command* parameter = findCommand(arb.script, Command::Kind::ProgramParameter);
  ASSERT_NE(parameter, nullptr);
  EXPECT_EQ(parameter->other, "env_fp");
  EXPECT_EQ(parameter->px, 2u);
  ASSERT_EQ(parameter->values.size(), 4u);
  EXPECT_DOUBLE_EQ(parameter->values[3].d, 1.0);
  ParseResult bad = parseShaderTest("[fragment program]\n!!ARBfp1.0\nEND\n[test]\nparameter env_fp 2 (1.0, 0.0)\n", "bad.shader_test");
  EXPECT_FALSE(bad.ok);
  EXPECT_EQ(bad.error, "bad.shader_test:5: error: parameter env_fp takes an index and (x, y, z, w)");
}

TEST(ShaderTestPiglit, GlslangFaultsAreNamedAndShaderErrorsAreNot) {
  const std::string source = "#define STATIC_ASSERT(cond) { float array[(cond) ? -1 : 1]; }\n"
                             "void main() {\n"
                             "  STATIC_ASSERT(vec4(1.0) !=\n"
                             "                fma(vec4(1.0), vec4(1.0), vec4(0.0)));\n"
                             "}\n";
  // The source starts at line 10 of the file: the error's line 12 is the STATIC_ASSERT.
  std::optional<std::string> fma =
      glslangLimitation(source, 10, "t.shader_test:12: error: '' : array size must be a constant integer expression\n");
  ASSERT_TRUE(fma.has_value());
  EXPECT_NE(fma->find("fma() in a constant expression"), std::string::npos) << *fma;
  EXPECT_EQ(fma->find("STATIC_ASSERT"), std::string::npos) << *fma;  // a macro, not a built-in
  EXPECT_EQ(fma->find("vec4()"), std::string::npos) << *fma;         // a constructor

  EXPECT_FALSE(glslangLimitation("void main() { x = 1; }\n", 1, "t:1: error: 'x' : undeclared identifier\n").has_value());
}

TEST(ShaderTestPiglit, ExplicitlyLocatedVaryingsAreFoundByDirection) {
  const std::string source = "layout(location = 0) out block {\n  vec4 a;\n} name;\n"
                             "layout(location = 1, component = 2) flat out double b;\n"
                             "layout(location = 3) in vec4 c[];\n"
                             "out vec4 byName;\n"
                             "layout(std140) uniform U { vec4 u; };\n";
  EXPECT_EQ(explicitlyLocated(source, true), (std::set<std::string>{"block", "b"}));
  EXPECT_EQ(explicitlyLocated(source, false), (std::set<std::string>{"c"}));
}

std::vector<uint32_t> compileOpenGl(const std::string& source, parity::rhi::ShaderStage stage) {
  return parity::test::openGlPort(stage, source);
}

TEST(ShaderTestPiglit, InterfaceVariablesAreNamedAsOpenGlLinksThem) {
  std::vector<uint32_t> spirv = compileOpenGl(
      "#version 450\nout vec4 first;\nout Block { vec4 member; } instance;\nlayout(location = 5) out float located;\n"
      "void main() { first = vec4(1.0); instance.member = vec4(2.0); located = 3.0; gl_Position = vec4(0.0); }\n",
      parity::rhi::ShaderStage::Vertex);
  std::map<std::string, InterfaceVariable> byName;
  for (const InterfaceVariable& v : interfaceVariables(spirv)) byName[v.name] = v;
  ASSERT_TRUE(byName.count("first"));
  ASSERT_TRUE(byName.count("Block"));  // a block by its block name, not its instance name
  ASSERT_TRUE(byName.count("located"));
  EXPECT_FALSE(byName.count("gl_PerVertex"));  // built-ins are not linked by name
  EXPECT_TRUE(byName["first"].output);
  EXPECT_EQ(byName["located"].location, 5u);
  EXPECT_EQ(spirv[byName["located"].locationWord], 5u);
  EXPECT_NE(byName["first"].location, byName["Block"].location);
}

// Location + the locations of the type: 64-bit three- and four-component vectors take two,
// matrices one per column, arrays and blocks the sum; a tessellation control shader's per-vertex
// outputs for one vertex, its patch outputs numbered after them (as glslang assigns them).
TEST(ShaderTestPiglit, OutputExtentCountsTheLocationsOfEachType) {
  std::vector<uint32_t> vs = compileOpenGl(
      "#version 450\nlayout(location = 2) out vec4 a[3];\nlayout(location = 7) flat out dmat3 m;\n"
      "void main() { a[0] = a[1] = a[2] = vec4(1.0); m = dmat3(1.0); gl_Position = vec4(0.0); }\n",
      parity::rhi::ShaderStage::Vertex);
  OutputExtent v = outputExtent(vs, false);
  EXPECT_EQ(v.end, 13u);  // m: 3 columns of dvec3, two locations each, from 7
  EXPECT_EQ(v.name, "m");
  std::vector<uint32_t> tcs = compileOpenGl(
      "#version 450\nlayout(vertices = 4) out;\nout block { vec4 m1[16]; vec4 m2[15]; } blk[];\n"
      "patch out vec4 p1[16];\npatch out vec4 p2[14];\n"
      "void main() { blk[gl_InvocationID].m1[0] = blk[gl_InvocationID].m2[0] = p1[0] = p2[0] = vec4(1.0); }\n",
      parity::rhi::ShaderStage::TessControl);
  OutputExtent perVertex = outputExtent(tcs, true);
  EXPECT_EQ(perVertex.end, 61u);  // blk 0..30, p1 31..46, p2 47..60
  EXPECT_EQ(perVertex.name, "p2");
  EXPECT_EQ(outputExtent(tcs, false).end, 124u);  // blk counted for its 4 vertices
}

TEST(ShaderTestPiglit, ViewportIndexOutputsAreFound) {
  const std::string writes = "#version 450\nlayout(triangles) in;\nlayout(triangle_strip, max_vertices = 3) out;\n"
                             "void main() { gl_ViewportIndex = 1; EmitVertex(); }\n";
  const std::string plain = "#version 450\nlayout(triangles) in;\nlayout(triangle_strip, max_vertices = 3) out;\n"
                            "void main() { gl_Position = vec4(0.0); EmitVertex(); }\n";
  EXPECT_TRUE(outputsBuiltIn(compileOpenGl(writes, parity::rhi::ShaderStage::Geometry), kBuiltInViewportIndex));
  EXPECT_FALSE(outputsBuiltIn(compileOpenGl(plain, parity::rhi::ShaderStage::Geometry), kBuiltInViewportIndex));
}

TEST(ShaderTestPiglit, AtomicCountersCompileAsGlsl430) {
  OpenGlGlsl gl = prepareOpenGlGlsl("#version 150\nlayout(binding = 0) uniform atomic_uint c;\nvoid main() {}\n", Stage::Fragment);
  EXPECT_EQ(gl.source.rfind("#version 430\n", 0), 0u) << gl.source;
}

// glslang declares min3/max3/mid3 from GLSL 4.30 on: a shader of an earlier version that enables
// GL_AMD_shader_trinary_minmax is ported as 4.30 and compiles (the RHI then expands the calls).
TEST(ShaderTestPiglit, TrinaryMinMaxShadersCompileAsGlsl430) {
  const std::string shader = "#version 130\n#extension GL_AMD_shader_trinary_minmax : require\nuniform uvec2 a, b, c;\n"
                             "out vec4 color;\nvoid main() { color = vec4(mid3(a, b, c), min3(1.0, 2.0, 3.0), 1.0); }\n";
  OpenGlGlsl gl = prepareOpenGlGlsl(shader, Stage::Fragment);
  EXPECT_EQ(gl.source.rfind("#version 430\n", 0), 0u) << gl.source;
  EXPECT_TRUE(gl.declarations.empty()) << gl.declarations;
  EXPECT_FALSE(compileOpenGl(gl.source, parity::rhi::ShaderStage::Fragment).empty());
}

// GL_MESA_shader_integer_functions brings GLSL 4.00's integer functions to 1.30: such a shader is
// ported as 4.00, where glslang has them, without the directive glslang does not know.
TEST(ShaderTestPiglit, MesaIntegerFunctionsCompileAsGlsl400) {
  const std::string shader = "#version 130\n#extension GL_MESA_shader_integer_functions : require\nuniform uint a, b;\n"
                             "out vec4 color;\nvoid main() { uint carry; uint sum = uaddCarry(a, b, carry); "
                             "color = vec4(float(sum), float(carry), float(findMSB(a)), 1.0); }\n";
  OpenGlGlsl gl = prepareOpenGlGlsl(shader, Stage::Fragment);
  EXPECT_EQ(gl.source.rfind("#version 400\n", 0), 0u) << gl.source;
  EXPECT_EQ(gl.source.find("GL_MESA_shader_integer_functions"), std::string::npos) << gl.source;
  EXPECT_FALSE(compileOpenGl(gl.source, parity::rhi::ShaderStage::Fragment).empty());
}

// Extensions glslang knows under other names or from later versions are ported under those: the
// result compiles, and the extension counts as ported (a [require] of it is met on Vulkan).
TEST(ShaderTestPiglit, ExtensionsArePortedUnderTheNamesGlslangKnows) {
  struct Case {
    const char* shader;
    parity::rhi::ShaderStage stage;
    const char* version;
    const char* absent;  // the directive glslang does not take
  };
  const Case cases[] = {
      {"#version 130\n#extension GL_AMD_conservative_depth : require\nlayout(depth_greater) out float gl_FragDepth;\n"
       "void main() { gl_FragDepth = gl_FragCoord.z; }\n",
       parity::rhi::ShaderStage::Fragment, "#version 420\n", "GL_AMD_conservative_depth"},
      {"#version 430\n#extension GL_NV_shader_atomic_float : require\nlayout(local_size_x = 1) in;\nshared float v;\n"
       "layout(std430, binding = 0) buffer B { float f; };\nvoid main() { f = atomicExchange(v, 0.5) + atomicAdd(f, 1.0); }\n",
       parity::rhi::ShaderStage::Compute, "#version 450\n", "GL_NV_shader_atomic_float"},
      {"#version 430\n#extension GL_INTEL_shader_atomic_float_minmax : require\nlayout(local_size_x = 1) in;\nshared float v;\n"
       "void main() { atomicMin(v, 0.5); }\n",
       parity::rhi::ShaderStage::Compute, "#version 450\n", "GL_INTEL_shader_atomic_float_minmax"},
      {"#version 150\n#extension GL_ARB_gpu_shader_int64 : require\nuniform i64vec2 a;\nout vec4 color;\n"
       "void main() { u64vec2 b = a; color = vec4(b == u64vec2(1ul) && sign(a.x) == 1l);}\n",
       parity::rhi::ShaderStage::Fragment, "#version 450\n", "GL_ARB_gpu_shader_int64"},
      // mix() selecting ints and bools by bools: core in 4.50, where glslang declares it.
      {"#version 130\n#extension GL_EXT_shader_integer_mix : enable\nuniform bool a, b, s;\nuniform ivec2 i;\nout vec4 color;\n"
       "void main() { color = vec4(mix(a, b, s), mix(i.x, i.y, s), 0.0, 1.0); }\n",
       parity::rhi::ShaderStage::Fragment, "#version 450\n", "GL_EXT_shader_integer_mix"},
      // GLSL 1.40 has inverse(); glslang declares it from 1.50 on.
      {"#version 140\nuniform mat3 m;\nout vec4 color;\nvoid main() { color = vec4(inverse(m)[0], 1.0); }\n",
       parity::rhi::ShaderStage::Fragment, "#version 150\n", nullptr},
      // GLSL 1.50 redeclares gl_PerVertex; glslang allows it from 4.10 on.
      {"#version 150\nout gl_PerVertex { vec4 gl_Position; float gl_ClipDistance[2]; };\nin vec4 p;\n"
       "void main() { gl_Position = p; gl_ClipDistance[0] = 1.0; }\n",
       parity::rhi::ShaderStage::Vertex, "#version 410\n", nullptr},
  };
  for (const Case& c : cases) {
    const Stage stage = c.stage == parity::rhi::ShaderStage::Vertex ? Stage::Vertex : c.stage == parity::rhi::ShaderStage::Compute ? Stage::Compute : Stage::Fragment;
    OpenGlGlsl gl = prepareOpenGlGlsl(c.shader, stage);
    EXPECT_EQ(gl.source.rfind(c.version, 0), 0u) << gl.source;
    if (c.absent) {
      EXPECT_EQ(gl.source.find(c.absent), std::string::npos) << gl.source;
    }
    const std::string unit = gl.source.substr(0, gl.source.find('\n') + 1) + gl.declarations + gl.source.substr(gl.source.find('\n') + 1);
    EXPECT_FALSE(compileOpenGl(unit, c.stage).empty()) << unit;
  }
  EXPECT_TRUE(portsExtension("GL_AMD_conservative_depth"));
  EXPECT_FALSE(portsExtension("GL_EXT_gpu_shader4"));
}

// GLSL 1.10's sampler functions, which glslang's Vulkan rules read as constructors of Vulkan's
// texture types, are ported as GLSL 1.30's overloads (a bias argument and all).
TEST(ShaderTestPiglit, LegacySamplerFunctionsArePortedAsTheirOverloads) {
  const std::string shader = "#version 110\n#extension GL_EXT_texture_array : enable\nuniform sampler1D a;\nuniform sampler2D b;\n"
                             "uniform sampler3D c;\nuniform samplerCube d;\nuniform sampler2DArray e;\nvarying vec4 p;\n"
                             "void main() {\n  gl_FragColor = texture1D(a, p.x) + texture2D(b, p.xy, 1.0) + texture2DProj(b, p) +\n"
                             "      texture3D(c, p.xyz) + textureCube(d, p.xyz) + texture2DArray(e, p.xyz) + texture1DProj (a, p.xy);\n}\n";
  OpenGlGlsl gl = prepareOpenGlGlsl(shader, Stage::Fragment);
  const std::string unit = gl.source.substr(0, gl.source.find('\n') + 1) + gl.declarations + gl.source.substr(gl.source.find('\n') + 1);
  EXPECT_FALSE(compileOpenGl(unit, parity::rhi::ShaderStage::Fragment).empty()) << unit;
}

// An unsized uniform array with an initialiser has the initialiser's size in the port (glslang,
// dropping uniform initialisers, would leave it unsized and refuse indexing it).
TEST(ShaderTestPiglit, UnsizedUniformArraysTakeTheirInitialisersSize) {
  const std::string shader = "#version 150\nuniform vec4 c[] = vec4[](vec4(1.0), vec4(0.0, vec2(1.0, 2.0), 3.0), vec4(2.0));\n"
                             "uniform int i;\nout vec4 color;\nvoid main() { color = c[i]; }\n";
  OpenGlGlsl gl = prepareOpenGlGlsl(shader, Stage::Fragment);
  EXPECT_NE(gl.source.find("uniform vec4 c[3] = vec4[]("), std::string::npos) << gl.source;
  EXPECT_FALSE(compileOpenGl(gl.source, parity::rhi::ShaderStage::Fragment).empty());
}

TEST(ShaderTestPiglit, LocatedInterfaceBlocksRaiseTheVersionTo440) {
  const std::string block = "#version 150\n#extension GL_ARB_separate_shader_objects: require\n"
                            "layout(location = 2) out block {\n  vec4 a;\n} name;\nvoid main() {}\n";
  OpenGlGlsl located = prepareOpenGlGlsl(block, Stage::Vertex);
  EXPECT_EQ(located.source.rfind("#version 440\n", 0), 0u) << located.source;
  const std::string variable = "#version 150\n#extension GL_ARB_separate_shader_objects: require\n"
                               "layout(location = 2) out vec4 a;\nvoid main() {}\n";
  OpenGlGlsl plain = prepareOpenGlGlsl(variable, Stage::Vertex);
  EXPECT_EQ(plain.source.rfind("#version 410\n", 0), 0u) << plain.source;  // where SSO is core
}

}  // namespace

namespace {

// What a program declares survives and its code does not: bodies become prototypes (their
// braces, and braces in comments, do not end a declaration early), lines are kept, and a shader
// defining main gets an empty one. The result compiles where the code would not.
TEST(ShaderTestPiglit, DeclarationsOnlyKeepTheInterfaceAndDropTheCode) {
  const std::string source = R"(#version 140
struct S { vec2 a; };
uniform S s; // a comment with a brace {
uniform B { vec4 b[2]; } blocks[2];
in vec4 piglit_vertex;
out vec4 v;
float helper(float x)
{
  return clockARB() + x; /* } */
}
void main() { gl_Position = piglit_vertex; v = vec4(helper(s.a.x)); }
)";
  const std::string d = declarationsOnly(source);
  EXPECT_EQ(std::count(d.begin(), d.end(), '\n'), std::count(source.begin(), source.end(), '\n') + 1) << d;
  for (const char* kept : {"struct S { vec2 a; };", "uniform S s;", "uniform B { vec4 b[2]; } blocks[2];", "in vec4 piglit_vertex;",
                           "out vec4 v;", "float helper(float x)\n;", "void main() ;", "void main() {}"})
    EXPECT_NE(d.find(kept), std::string::npos) << kept << " in\n" << d;
  EXPECT_EQ(d.find("clockARB"), std::string::npos) << d;
  parity::rhi::ShaderCompileOptions options;
  options.openGlSource = true;
  EXPECT_FALSE(parity::rhi::compileGlslSource(source, "t", parity::rhi::ShaderStage::Vertex, options).ok());
  parity::rhi::CompiledShader port = parity::rhi::compileGlslSource(d, "t", parity::rhi::ShaderStage::Vertex, options);
  ASSERT_TRUE(port.ok()) << port.error << "\n" << d;
  EXPECT_TRUE(findUniformBlock(port.spirv, "B").has_value());
  EXPECT_TRUE(findUniform(port.spirv, "gl_DefaultUniformBlock", "s.a").has_value());
  // A unit without main (one of several shader objects of a stage) gets none.
  EXPECT_EQ(declarationsOnly("float f() { return 1.0; }\n"), "float f() ;\n");
}

}  // namespace
