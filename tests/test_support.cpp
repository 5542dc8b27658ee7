#include <iterator>
#include <fstream>
#include "tests/test_support.h"

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "platforms/platform_layer.h"
#include "rhi/shader_compiler.h"
#include "techniques/technique.h"

namespace parity::test {

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void writeEvidence(const std::string& goldenDir, const std::string& test) {
  std::filesystem::create_directories(goldenDir);
  std::ofstream(std::filesystem::path(goldenDir) / "evidence.json", std::ios::binary | std::ios::trunc)
      << "{\"tests_root\": \"" << PARITY_SOURCE_DIR << "\", \"evidence\": [{\"case\": \"*\", \"tests\": [\"" << test
      << "\"], \"why\": \"the test that blesses into this folder checks what it needs of the images\"}]}\n";
}

std::vector<std::string> allBackends() { return rhi::compiledBackends(); }

bool requiredBackend(const std::string& backend) {
  const char* env = std::getenv("PARITY_REQUIRE_BACKENDS");
  if (!env) return false;
  std::stringstream ss(env);
  std::string item;
  while (std::getline(ss, item, ','))
    if (item == backend) return true;
  return false;
}

std::unique_ptr<rhi::Device> makeDevice(const std::string& backend, bool validation) {
  rhi::DeviceDesc desc;
  desc.backend = backend;
  desc.validation = validation;
  desc.debug = true;
  desc.onValidationError = [](const std::string& id, const std::string& message) {
    ADD_FAILURE() << "rhi validation " << id << ": " << message;
  };
  desc.log = [](const std::string& message) { ADD_FAILURE() << "driver debug message: " << message; };
  return makeDeviceWith(desc);
}

rhi::DeviceDesc strictDeviceDesc(const std::string& backend) {
  rhi::DeviceDesc desc;
  desc.backend = backend;
  desc.onValidationError = [](const std::string& id, const std::string& message) { ADD_FAILURE() << id << ": " << message; };
  desc.log = [](const std::string& message) { ADD_FAILURE() << "driver: " << message; };
  return desc;
}

std::unique_ptr<rhi::Device> makeDeviceWith(const rhi::DeviceDesc& desc) {
  const std::string& backend = desc.backend;
  std::string why;
  auto dev = rhi::createDevice(desc, &why);
  if (!dev) {
    if (requiredBackend(backend)) {
      ADD_FAILURE() << "backend " << backend << " is required (PARITY_REQUIRE_BACKENDS) but unavailable: " << why;
    } else {
      GTEST_MESSAGE_(("backend " + backend + " unavailable: " + why).c_str(), ::testing::TestPartResult::kSkip);
    }
  }
  return dev;
}

rhi::ShaderHandle makeShader(rhi::Device& dev, rhi::ShaderStage stage, const std::string& glsl) {
  rhi::CompiledShader compiled = rhi::compileGlslSource(glsl, "inline", stage);
  if (!compiled.ok()) {
    ADD_FAILURE() << "shader compile failed:\n" << compiled.error;
    return {};
  }
  rhi::ShaderDesc desc;
  desc.stage = stage;
  desc.spirv = compiled.spirv;
  return dev.createShader(desc);
}

std::string findExecutable(const std::vector<std::string>& names) {
  const char* path = std::getenv("PATH");
  std::stringstream s(path ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(s, dir, ':');)
    for (const std::string& name : names) {
      std::filesystem::path p = std::filesystem::path(dir) / name;
      if (::access(p.c_str(), X_OK) == 0) return p.string();
    }
  return "";
}

std::vector<std::string> techniqueNames() {
  std::vector<std::string> names;
  for (const techniques::TechniqueEntry& e : techniques::techniqueRegistry()) names.push_back(e.name);
  return names;
}

std::string BackendTechniqueName::operator()(
    const ::testing::TestParamInfo<std::tuple<std::string, std::string>>& info) const {
  std::string name = std::get<1>(info.param) + "_" + std::get<0>(info.param);
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

bool hasLossyTarget(const std::string& technique) {
  techniques::RenderSettings settings;
  for (const platforms::LogicalTarget& t : techniques::createTechnique(technique)->logicalTargets(settings)) {
    const bool exact = t.format == platforms::LogicalFormat::Output || t.format == platforms::LogicalFormat::Rgba8Bits ||
                       t.format == platforms::LogicalFormat::R8Unorm || t.format == platforms::LogicalFormat::R32Float ||
                       (t.format == platforms::LogicalFormat::Depth24Stencil8 && !t.readLater);
    if (!exact) return true;
  }
  return false;
}

bool averagesSamples(const std::string& technique) {
  techniques::RenderSettings settings;
  for (const platforms::LogicalTarget& t : techniques::createTechnique(technique)->logicalTargets(settings))
    if (t.samples > 1 && t.readLater && !t.readSamples) return true;
  return false;
}

std::vector<float> redChannel(const std::vector<uint8_t>& texels, rhi::Format format) {
  const bool isFloat = format == rhi::Format::R32F || format == rhi::Format::RGBA32F;
  const size_t stride = format == rhi::Format::RGBA32F ? 16 : format == rhi::Format::RGBA8 || format == rhi::Format::R32F ? 4 : 1;
  EXPECT_TRUE(isFloat || format == rhi::Format::R8 || format == rhi::Format::RGBA8) << "no red decode of this format";
  std::vector<float> red;
  for (size_t i = 0; i + stride <= texels.size(); i += stride) {
    float v = texels[i] / 255.0f;
    if (isFloat) std::memcpy(&v, texels.data() + i, sizeof(v));
    red.push_back(v);
  }
  return red;
}

std::vector<uint32_t> openGlPort(rhi::ShaderStage stage, const std::string& source, uint32_t defaultUniformBinding) {
  rhi::ShaderCompileOptions options;
  options.openGlSource = true;
  options.defaultUniformBinding = defaultUniformBinding;
  rhi::CompiledShader c = rhi::compileGlslSource(source, "port", stage, options);
  EXPECT_TRUE(c.ok()) << c.error;
  return c.spirv;
}

}  // namespace parity::test
