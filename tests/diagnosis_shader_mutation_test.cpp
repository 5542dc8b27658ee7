// The diagnosis names porting bugs made the way porting engineers make them: in a shader. Each
// case breaks one line of a copy of shaders/ (found through PARITY_SHADER_DIR, so the tree is
// never touched), renders the default scene on the same device with and without the break, and
// asks the diagnosis that `parity run` and `parity diff --explain` use to name what changed.
// Vertex-stage shifts break forward's vertex shader (every draw moves); the flips, swizzles,
// transfer functions, range and precision mistakes break a full-screen pass (deferred's compose,
// which reads the light accumulation at the fragment's position) or forward's output. Genuine
// regressions (a light lost, a light's colour changed) must get no name.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>

#include "harness/compare/diagnosis.h"
#include "harness/run/render.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

struct ShaderBug {
  const char* name;
  const char* technique;
  const char* file;   // relative to shaders/
  const char* from;   // replaced once
  const char* to;
  const char* cause;  // the diagnosis must start with this; empty: it must name nothing
};

void PrintTo(const ShaderBug& b, std::ostream* os) { *os << b.name; }

const char* kForwardPosition = "  gl_Position = mul(frame.viewProj, vec4(inPosition, 1.0));";
const char* kForwardOutput = "  outColor = vec4(color, 1.0);\n#endif";
const char* kComposeFetch = "texelFetch(lightAccumulation, ivec2(gl_FragCoord.xy), 0)";
const char* kComposeOutput = "  outColor = vec4(light.rgb, 1.0);";

const ShaderBug kBugs[] = {
    // Screen-space reads with the other origin convention (v = 0 at the bottom, or mirrored x).
    {"vertical_flip", "deferred", "deferred/compose.frag", kComposeFetch,
     "texelFetch(lightAccumulation, ivec2(gl_FragCoord.x, textureSize(lightAccumulation, 0).y - 1 - int(gl_FragCoord.y)), 0)",
     "vertical flip"},
    {"horizontal_flip", "deferred", "deferred/compose.frag", kComposeFetch,
     "texelFetch(lightAccumulation, ivec2(textureSize(lightAccumulation, 0).x - 1 - int(gl_FragCoord.x), gl_FragCoord.y), 0)",
     "horizontal flip"},
    // Offsets added in the vertex stage: two pixels right and one down, then half a pixel (the
    // D3D9 pixel-centre fix applied where it does not belong). NDC spans 2 over 320x180 pixels.
    {"integer_offset_vertex", "forward", "forward/forward.vert", kForwardPosition,
     "  gl_Position = mul(frame.viewProj, vec4(inPosition, 1.0));\n"
     "  gl_Position.xy += vec2(2.0 * 2.0 / 320.0, 1.0 * 2.0 / 180.0) * gl_Position.w;",
     "integer shift"},
    {"half_pixel_offset_vertex", "forward", "forward/forward.vert", kForwardPosition,
     "  gl_Position = mul(frame.viewProj, vec4(inPosition, 1.0));\n"
     "  gl_Position.xy += vec2(1.0 / 320.0, 1.0 / 180.0) * gl_Position.w;",
     "half-pixel shift"},
    // Output mistakes.
    {"bgra_swizzle", "forward", "forward/forward_single_pass.frag", kForwardOutput,
     "  outColor = vec4(color, 1.0).bgra;\n#endif", "RGBA/BGRA swizzle"},
    {"srgb_twice", "deferred", "deferred/compose.frag", kComposeOutput,
     "  vec3 c = clamp(light.rgb, 0.0, 1.0);\n"
     "  outColor = vec4(mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c)), 1.0);",
     "sRGB applied twice"},
    {"srgb_missing", "deferred", "deferred/compose.frag", kComposeOutput,
     "  vec3 c = clamp(light.rgb, 0.0, 1.0);\n"
     "  outColor = vec4(mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(0.04045, c)), 1.0);",
     "sRGB missing"},
    {"signed_range_mapping", "forward", "forward/forward_single_pass.frag", kForwardOutput,
     "  outColor = vec4(clamp(color, 0.0, 1.0) * 0.5 + 0.5, 1.0);\n#endif", "value range 0..1 vs -1..1"},
    {"range_scale", "deferred", "deferred/compose.frag", kComposeOutput, "  outColor = vec4(light.rgb * 0.5, 1.0);",
     "value range scaled"},
    {"precision_loss", "deferred", "deferred/compose.frag", kComposeOutput,
     "  outColor = vec4(floor(clamp(light.rgb, 0.0, 1.0) * 31.0 + 0.5) / 31.0, 1.0);", "precision loss"},
    // Genuine regressions: no porting bug explains them.
    {"light_lost", "forward", "forward/forward_single_pass.frag", "    Light light = lights[i];",
     "    if (i == 1u) continue;\n    Light light = lights[i];", ""},
    {"light_colour_changed", "forward", "forward/forward_single_pass.frag", "    Light light = lights[i];",
     "    Light light = lights[i];\n    if (i == 1u) light.colorK.rgb *= vec3(1.0, 0.25, 0.25);", ""},
};

using Param = std::tuple<std::string, ShaderBug>;

class ShaderBugDiagnosis : public ::testing::TestWithParam<Param> {
 protected:
  void TearDown() override {
    unsetenv("PARITY_SHADER_DIR");
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  fs::path dir_;
};

harness::RenderResult render(rhi::Device& device, const std::string& technique) {
  harness::RenderRequest r;
  r.frame.technique = technique;  // the default scene on the reference platform at the CI size
  return harness::renderFrame(device, r);
}

TEST_P(ShaderBugDiagnosis, NamesTheBugAndNothingElse) {
  const auto& [backend, bug] = GetParam();
  auto device = test::makeDevice(backend);
  if (!device) return;
  unsetenv("PARITY_SHADER_DIR");
  harness::RenderResult good = render(*device, bug.technique);
  ASSERT_TRUE(good.ok) << good.error;

  dir_ = fs::temp_directory_path() / ("parity-shader-bug-" + std::to_string(::getpid()) + "-" + bug.name);
  fs::remove_all(dir_);
  fs::copy(fs::path(PARITY_SOURCE_DIR) / "shaders", dir_, fs::copy_options::recursive);
  const fs::path file = dir_ / bug.file;
  std::stringstream text;
  text << std::ifstream(file).rdbuf();
  std::string source = text.str();
  const size_t at = source.find(bug.from);
  ASSERT_NE(at, std::string::npos) << bug.file << " no longer contains '" << bug.from << "'";
  source.replace(at, std::string(bug.from).size(), bug.to);
  std::ofstream(file, std::ios::trunc) << source;
  setenv("PARITY_SHADER_DIR", dir_.c_str(), 1);
  harness::RenderResult broken = render(*device, bug.technique);
  unsetenv("PARITY_SHADER_DIR");
  ASSERT_TRUE(broken.ok) << broken.error;
  ASSERT_NE(good.texels, broken.texels) << "the break changes nothing";

  std::optional<harness::Diagnosis> d = harness::diagnose(good.image, broken.image);
  if (std::string(bug.cause).empty()) {
    EXPECT_FALSE(d.has_value()) << "a genuine regression was named: " << d->cause << " (" << d->detail << ")";
    return;
  }
  ASSERT_TRUE(d.has_value()) << bug.name << " got no name";
  EXPECT_EQ(d->cause.rfind(bug.cause, 0), 0u) << bug.name << ": named '" << d->cause << "' (" << d->detail << ")";
  std::printf("[ diagnosis ] %s on %s: %s\n", bug.name, backend.c_str(), d->cause.c_str());
}

std::string paramName(const ::testing::TestParamInfo<Param>& info) {
  return std::string(std::get<1>(info.param).name) + "_" + std::get<0>(info.param);
}

INSTANTIATE_TEST_SUITE_P(Bugs, ShaderBugDiagnosis,
                         ::testing::Combine(::testing::Values("gl", "vk"), ::testing::ValuesIn(kBugs)), paramName);

}  // namespace
