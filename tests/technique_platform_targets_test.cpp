// Every technique renders through its platform's targets: it declares its frame colour (the
// Output the harness reads) and its scene depth as logical targets, the platform plans them
// (x360: EDRAM placement and the resolve of the colour to the front buffer, padded to the resolve
// granularity as a port allocates it), and what a technique still renders outside the plan is exactly the
// list below, each with the reason it is not a platform target yet. A technique that starts
// rendering into a texture of its own, or one whose target moves into the plan, fails here until
// the list says so. On dx10 and ps3 a technique's image differs from the reference platform's
// exactly when one of its targets is stored lossily there.
#include <gtest/gtest.h>

#include <string>
#include <tuple>

#include "harness/run/render.h"
#include "platforms/platform_layer.h"
#include "techniques/technique.h"
#include "test_support.h"

using namespace parity;

namespace {

// Every technique's colour and depth are platform targets: of its main plan, or (inferred's,
// at the output size where its G-buffers are smaller) of a plan of their own size.
TEST(TechniquePlatformTargets, EveryTechniqueDeclaresItsOutputAndDepth) {
  for (const techniques::TechniqueEntry& e : techniques::techniqueRegistry()) {
    for (platforms::PlatformId p : {platforms::PlatformId::Reference, platforms::PlatformId::Dx10,
                                    platforms::PlatformId::Ps3, platforms::PlatformId::X360}) {
      techniques::RenderSettings settings;
      settings.platform = p;
      const std::unique_ptr<techniques::Technique> technique = e.create();
      std::vector<platforms::LogicalTarget> all = technique->logicalTargets(settings);
      for (const techniques::Technique::SizedTargets& s : technique->furtherTargetPlans(settings))
        all.insert(all.end(), s.targets.begin(), s.targets.end());
      bool output = false, depth = false;
      for (const platforms::LogicalTarget& t : all) {
        output |= t.name == "color" && t.format == platforms::LogicalFormat::Output;
        depth |= t.format == platforms::LogicalFormat::Depth24Stencil8;
      }
      EXPECT_TRUE(output) << e.name << " on " << platforms::platformName(p) << ": no Output colour target";
      EXPECT_TRUE(depth) << e.name << " on " << platforms::platformName(p) << ": no depth target";
    }
  }
}

using Param = std::tuple<std::string, std::string>;  // backend, technique

class TechniquePlatformTargetsOnX360 : public ::testing::TestWithParam<Param> {};

TEST_P(TechniquePlatformTargetsOnX360, ColourAndDepthAreThePlatformsAndNothingElseEscapes) {
  const auto& [backend, technique] = GetParam();
  auto device = test::makeDevice(backend);
  if (!device) return;
  harness::RenderRequest r;
  r.frame.technique = technique;
  r.frame.platform = platforms::PlatformId::X360;
  r.frame.readTargets = true;
  harness::RenderResult result = harness::renderFrame(*device, r);
  ASSERT_TRUE(result.ok) << result.error;

  // A port's targets: every surface padded to the resolve granularity (the 180-row colour too),
  // so no resolve breaks X3, and no rule fires but the known port problems' warnings.
  for (const platforms::Diagnostic& d : result.diagnostics)
    EXPECT_NE(d.severity, platforms::Severity::Error) << technique << ": " << d.format();

  // Every attachment a pass renders to is a platform target: none is left in host formats.
  std::string list;
  for (const std::string& s : result.unplannedTargets) list += "\n  " + s;
  EXPECT_TRUE(result.unplannedTargets.empty()) << technique << " renders outside the platform's plan:" << list;
}

class TechniqueOnDx10AndPs3 : public ::testing::TestWithParam<Param> {};

// What dx10 and ps3 change in a technique's image is its storage alone (their pixel centres are
// the host's): a technique with a lossy target differs from the reference platform's image, one
// without renders it bit for bit (docs/HARNESS.md, "What each platform changes").
TEST_P(TechniqueOnDx10AndPs3, DiffersFromTheReferenceExactlyWhenATargetIsLossy) {
  const auto& [backend, technique] = GetParam();
  auto device = test::makeDevice(backend);
  if (!device) return;
  auto render = [&](platforms::PlatformId platform) {
    harness::RenderRequest r;
    r.frame.technique = technique;
    r.frame.platform = platform;
    return harness::renderFrame(*device, r);
  };
  harness::RenderResult reference = render(platforms::PlatformId::Reference);
  ASSERT_TRUE(reference.ok) << reference.error;
  const bool lossy = test::hasLossyTarget(technique);
  for (platforms::PlatformId platform : {platforms::PlatformId::Dx10, platforms::PlatformId::Ps3}) {
    harness::RenderResult console = render(platform);
    ASSERT_TRUE(console.ok) << console.error;
    if (lossy)
      EXPECT_NE(console.texels, reference.texels) << technique << " on " << platforms::platformName(platform)
                                                  << ": a lossy target that changes nothing";
    else
      EXPECT_EQ(console.texels, reference.texels) << technique << " on " << platforms::platformName(platform)
                                                  << ": no lossy target, yet the image differs";
  }
}

INSTANTIATE_TEST_SUITE_P(AllTechniques, TechniqueOnDx10AndPs3,
                         ::testing::Combine(::testing::Values("gl", "vk"), ::testing::ValuesIn(test::techniqueNames())),
                         test::BackendTechniqueName());
INSTANTIATE_TEST_SUITE_P(AllTechniques, TechniquePlatformTargetsOnX360,
                         ::testing::Combine(::testing::Values("gl", "vk"), ::testing::ValuesIn(test::techniqueNames())),
                         test::BackendTechniqueName());

}  // namespace
