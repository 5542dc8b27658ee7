// X5 in technique renders: on x360 with D3DRS_HALFPIXELOFFSET false (the console's default)
// every technique rasterises with D3D9 pixel centres (platforms/platform_device.h), so its image
// differs from the reference platform's; with HALFPIXELOFFSET true the centres are the host's
// again. The difference between the two x360 renders is the pixel-centre quirk alone, and the
// run's diagnosis must name it as a half-pixel shift in rasterisation: content moved half a pixel
// down and to the right, i.e. every pixel sampled half a pixel up and to the left.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <tuple>

#include "harness/compare/diagnosis.h"
#include "harness/run/render.h"
#include "techniques/technique.h"
#include "test_support.h"

using namespace parity;

namespace {

using Param = std::tuple<std::string, std::string>;  // backend, technique

harness::RenderResult render(rhi::Device& device, const std::string& technique, platforms::PlatformId platform,
                             bool halfPixelOffset) {
  harness::RenderRequest r;
  r.frame.technique = technique;
  r.frame.platform = platform;
  r.frame.platformParams.halfPixelOffset = halfPixelOffset;
  return harness::renderFrame(device, r);  // the CI size, 320x180, as the goldens
}

class TechniquePixelCenters : public ::testing::TestWithParam<Param> {};

TEST_P(TechniquePixelCenters, X360DrawsWithD3D9CentresUnlessHalfPixelOffset) {
  const auto& [backend, technique] = GetParam();
  auto device = test::makeDevice(backend);
  if (!device) return;
  harness::RenderResult reference = render(*device, technique, platforms::PlatformId::Reference, false);
  harness::RenderResult d3d9 = render(*device, technique, platforms::PlatformId::X360, false);
  harness::RenderResult d3d10 = render(*device, technique, platforms::PlatformId::X360, true);
  ASSERT_TRUE(reference.ok && d3d9.ok && d3d10.ok) << reference.error << d3d9.error << d3d10.error;

  EXPECT_NE(d3d9.texels, reference.texels) << technique << " renders the reference image on x360";
  EXPECT_NE(d3d9.texels, d3d10.texels) << "x360.halfpixeloffset changes nothing in " << technique;
  // Techniques whose targets have no lossy x360 path (8-bit colour resolved bit for bit, depth
  // no pass reads) render the reference image with D3D10 centres: the pixel centre is the only
  // x360 quirk they show.
  // A multisampled frame is resolved by the x360 rule (the samples' bytes averaged, ties rounded
  // up, as Xenia packs) where the hosts resolve as their driver does: at most 1/255 apart, and
  // apart somewhere (ties are common where the edges cut the samples in halves).
  if (!test::hasLossyTarget(technique) && !test::averagesSamples(technique)) {
    EXPECT_EQ(d3d10.texels, reference.texels) << technique << " with HALFPIXELOFFSET true";
  } else if (!test::hasLossyTarget(technique)) {
    ASSERT_EQ(d3d10.texels.size(), reference.texels.size());
    size_t apart = 0;
    for (size_t i = 0; i < reference.texels.size(); ++i) {
      const int step = std::abs(int(d3d10.texels[i]) - int(reference.texels[i]));
      EXPECT_LE(step, 1) << technique << ": byte " << i;
      apart += step != 0;
    }
    EXPECT_GT(apart, 0u) << technique << ": the x360 resolve rounds like the host's everywhere";
  }

  // HDR's exposure is the log-average luminance of the whole frame, which the shift changes
  // too: every pixel moves a little, which no local candidate explains. The shadow techniques'
  // maps are rasterised half a shadow texel off as well, which moves shadow edges by another
  // amount than the image's (docs/HARNESS.md, "What each platform changes").
  if (technique == "hdr") return;
  const techniques::TechniqueEntry* entry = nullptr;
  for (const techniques::TechniqueEntry& e : techniques::techniqueRegistry())
    if (e.name == technique) entry = &e;
  if (entry && entry->rendersShadows) return;
  std::optional<harness::Diagnosis> d = harness::diagnose(d3d10.image, d3d9.image);
  ASSERT_TRUE(d.has_value()) << technique << ": the D3D9 centres got no name";
  EXPECT_EQ(d->cause, "half-pixel shift by (-0.5, -0.5) in rasterisation") << technique << ": " << d->detail;
}

INSTANTIATE_TEST_SUITE_P(Techniques, TechniquePixelCenters,
                         ::testing::Combine(::testing::ValuesIn(test::allBackends()), ::testing::ValuesIn(test::techniqueNames())),
                         test::BackendTechniqueName());

}  // namespace
