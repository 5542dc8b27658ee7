// Diagnosis of failed comparisons on real renders: each classic porting bug planted in a
// rendered frame must be named; genuine regressions (a light missing, a material changed) must
// not get one of those names. And the tolerances' sensitivity: perturbed copies of real outputs
// (1-pixel shift, channel swap, a light removed, wrong mip) must fail their case's tolerance.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebufalgo.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>

#include "harness/compare/diagnosis.h"
#include "harness/compare/diff.h"
#include "harness/compare/flip.h"
#include "harness/run/golden.h"
#include "harness/run/render.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

constexpr int kW = 160, kH = 90;

harness::RenderRequest request(uint32_t lights = 24) {
  harness::RenderRequest r;
  r.frame.technique = "forward";
  r.frame.scene = "default";
  r.frame.width = kW;
  r.frame.height = kH;
  r.frame.sceneParams.lightCount = lights;
  return r;
}

// Applies f to every RGB value of an 8-bit copy (the planted image is stored as a render would be).
OIIO::ImageBuf mapValues(const OIIO::ImageBuf& src, const std::function<float(float)>& f) {
  OIIO::ImageBuf out;
  out.copy(src, OIIO::TypeDesc::UINT8);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      float p[4] = {0, 0, 0, 1};
      src.getpixel(x, y, p, 4);
      for (int c = 0; c < 3; ++c) p[c] = std::clamp(f(p[c]), 0.0f, 1.0f);
      out.setpixel(x, y, p, 4);
    }
  return out;
}

// out(x, y) = sample(x, y) for a sampler reading the source with clamped coordinates.
OIIO::ImageBuf mapPixels(const OIIO::ImageBuf& src, const std::function<void(int, int, float*)>& sample) {
  OIIO::ImageBuf out;
  out.copy(src, OIIO::TypeDesc::UINT8);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      float p[4] = {0, 0, 0, 1};
      sample(x, y, p);
      out.setpixel(x, y, p, 4);
    }
  return out;
}

float at(const OIIO::ImageBuf& img, int x, int y, int c) {
  float p[4] = {0, 0, 0, 1};
  img.getpixel(std::clamp(x, 0, kW - 1), std::clamp(y, 0, kH - 1), p, 4);
  return p[c];
}

OIIO::ImageBuf shifted(const OIIO::ImageBuf& g, int dx, int dy) {
  return mapPixels(g, [&](int x, int y, float* p) {
    for (int c = 0; c < 4; ++c) p[c] = at(g, x - dx, y - dy, c);
  });
}

// A frame with n lights and the same frame with its last light removed, for the largest n <= 24
// whose last light lights at least 0.5% of the frame (some lights of the default scene light a
// few pixels, or none: a regression a per-pixel tolerance cannot be asked to see).
bool lightRemovedPair(rhi::Device& device, OIIO::ImageBuf* withLight, OIIO::ImageBuf* without, uint32_t* lights) {
  harness::RenderResult previous = harness::renderFrame(device, request(24));
  for (uint32_t n = 24; n >= 2 && previous.ok; --n) {
    harness::RenderResult fewer = harness::renderFrame(device, request(n - 1));
    if (!fewer.ok) return false;
    size_t changed = 0;
    for (size_t k = 0; k + 3 < fewer.texels.size() && k + 3 < previous.texels.size(); k += 4)
      changed += std::memcmp(&fewer.texels[k], &previous.texels[k], 3) != 0;
    if (changed * 200 >= size_t{kW} * kH) {
      *withLight = previous.image;
      *without = fewer.image;
      *lights = n;
      return true;
    }
    previous = std::move(fewer);
  }
  return false;
}

class Diagnosis : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    device_ = test::makeDevice(GetParam());
    if (!device_) return;
    harness::RenderResult r = harness::renderFrame(*device_, request());
    ASSERT_TRUE(r.ok) << r.error;
    golden_ = r.image;
  }
  std::unique_ptr<rhi::Device> device_;
  OIIO::ImageBuf golden_;
};

TEST_P(Diagnosis, NamesEachPlantedPortingBug) {
  if (!device_) return;
  const OIIO::ImageBuf& g = golden_;
  struct Plant {
    std::string cause;
    OIIO::ImageBuf image;
  };
  std::vector<Plant> plants = {
      {"vertical flip", OIIO::ImageBufAlgo::flip(g)},
      {"horizontal flip", OIIO::ImageBufAlgo::flop(g)},
      {"integer shift by (1, 0) pixels", shifted(g, 1, 0)},
      {"integer shift by (0, -2) pixels", shifted(g, 0, -2)},
      {"half-pixel shift by (0.5, 0.5)", mapPixels(g,
                                                   [&](int x, int y, float* p) {
                                                     for (int c = 0; c < 4; ++c)
                                                       p[c] = 0.25f * (at(g, x, y, c) + at(g, x + 1, y, c) +
                                                                       at(g, x, y + 1, c) + at(g, x + 1, y + 1, c));
                                                   })},
      {"RGBA/BGRA swizzle", mapPixels(g,
                                      [&](int x, int y, float* p) {
                                        p[0] = at(g, x, y, 2);
                                        p[1] = at(g, x, y, 1);
                                        p[2] = at(g, x, y, 0);
                                        p[3] = at(g, x, y, 3);
                                      })},
      {"sRGB applied twice",
       mapValues(g, [](float v) { return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1 / 2.4f) - 0.055f; })},
      {"sRGB missing", mapValues(g, [](float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); })},
      {"value range scaled x32", mapValues(g, [](float v) { return v * 32.0f; })},
      {"value range 0..1 vs -1..1 (written as x*0.5+0.5)", mapValues(g, [](float v) { return v * 0.5f + 0.5f; })},
      {"precision loss of 3 bits", mapValues(g, [](float v) {
         int q = static_cast<int>(std::lround(v * 255.0f));
         return static_cast<float>((q >> 3) << 3) / 255.0f;
       })},
  };
  for (const Plant& p : plants) {
    std::optional<harness::Diagnosis> d = harness::diagnose(g, p.image);
    ASSERT_TRUE(d.has_value()) << "no cause named for a planted " << p.cause;
    EXPECT_EQ(d->cause, p.cause) << d->detail;
  }
  EXPECT_FALSE(harness::diagnose(g, g).has_value()) << "identical images need no diagnosis";
}

TEST_P(Diagnosis, GenuineRegressionsGetNoPortingBugName) {
  if (!device_) return;
  OIIO::ImageBuf withLight, without;
  uint32_t lights = 0;
  ASSERT_TRUE(lightRemovedPair(*device_, &withLight, &without, &lights)) << "no visible light in the default scene";
  std::optional<harness::Diagnosis> d = harness::diagnose(withLight, without);
  EXPECT_FALSE(d.has_value()) << "light " << lights << " missing was named " << d->cause << ": " << d->detail;

  // A material changed: one object's region (the middle of the frame) turns redder.
  OIIO::ImageBuf tinted = mapPixels(golden_, [&](int x, int y, float* p) {
    for (int c = 0; c < 4; ++c) p[c] = at(golden_, x, y, c);
    if (x > kW / 3 && x < kW / 2 && y > kH / 3 && y < 2 * kH / 3) {
      p[1] *= 0.6f;
      p[2] *= 0.6f;
    }
  });
  d = harness::diagnose(golden_, tinted);
  EXPECT_FALSE(d.has_value()) << "a changed material was named " << d->cause << ": " << d->detail;
}

TEST_P(Diagnosis, PerturbedOutputsFailTheirCaseTolerance) {
  if (!device_) return;
  harness::CaseKey key{"forward", "default", "reference", GetParam()};
  harness::Tolerance tolerance;
  std::string error;
  ASSERT_TRUE(harness::loadTolerance((fs::path(harness::defaultGoldenDir()) / "tolerances.json").string(), key, &tolerance,
                                     &error))
      << error;
  OIIO::ImageBuf withLight, without;
  uint32_t lights = 0;
  ASSERT_TRUE(lightRemovedPair(*device_, &withLight, &without, &lights)) << "no visible light in the default scene";
  // Wrong mip: the frame as its next-smaller mip level, magnified back (2x2 box, then nearest).
  OIIO::ImageBuf wrongMip = mapPixels(golden_, [&](int x, int y, float* p) {
    int bx = x / 2 * 2, by = y / 2 * 2;
    for (int c = 0; c < 4; ++c)
      p[c] = 0.25f * (at(golden_, bx, by, c) + at(golden_, bx + 1, by, c) + at(golden_, bx, by + 1, c) +
                      at(golden_, bx + 1, by + 1, c));
  });
  OIIO::ImageBuf swapped = mapPixels(golden_, [&](int x, int y, float* p) {
    p[0] = at(golden_, x, y, 2);
    p[1] = at(golden_, x, y, 1);
    p[2] = at(golden_, x, y, 0);
    p[3] = at(golden_, x, y, 3);
  });
  struct Perturbed {
    const char* name;
    OIIO::ImageBuf image, golden;
  };
  std::vector<Perturbed> perturbed = {{"1-pixel shift", shifted(golden_, 1, 0), golden_},
                                      {"channel swap", swapped, golden_},
                                      {"a light removed", without, withLight},
                                      {"wrong mip", wrongMip, golden_}};
  for (const Perturbed& p : perturbed) {
    harness::DiffResult d = harness::diffImages(p.image, p.golden, tolerance.golden);
    harness::FlipResult flip = harness::computeLdrFlip(p.golden, p.image);
    ASSERT_TRUE(flip.ok) << flip.error;
    bool fails = d.verdict == harness::DiffVerdict::Fail || flip.mean > tolerance.flipMean;
    EXPECT_TRUE(fails) << p.name << " passes the tolerance of " << key.id() << " (" << tolerance.source
                       << "): " << harness::summaryLine(d) << ", FLIP mean " << flip.mean;
    // The pixel rule alone must catch each of them too: FLIP is the second line, not the only one.
    EXPECT_EQ(d.verdict, harness::DiffVerdict::Fail) << p.name << ": " << harness::summaryLine(d);
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, Diagnosis, ::testing::ValuesIn(test::allBackends()), test::BackendName());

}  // namespace
