// HDR tone mapping: the log-average luminance the GPU reduction computes equals a CPU computation
// over the read-back 16-bit float accumulation buffer; and the tone-mapped image keeps detail
// where the accumulation exceeds 1.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "scene/scene_gpu.h"
#include "techniques/hdr/hdr.h"
#include "test_support.h"

using namespace parity;

namespace {

float halfToFloat(uint16_t h) {
  uint32_t sign = (h >> 15) & 1, exp = (h >> 10) & 0x1F, mant = h & 0x3FF;
  float v = exp == 0 ? std::ldexp(static_cast<float>(mant), -24)
                     : std::ldexp(static_cast<float>(mant | 0x400), static_cast<int>(exp) - 25);
  return sign ? -v : v;
}

class EffectsHdr : public ::testing::TestWithParam<std::string> {};

TEST_P(EffectsHdr, LogAverageLuminanceMatchesCpu) {
  auto dev = test::makeDevice(GetParam());
  if (!dev) return;
  scene::Scene s;
  scene::SceneParams params;
  params.lightCount = 24;
  params.lightSize = scene::LightSize::Big;  // overlapping lights push the accumulation above 1
  std::string error;
  ASSERT_TRUE(scene::makeScene("default", params, &s, &error)) << error;
  scene::SceneGpu gpu(*dev, s);
  techniques::HdrToneMapping hdr;
  techniques::RenderSettings settings;
  settings.width = 160;
  settings.height = 90;
  hdr.prepare(*dev, settings);
  hdr.render(*dev, gpu, s.cameras[0]);
  dev->submit();
  std::vector<uint8_t> accumulation;
  for (const techniques::NamedTarget& t : hdr.targets())
    if (t.name == "hdr.accumulation") accumulation = dev->readTexture(t.texture);
  std::vector<uint8_t> resultBytes = dev->readBuffer(hdr.luminanceResult(), 0, 16);
  hdr.release(*dev);
  ASSERT_EQ(accumulation.size(), size_t{160} * 90 * 8);
  ASSERT_EQ(resultBytes.size(), 16u);
  float result[4];
  std::memcpy(result, resultBytes.data(), 16);

  double sumLog = 0;
  size_t above1 = 0;
  for (size_t i = 0; i < size_t{160} * 90; ++i) {
    uint16_t h[4];
    std::memcpy(h, accumulation.data() + i * 8, 8);
    double L = 0.2126 * halfToFloat(h[0]) + 0.7152 * halfToFloat(h[1]) + 0.0722 * halfToFloat(h[2]);
    above1 += L > 1.0;
    sumLog += std::log(hdr.params().delta + std::max(L, 0.0));
  }
  double cpu = std::exp(sumLog / (160.0 * 90.0));
  EXPECT_EQ(result[2], 160.0f * 90.0f);
  EXPECT_NEAR(result[0], cpu, cpu * 1e-4) << "GPU log-average " << result[0] << ", CPU " << cpu;
  EXPECT_GT(cpu, 0.01) << "the scene is too dark to test tone mapping";
  EXPECT_GT(above1, 0u) << "the accumulation never exceeds 1: not an HDR test scene";
}

INSTANTIATE_TEST_SUITE_P(Backends, EffectsHdr, ::testing::ValuesIn(test::allBackends()), test::BackendName());

}  // namespace
