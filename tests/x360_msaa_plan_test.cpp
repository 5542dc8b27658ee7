// x360 EDRAM placement of MSAA and 64-bpp targets as planTargets() plans them for a technique's
// passes, against the CPU model's surface sizes (X1 XGSurfaceSize) and the pack's table.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "platforms/platform_layer.h"
#include "platforms/x360/edram.h"
#include "techniques/inferred/inferred.h"

namespace parity::platforms {
namespace {

bool is64bpp(LogicalFormat f) { return f == LogicalFormat::Rgba16Hdr; }

std::vector<LogicalTarget> inferredTargets(uint32_t samples) {
  techniques::InferredLighting technique;
  std::vector<LogicalTarget> targets = technique.logicalTargets({});
  for (LogicalTarget& t : targets) t.samples = samples;
  return targets;
}

// Every target's tiles are the model's; the G-buffer bases follow one another from tile 0 (mod
// 2048), and the L-buffer takes tile 0 (the resolved G-buffer colour tiles, X4) when it fits
// there without touching depth, else it follows them too.
void expectModelPlacement(const TargetPlan& plan, x360::MsaaSamples msaa) {
  uint32_t next = 0;
  for (const PhysicalTarget& t : plan.targets) {
    SCOPED_TRACE(t.logical.name);
    EXPECT_TRUE(t.inEdram);
    EXPECT_EQ(t.samples, x360::sampleCount(msaa));
    EXPECT_EQ(t.edramTiles, x360::surfaceSizeTiles(plan.width, plan.height, msaa, is64bpp(t.logical.format)));
    if (t.logical.role == TargetRole::LBuffer) {
      const PhysicalTarget* depth = plan.find("gbuffer.depth");
      ASSERT_NE(depth, nullptr);
      const bool fitsAtZero = t.edramTiles <= depth->edramBase && depth->edramBase + depth->edramTiles <= x360::kEdramTileCount;
      EXPECT_EQ(t.edramBase, fitsAtZero ? 0u : next % x360::kEdramTileCount);
      if (fitsAtZero) continue;
    }
    EXPECT_EQ(t.edramBase, next % x360::kEdramTileCount);
    next += t.edramTiles;
  }
}

TEST(X360MsaaPlan, InferredTargetsAt4xTakeTheModelsTiles) {
  const std::vector<LogicalTarget> targets = inferredTargets(4);
  TargetPlan plan = planTargets(PlatformId::X360, targets, 256, 256);
  expectModelPlacement(plan, x360::MsaaSamples::k4X);
  // Pack table (X1 (3)): 256x256 4x 32 bpp = 224 tiles; 64 bpp doubles it.
  for (const PhysicalTarget& t : plan.targets) EXPECT_EQ(t.edramTiles, is64bpp(t.logical.format) ? 448u : 224u);
  // 4 x 224 + 448 = 1344 tiles: no error, no wrap.
  EXPECT_FALSE(plan.diagnostics.hasErrors()) << plan.diagnostics.format();
  EXPECT_FALSE(plan.diagnostics.has("W_EDRAM_WRAP")) << plan.diagnostics.format();
}

TEST(X360MsaaPlan, FourTimesTheSamplesOverflowTheGeometryPass) {
  // 1024x576 (the X4 vectors' size): 1x 32 bpp is 468 tiles per surface, so the geometry pass's
  // four surfaces (two k_16_16, one k_8_8_8_8, depth) take 1872 tiles and fit; at 4x each takes
  // 1872 (pack table) and the pass cannot be placed without overlap.
  TargetPlan one = planTargets(PlatformId::X360, inferredTargets(1), 1024, 576);
  expectModelPlacement(one, x360::MsaaSamples::k1X);
  ASSERT_NE(one.find("lbuffer"), nullptr);
  EXPECT_EQ(one.find("lbuffer")->edramTiles, 936u);  // pack: 1x 64 bpp
  ASSERT_NE(one.find("gbuffer.depth"), nullptr);
  EXPECT_EQ(one.find("gbuffer.depth")->edramTiles, 468u);  // pack X4: D24S8 at 1024x576
  TargetPlan four = planTargets(PlatformId::X360, inferredTargets(4), 1024, 576);
  expectModelPlacement(four, x360::MsaaSamples::k4X);
  for (const PhysicalTarget& t : four.targets) {
    if (!is64bpp(t.logical.format)) {
      EXPECT_EQ(t.edramTiles, 1872u) << t.logical.name;
    }
  }
  EXPECT_TRUE(four.diagnostics.has("E_EDRAM_OVERLAP")) << four.diagnostics.format();
  EXPECT_FALSE(one.diagnostics.has("E_EDRAM_OVERLAP")) << one.diagnostics.format();
}

TEST(X360MsaaPlan, SurfaceRulesSeeTheSampleCount) {
  // 1280x720 4x: 2880 tiles, more than EDRAM holds (pack: OVER).
  LogicalTarget big{"dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry", 4};
  TargetPlan tooLarge = planTargets(PlatformId::X360, {&big, 1}, 1280, 720);
  EXPECT_EQ(tooLarge.targets[0].edramTiles, 2880u);
  EXPECT_TRUE(tooLarge.diagnostics.has("E_EDRAM_SURFACE_TOO_LARGE")) << tooLarge.diagnostics.format();
  // Each target is placed at its own sample count. Whether a pass binds a 4x and a 1x target
  // together (one RB_SURFACE_INFO per draw) is the pass's business: the rule fires on the real
  // pass (PortingMistakes, mrt-msaa-mismatch), not on the plan.
  const LogicalTarget mixed[] = {{"normals", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry", 4},
                                 {"dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry", 1}};
  TargetPlan mismatch = planTargets(PlatformId::X360, mixed, 640, 360);
  EXPECT_EQ(mismatch.targets[0].edramTiles, 720u);  // pack: 640x360 4x 32 bpp
  EXPECT_EQ(mismatch.targets[1].edramTiles, 184u);  // pack: 640x360 1x 32 bpp
  EXPECT_FALSE(mismatch.diagnostics.has("E_MRT_SURFACE_INFO_MISMATCH")) << mismatch.diagnostics.format();
  // Targets in different passes may differ.
  const LogicalTarget separate[] = {{"normals", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry", 4},
                                    {"lbuffer", LogicalFormat::Rgba16Hdr, true, TargetRole::LBuffer, "light", 1}};
  TargetPlan fine = planTargets(PlatformId::X360, separate, 640, 360);
  EXPECT_EQ(fine.targets[1].edramTiles, 368u);  // pack: 640x360 1x 64 bpp
  EXPECT_EQ(fine.targets[1].edramBase, 720u);
  EXPECT_FALSE(fine.diagnostics.has("E_MRT_SURFACE_INFO_MISMATCH")) << fine.diagnostics.format();
}

// X4 with the technique's own targets: the L-buffer lands in the G-buffer colour tiles (as the
// paper places it), which the plan accepts because those are resolved before the light pass; the
// depth it is rendered with stays live, so the L-buffer forced over depth fires the diagnostic.
TEST(X360MsaaPlan, InferredLBufferReusesTheGBufferColourTiles) {
  TargetPlan plan = planTargets(PlatformId::X360, inferredTargets(1), 1024, 576);
  const PhysicalTarget* lbuffer = plan.find("lbuffer");
  const PhysicalTarget* depth = plan.find("gbuffer.depth");
  ASSERT_NE(lbuffer, nullptr);
  ASSERT_NE(depth, nullptr);
  // Pack X4 (3): G0, G1 (and the specular target) from tile 0, depth after them; L-buffer at 0.
  EXPECT_EQ(lbuffer->edramBase, 0u);
  EXPECT_EQ(lbuffer->edramTiles, 936u);
  EXPECT_EQ(depth->edramBase, 1404u);
  EXPECT_FALSE(plan.diagnostics.hasErrors()) << plan.diagnostics.format();

  // The same targets at 1280x720 do not fit: depth wraps onto [112, 832) and the L-buffer (1440
  // tiles) finds no place clear of it, so the pair live together in the light pass is reported.
  TargetPlan big = planTargets(PlatformId::X360, inferredTargets(1), 1280, 720);
  EXPECT_TRUE(big.diagnostics.has("E_LBUF_DEPTH_ALIAS")) << big.diagnostics.format();
}

// Targets in different passes with no declared lifetimes keep the old placement and checks;
// declaring depth live in the light pass makes the L-buffer-over-depth pair a checked pair.
TEST(X360MsaaPlan, EveryPairLiveTogetherIsChecked) {
  // 1280x720 1x: normals 720 tiles, depth 720, L-buffer 1440: no placement avoids depth.
  std::vector<LogicalTarget> targets = {{"normals", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"},
                                        {"depth", LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer, "geometry"},
                                        {"lbuffer", LogicalFormat::Rgba16Hdr, true, TargetRole::LBuffer, "light"}};
  TargetPlan undeclared = planTargets(PlatformId::X360, targets, 1280, 720);
  EXPECT_EQ(undeclared.find("lbuffer")->edramBase, 1440u);  // after the others, as before
  EXPECT_FALSE(undeclared.diagnostics.has("E_LBUF_DEPTH_ALIAS")) << undeclared.diagnostics.format();
  targets[1].livePasses = {"geometry", "light"};
  targets[2].livePasses = {"light"};
  TargetPlan declared = planTargets(PlatformId::X360, targets, 1280, 720);
  EXPECT_TRUE(declared.diagnostics.has("E_LBUF_DEPTH_ALIAS")) << declared.diagnostics.format();
  EXPECT_FALSE(declared.diagnostics.has("E_USE_BEFORE_RESOLVE")) << "normals are resolved before the light pass";
  // At 1024x576 the L-buffer fits clear of depth (after it: normals end where depth starts).
  TargetPlan fits = planTargets(PlatformId::X360, targets, 1024, 576);
  EXPECT_EQ(fits.find("lbuffer")->edramBase, 936u);
  EXPECT_FALSE(fits.diagnostics.hasErrors()) << fits.diagnostics.format();
}

// Every platform plans the samples a technique asks for. A colour target a later pass reads is
// resolved by averaging: the host's MSAA resolve, or on x360 the EDRAM resolve (k0123); a target
// read sample by sample is read in place on the hosts and resolved sample by sample on x360.
TEST(MsaaPlan, EveryPlatformPlansTheSamplesItIsAskedFor) {
  std::vector<LogicalTarget> targets = {{"color", LogicalFormat::Rgba8Unorm, true, TargetRole::Plain, "draw", 4},
                                        {"depths", LogicalFormat::R32Float, true, TargetRole::Plain, "draw", 4},
                                        {"depth", LogicalFormat::Depth24Stencil8, false, TargetRole::Plain, "draw", 4}};
  targets[1].readSamples = true;
  for (PlatformId p : {PlatformId::Reference, PlatformId::Dx10, PlatformId::Ps3, PlatformId::X360}) {
    SCOPED_TRACE(std::string(platformName(p)));
    TargetPlan plan = planTargets(p, targets, 64, 64);
    for (const PhysicalTarget& t : plan.targets) EXPECT_EQ(t.samples, 4u) << t.logical.name;
    const PhysicalTarget& color = *plan.find("color");
    EXPECT_TRUE(color.resolve.needed);
    EXPECT_NE(color.resolve.description.find(p == PlatformId::X360 ? "copy_sample_select k0123" : "MSAA resolve"),
              std::string::npos)
        << color.resolve.description;
    const PhysicalTarget& depths = *plan.find("depths");
    EXPECT_EQ(depths.resolve.needed, p == PlatformId::X360) << depths.resolve.description;
    EXPECT_FALSE(plan.find("depth")->resolve.needed);
  }
}

}  // namespace
}  // namespace parity::platforms
