// The driver-level checks the whole suite relies on are really active. test::makeDevice turns on
// the GL debug context (KHR_debug) and the Khronos Vulkan validation layer and fails a test on any
// message; if the layer were missing or the debug context silently not granted, every test would
// pass without being checked. Each test here makes one call that the backend's validation must
// flag (parity's own validation layer is off, so the call reaches the driver) and expects the
// message.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/test_support.h"

using namespace parity;

namespace {

class DriverValidation : public ::testing::TestWithParam<std::string> {};

TEST_P(DriverValidation, AnInvalidCallReachingTheDriverIsReported) {
  std::vector<std::string> messages;
  rhi::DeviceDesc desc;
  desc.backend = GetParam();
  desc.validation = false;  // let the invalid call through to the driver
  desc.debug = true;
  desc.log = [&messages](const std::string& m) { messages.push_back(m); };
  auto dev = test::makeDeviceWith(desc);
  if (!dev) return;
  ASSERT_TRUE(messages.empty()) << "messages before any call: " << messages.front();

  // A 4x4 texture with 8 mip levels (at most 3 exist): VUID-VkImageCreateInfo-mipLevels-00947
  // for Vulkan, GL_INVALID_OPERATION from glTextureStorage2D for GL. Neither driver touches
  // memory it does not own for it (GL refuses the storage, lavapipe sizes levels down to 1x1).
  rhi::TextureDesc texture;
  texture.width = 4;
  texture.height = 4;
  texture.mipLevels = 8;
  texture.label = "too-many-mips";
  rhi::TextureHandle handle = dev->createTexture(texture);
  if (handle) dev->destroy(handle);
  dev->submit();
  dev.reset();

  ASSERT_FALSE(messages.empty())
      << "no driver message for an invalid call: the " << GetParam()
      << " debug output is not active (Vulkan: is vulkan-validationlayers installed? GL: debug context?)";
  std::string all;
  for (const auto& m : messages) all += m + "\n";
  EXPECT_NE(all.find("error"), std::string::npos) << all;
}

INSTANTIATE_TEST_SUITE_P(Backends, DriverValidation, ::testing::ValuesIn(test::allBackends()), test::BackendName{});

}  // namespace
