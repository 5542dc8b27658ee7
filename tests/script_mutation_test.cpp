// Library scripts fail when the thing they test is broken. Each case breaks one shader of a copy
// of shaders/ (found through PARITY_SHADER_DIR, so the tree is never touched) or one platform
// assumption of a copy of the script, runs the script and expects FAIL. The unbroken scripts
// pass in ScriptLibrary.PassesOnEveryBackend.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "harness/run/process.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace {

std::string readText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

using parity::test::requiredBackend;

struct Mutation {
  const char* name;
  const char* file;  // relative to shaders/ (a shader mutation) or empty (a script mutation)
  const char* from;
  const char* to;
  const char* script;  // in tests/scripts
  const char* platform;
};

void PrintTo(const Mutation& m, std::ostream* os) { *os << m.name; }

class ScriptMutation : public ::testing::TestWithParam<Mutation> {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("parity-mutation-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    unsetenv("PARITY_SHADER_DIR");
    fs::remove_all(dir_);
  }
  fs::path dir_;
};

TEST_P(ScriptMutation, BrokenSubjectFailsTheScript) {
  const Mutation& m = GetParam();
  const fs::path source = PARITY_SOURCE_DIR;
  fs::path script = source / "tests/scripts" / m.script;
  if (std::string(m.file).empty()) {
    std::string text = readText(script);
    size_t at = text.find(m.from);
    ASSERT_NE(at, std::string::npos) << m.script << " no longer contains '" << m.from << "'";
    text.replace(at, std::string(m.from).size(), m.to);
    script = dir_ / m.script;
    std::ofstream(script) << text;
  } else {
    fs::path shaders = dir_ / "shaders";
    fs::copy(source / "shaders", shaders, fs::copy_options::recursive);
    fs::path file = shaders / m.file;
    std::string text = readText(file);
    size_t at = text.find(m.from);
    ASSERT_NE(at, std::string::npos) << m.file << " no longer contains '" << m.from << "'";
    text.replace(at, std::string(m.from).size(), m.to);
    std::ofstream(file, std::ios::trunc) << text;
    setenv("PARITY_SHADER_DIR", shaders.string().c_str(), 1);
  }
  auto r = parity::harness::runProcess(
      {PARITY_BINARY, "test", script.string(), "--backend", "vk", "--platform", m.platform, "--json"}, 120);
  ASSERT_FALSE(r.timedOut);
  nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["cases"].size(), 1u) << r.out;
  const auto& c = j["cases"][0];
  if (c["result"] == "SKIP" && !requiredBackend("vk")) GTEST_SKIP() << c.value("reason", "");
  EXPECT_EQ(c["result"], "FAIL") << m.name << ": " << c.dump();
  EXPECT_EQ(r.exitCode, 1);
}

const Mutation kMutations[] = {
    // Eq. 1 with the wrong half-way vector.
    {"normal_encoding_halfway", "include/normal_encoding.glsl", "n + vec3(0.0, 0.0, 1.0)", "n + vec3(0.0, 0.0, 0.5)",
     "normal_encoding.amber", "reference"},
    // The MAX scheme's second index read without the inversion.
    {"lidr_max_inversion", "light_indexed/lidr_unpack.glsl", "255u - b.g != b.r) ? 255u - b.g", "b.g != b.r) ? b.g",
     "light_index_max_blend.amber", "reference"},
    // The bit-shifting unpack with the wrong rounding of the packed bytes.
    {"lidr_bits_rounding", "light_indexed/lidr_unpack.glsl", "ceil(packedA * 254.5)", "floor(packedA * 254.5)",
     "light_index_bit_shift.amber", "reference"},
    // PS3 packed16x2 with the bytes of X16 swapped.
    {"ps3_packed16_byte_order", "platforms/ps3/targets.glsl", "q.x >> 8, q.x & 255u", "q.x & 255u, q.x >> 8",
     "ps3_packed16_memory.amber", "ps3"},
    // x360 k_16_16 encode rounding towards zero instead of half away from zero.
    {"x360_fixed16_rounding", "platforms/x360/fixed16.glsl", "(c < 0.0 ? -0.5 : 0.5)", "0.0", "x360_k16_encode.amber",
     "x360"},
    // DX10 R24X8 read losing the low byte.
    {"dx10_r24x8_mask", "platforms/dx10/targets.glsl", "texel.x & 0xFFFFFFu", "texel.x & 0xFFFF00u",
     "dx10_r24x8_depth.amber", "dx10"},
    // Path C through mainline Xenia's resolve (the sign is lost: every v < 0.5 becomes 0).
    {"x360_path_c_unsigned_resolve", "", "SET PLATFORM_PARAM RESOLVE_PATH paper-signed-c",
     "SET PLATFORM_PARAM RESOLVE_PATH paper-signed-c\nSET PLATFORM_PARAM SIGNED_K16_RESOLVE unsigned-saturate",
     "x360_k16_path_c.amber", "x360"},
    // The opposite HALFPIXELOFFSET -> PIX_CENTER mapping (open question 5).
    {"x360_pixel_centre_mapping", "", "REQUIRE platform x360",
     "REQUIRE platform x360\nSET PLATFORM_PARAM x360.halfpixeloffset_mapping true-is-pix-center-zero",
     "x360_pixel_centre_d3d9.amber", "x360"},
};

INSTANTIATE_TEST_SUITE_P(Library, ScriptMutation, ::testing::ValuesIn(kMutations),
                         [](const ::testing::TestParamInfo<Mutation>& i) { return std::string(i.param.name); });

}  // namespace
