// Per-pass metrics decode what each platform stores: a two-channel logical target (normals in the
// half-sphere mapping of shaders/include/normal_encoding.glsl) is reference RG32F, dx10
// RG16_UNORM, ps3 A8R8G8B8 holding two little-endian 16-bit words and x360 RG16_SNORM holding
// the k_16_16 fixed point of the DSF path. Two normals about 10 degrees apart must measure their
// angle on every platform, as the shaders would see them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>
#include <glm/glm.hpp>

#include "harness/compare/attachments.h"
#include "platforms/common/platform_params.h"
#include "platforms/x360/fixed16.h"
#include "platforms/x360/resolve.h"

using namespace parity;

namespace {

// Eq. 1 of the half-sphere mapping, as encodeNormalHalfSphere writes it.
glm::vec2 encodeHalfSphere(glm::vec3 n) {
  const glm::vec3 h = glm::normalize(n + glm::vec3(0, 0, 1));
  return glm::vec2(h) * 0.5f + 0.5f;
}

// One texel holding logical value `v` as `platform` stores it in the dumped attachment.
OIIO::ImageBuf stored(const std::string& platform, glm::vec2 v) {
  std::vector<float> texel;
  if (platform == "ps3") {
    for (float c : {v.x, v.y}) {
      const auto word = static_cast<uint32_t>(std::lround(c * 65535.0f));
      texel.push_back(float(word & 255u) / 255.0f);  // host r (b): the low byte
      texel.push_back(float(word >> 8) / 255.0f);    // host g (a): the high byte
    }
  } else if (platform == "x360") {
    const platforms::x360::DsfPathSpec path = platforms::x360::dsfPath(platforms::PlatformParams{}.dsfResolvePath);
    for (float c : {v.x, v.y}) {
      const int16_t s = platforms::x360::encodeFixed16(c * path.shaderScale + path.shaderOffset, path.colorExpBias).value;
      texel.push_back(std::max(float(s) / 32767.0f, -1.0f));  // RG16_SNORM read back as float
    }
  } else if (platform == "dx10") {
    for (float c : {v.x, v.y}) texel.push_back(std::round(c * 65535.0f) / 65535.0f);
  } else {
    texel = {v.x, v.y};
  }
  OIIO::ImageBuf image(OIIO::ImageSpec(1, 1, int(texel.size()), OIIO::TypeDesc::FLOAT));
  image.setpixel(0, 0, texel.data(), int(texel.size()));
  return image;
}

const char* formatOn(const std::string& platform) {
  return platform == "ps3" ? "RGBA8" : platform == "x360" ? "RG16_SNORM" : platform == "dx10" ? "RG16_UNORM" : "RG32F";
}

TEST(Attachments, HalfSphereNormalsMeasureTheirAngleOnEveryPlatformsStorage) {
  const glm::vec3 a = glm::normalize(glm::vec3(0.3f, 0.2f, 0.9f));
  const float angle = glm::radians(10.0f);
  const glm::vec3 b = glm::vec3(a.x * std::cos(angle) + a.z * std::sin(angle), a.y,
                                -a.x * std::sin(angle) + a.z * std::cos(angle));  // a turned 10 degrees about y
  // a is not perpendicular to y: the angle between a and b is a little under 10 degrees.
  const double expected = glm::degrees(std::acos(double(glm::dot(a, b))));
  for (const std::string platform : {"reference", "dx10", "ps3", "x360"}) {
    SCOPED_TRACE(platform);
    const harness::AttachmentClass cls =
        harness::classifyAttachment("gbuffer.normals", formatOn(platform), "rg16_unorm", platform);
    EXPECT_EQ(cls.normals, harness::NormalEncoding::HalfSphere);
    const harness::AttachmentMetrics m =
        harness::compareAttachment(cls, stored(platform, encodeHalfSphere(a)), stored(platform, encodeHalfSphere(b)), {});
    ASSERT_TRUE(m.ok) << m.error;
    EXPECT_EQ(m.metric, "angular_error_deg");
    // 16-bit storage (x360: steps of 1/65536 of v through the path's scale) moves it by far less.
    EXPECT_NEAR(m.max, expected, 0.02);
    EXPECT_GT(expected, 9.5);
  }
}

// A DSF-like two-channel target that is not normals compares its logical values in steps of 16
// bits, whatever the storage: one step of v differs, two steps fail the default 1.5 steps.
TEST(Attachments, TwoChannelDataIsComparedAsTheLogicalValues) {
  for (const std::string platform : {"reference", "dx10", "ps3", "x360"}) {
    SCOPED_TRACE(platform);
    const harness::AttachmentClass cls = harness::classifyAttachment("gbuffer.dsf", formatOn(platform), "rg16_unorm", platform);
    const glm::vec2 v(0.25f, 0.75f);
    const harness::AttachmentMetrics same = harness::compareAttachment(cls, stored(platform, v), stored(platform, v), {});
    EXPECT_EQ(same.max, 0.0);
    const harness::AttachmentMetrics off =
        harness::compareAttachment(cls, stored(platform, v), stored(platform, v + glm::vec2(4.0f / 65535.0f, 0.0f)), {});
    EXPECT_NEAR(off.max, 4.0 / 65535.0, 0.6 / 65535.0);
    EXPECT_EQ(off.differing, 1u);
  }
}

}  // namespace
