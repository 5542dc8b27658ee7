// ARB assembly programs translated to Vulkan GLSL (harness/scripts/arb_program_glsl.h): every
// instruction group of the two specifications compiles, the state block is as large as the
// parameters read, and what the translation does not do is named.
#include <gtest/gtest.h>

#include "harness/scripts/arb_program_glsl.h"
#include "rhi/shader_compiler.h"

namespace {

using parity::harness::script::ArbProgramGlsl;
using parity::harness::script::translateArbProgram;

ArbProgramGlsl translated(const std::string& text) {
  ArbProgramGlsl t = translateArbProgram(text, 0, 16);
  EXPECT_TRUE(t.unsupported.empty()) << t.unsupported;
  const auto stage = t.vertex ? parity::rhi::ShaderStage::Vertex : parity::rhi::ShaderStage::Fragment;
  parity::rhi::CompiledShader c = parity::rhi::compileGlslSource(t.glsl, "arb.glsl", stage, {});
  EXPECT_TRUE(c.ok()) << c.error << "\n" << t.glsl;
  return t;
}

TEST(ArbProgramGlsl, VertexInstructionsCompile) {
  const ArbProgramGlsl t = translated(R"(!!ARBvp1.0
# Every ARB_vertex_program instruction, declarations of each kind, relative addressing.
ATTRIB pos = vertex.position;
OUTPUT colour = result.color;
PARAM mvp[4] = { state.matrix.mvp };
PARAM rows[] = { program.env[2..4], state.matrix.modelview.inverse.row[1], {1, 2}, 0.5 };
PARAM one = program.local[7];
TEMP a, b;
ALIAS c = a;
ADDRESS a0;
DP4 result.position.x, mvp[0], pos;
DP4 result.position.y, mvp[1], pos;
DP4 result.position.z, mvp[2], pos;
DP4 result.position.w, mvp[3], pos;
ARL a0.x, one.x;
MOV a, rows[a0.x + 2];
ABS b, -a.yzwx; ADD b, b, a; DP3 b.x, a, b; DPH b.y, a, b; DST b, a, b; EX2 b.z, a.w; EXP b, a.x;
FLR a, b; FRC a, b; LG2 a.x, b.y; LIT a, b; LOG b, a.z; MAD a, a, b, c; MAX a, a, b; MIN a, a, b;
MUL a, a, b; POW a.x, a.x, b.y; RCP a.y, a.x; RSQ a.z, a.y; SGE b, a, c; SLT b, a, c; SUB a, a, b;
SWZ a, b, -x, 0, 1, -w; XPD b, a, b;
MOV colour, a;
MOV result.color.secondary, vertex.color.secondary;
MOV result.texcoord[3].xz, vertex.texcoord[3];
MOV result.fogcoord.x, b.z;
END
)");
  EXPECT_TRUE(t.vertex);
  EXPECT_EQ(t.state.envCount, 5u);    // program.env[0..4]
  EXPECT_EQ(t.state.localCount, 8u);  // program.local[0..7]
  EXPECT_TRUE(t.textures.empty());
  EXPECT_NE(t.glsl.find("gl_Position.z = (gl_Position.z + gl_Position.w) * 0.5"), std::string::npos) << t.glsl;
}

TEST(ArbProgramGlsl, FragmentInstructionsCompile) {
  const ArbProgramGlsl t = translated(R"(!!ARBfp1.0
OPTION ARB_fragment_program_shadow;
TEMP a, b;
TEX a, fragment.texcoord[0], texture[2], 2D;
TXP b, fragment.texcoord[1], texture[3], CUBE;
TXB a, a, texture[2], 2D;
TEX b, b, texture[5], SHADOW2D;
TXP b, b, texture[6], 3D;
TEX b, b, texture, 1D;
CMP a, a, b, fragment.color; COS a.x, b.y; SIN a.y, b.x; SCS a.xy, b.z; LRP_SAT a, a, b, fragment.color.secondary;
KIL -a.xyzw; KIL b.x;
MAD_SAT result.color, a, program.env[3], fragment.position;
MOV result.depth.z, fragment.fogcoord.x;
END
)");
  EXPECT_FALSE(t.vertex);
  EXPECT_EQ(t.state.envCount, 4u);
  const std::map<uint32_t, std::string> units = {{0, "sampler1D"}, {2, "sampler2D"}, {3, "samplerCube"},
                                                 {5, "sampler2DShadow"}, {6, "sampler3D"}};
  EXPECT_EQ(t.textures, units);
  EXPECT_NE(t.glsl.find("gl_FragDepth"), std::string::npos) << t.glsl;
}

TEST(ArbProgramGlsl, UntranslatedConstructsAreNamed) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"!!ARBfp1.0\nTEX result.color, fragment.texcoord[0], texture[0], RECT;\nEND\n", "texture target RECT"},
      {"!!ARBfp1.0\nOPTION ARB_fog_linear;\nMOV result.color, fragment.color;\nEND\n", "OPTION ARB_fog_linear"},
      {"!!ARBvp1.0\nMOV result.color, vertex.weight;\nEND\n", "vertex.weight"},
      {"!!ARBvp1.0\nMOV result.color, state.light[0].ambient;\nEND\n", "state"},
      {"!!ARBvp1.0\nTEX result.color, vertex.position, texture[0], 2D;\nEND\n", "instruction TEX in a vertex program"},
      {"!!ARBfp1.0\nMOV result.color, fragment.color\nEND\n", "';' expected"},
  };
  for (const auto& [text, named] : cases) {
    ArbProgramGlsl t = translateArbProgram(text, 0, 16);
    EXPECT_TRUE(t.glsl.empty()) << text;
    EXPECT_NE(t.unsupported.find(named), std::string::npos) << text << ": " << t.unsupported;
  }
}

}  // namespace
