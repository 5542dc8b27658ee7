// Helpers shared by the tests: which backends to parameterise over, device creation, shader
// compilation from inline GLSL.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "rhi/rhi.h"

namespace parity::test {

// Every backend this build knows ("gl", "vk"). Tests are instantiated for all of them; a
// backend that cannot be created on this machine makes its tests skip with the reason, unless
// PARITY_REQUIRE_BACKENDS (comma-separated, set by CI) names it: then they fail.
std::vector<std::string> allBackends();

// Whether PARITY_REQUIRE_BACKENDS (comma-separated) names `backend`: then a test must not skip it.
bool requiredBackend(const std::string& backend);

// Creates a device with validation on; any validation error fails the current test. Returns
// null after GTEST_SKIP()/FAIL when the backend is unavailable (check with `if (!dev) return;`).
std::unique_ptr<rhi::Device> makeDevice(const std::string& backend, bool validation = true);

// Creates a device from a complete descriptor (own callbacks); an unavailable backend is handled
// as in makeDevice (skip, or failure when PARITY_REQUIRE_BACKENDS names it).
std::unique_ptr<rhi::Device> makeDeviceWith(const rhi::DeviceDesc& desc);

// A descriptor for `backend` whose validation errors and driver messages each fail the test.
rhi::DeviceDesc strictDeviceDesc(const std::string& backend);

// A whole file as bytes (empty when it cannot be read).
std::string readFile(const std::string& path);

// GOLDEN/evidence.json covering every case with one tests claim: `test` ("tests/FILE: Suite.Name",
// relative to parity's source tree), the test that blesses into GOLDEN (`parity bless` refuses a
// golden no claim covers).
void writeEvidence(const std::string& goldenDir, const std::string& test);

// Compiles inline GLSL 450 and creates the shader; fails the test on a compile error.

rhi::ShaderHandle makeShader(rhi::Device& dev, rhi::ShaderStage stage, const std::string& glsl);

// The first of `names` found as an executable on PATH (e.g. {"chromium", "chromium-browser"});
// empty when none is.
std::string findExecutable(const std::vector<std::string>& names);

// OpenGL GLSL compiled as parity's port of it (ShaderCompileOptions::openGlSource: glslang's
// relaxed Vulkan rules, the loose uniforms in a block at `defaultUniformBinding`); a test failure
// with glslang's log where it does not compile.
std::vector<uint32_t> openGlPort(rhi::ShaderStage stage, const std::string& source, uint32_t defaultUniformBinding = 0);

// Name printer for backend-parameterised tests: "gl", "vk".
struct BackendName {
  std::string operator()(const ::testing::TestParamInfo<std::string>& info) const { return info.param; }
};

// Every registered technique's name, for tests parameterised over techniques.
std::vector<std::string> techniqueNames();
// Name printer for (backend, technique) tests: "lidr_bits_8x255_vk".
struct BackendTechniqueName {
  std::string operator()(const ::testing::TestParamInfo<std::tuple<std::string, std::string>>& info) const;
};

// True when one of the technique's logical targets stores less on a console than on the
// reference: 16-bit and packed channels, half or fixed-point light buffers, 8-bit intermediate
// colour (the reference keeps it in float), depth a later pass reads at 24 bits. The frame's
// output, LIDR's exact 8-bit index, single 8-bit and 32-bit float channels and a depth nothing
// reads are stored alike everywhere.
bool hasLossyTarget(const std::string& technique);

// True when the technique resolves a multisampled target by averaging its samples (which x360
// does by its own rounding rule, the hosts by their driver's).
bool averagesSamples(const std::string& technique);

// The red channel of every texel of `texels` (a readback of `format`: R8, RGBA8, R32F or
// RGBA32F) as a float, unorm formats in [0, 1]. A count stored as k / 255 reads back as k / 255.
std::vector<float> redChannel(const std::vector<uint8_t>& texels, rhi::Format format);

}  // namespace parity::test
