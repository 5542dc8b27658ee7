// `parity explain` as a user runs it.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "harness/run/process.h"
#include "techniques/technique.h"

using namespace parity;

namespace {

harness::ProcessResult parity(std::vector<std::string> args) {
  args.insert(args.begin(), PARITY_BINARY);
  return harness::runProcess(args, 60);
}

TEST(ExplainCli, WorksForEveryPlatform) {
  for (const std::string platform : {"reference", "dx10", "ps3", "x360"}) {
    auto r = parity({"explain", "--platform", platform, "--technique", "forward", "--size", "1280x720"});
    ASSERT_EQ(r.exitCode, 0) << platform << ": " << r.err;
    EXPECT_NE(r.out.find("targets:"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("diagnostics:"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("x360.signed_k16_resolve"), std::string::npos) << "parameters listed";
  }
}

TEST(ExplainCli, X360GBuffersPlusDepthDoNotFitAt720p) {
  auto r = parity({"explain", "--platform", "x360", "--technique", "gbuffer-test", "--size", "1280x720"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("2160"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("DOES NOT FIT"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("E_EDRAM_OVERLAP"), std::string::npos) << r.out;

  auto j = parity({"explain", "--platform", "x360", "--technique", "gbuffer-test", "--size", "1280x720", "--json"});
  ASSERT_EQ(j.exitCode, 0) << j.err;
  nlohmann::json doc = nlohmann::json::parse(j.out);
  EXPECT_EQ(doc["edram"]["tiles_total"], 2160);
  EXPECT_FALSE(doc["edram"]["fits"].get<bool>());
  bool overflow = false;
  for (const auto& d : doc["diagnostics"]) overflow |= d["code"] == "E_EDRAM_OVERLAP";
  EXPECT_TRUE(overflow);
  for (const auto& t : doc["targets"]) EXPECT_EQ(t["edram"]["tiles"], 720) << t["name"];
}

// The acceptance command: any technique's x360 explanation carries the inferred-lighting budget
// (two 32-bpp G-buffers + D24S8 = 3 x 720 tiles) with the overlap diagnostic.
TEST(ExplainCli, X360ForwardShowsTheGBufferBudget) {
  auto r = parity({"explain", "--platform", "x360", "--technique", "forward", "--size", "1280x720"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const size_t line = r.out.find("inferred-lighting budget at 1280x720");
  ASSERT_NE(line, std::string::npos) << r.out;
  const std::string budget = r.out.substr(line, r.out.find('\n', line) - line);
  EXPECT_NE(budget.find("2160 of 2048 tiles: DOES NOT FIT"), std::string::npos) << budget;
  EXPECT_NE(budget.find("E_EDRAM_OVERLAP"), std::string::npos) << budget;
  EXPECT_NE(r.out.find("total 1440 of 2048 tiles: fits"), std::string::npos) << "forward's own colour + depth";

  auto j = parity({"explain", "--platform", "x360", "--technique", "forward", "--size", "1024x576", "--json"});
  ASSERT_EQ(j.exitCode, 0) << j.err;
  nlohmann::json doc = nlohmann::json::parse(j.out);
  EXPECT_EQ(doc["edram"]["gbuffer_budget"]["tiles_total"], 1404);
  EXPECT_TRUE(doc["edram"]["gbuffer_budget"]["fits"].get<bool>());
  EXPECT_TRUE(doc["edram"]["gbuffer_budget"]["diagnostics"].empty());
}

// Every registered technique plans its targets with its platform and is explained with that plan.
TEST(ExplainCli, RegisteredTechniquesShowTheirOwnTargets) {
  int explained = 0;
  for (const auto& entry : techniques::techniqueRegistry()) {
    techniques::RenderSettings settings;
    settings.width = 1280;
    settings.height = 720;
    settings.platform = platforms::PlatformId::X360;
    std::vector<platforms::LogicalTarget> targets = entry.create()->logicalTargets(settings);
    ASSERT_FALSE(targets.empty()) << entry.name << " plans no target with its platform";
    auto r = parity({"explain", "--platform", "x360", "--technique", entry.name, "--size", "1280x720"});
    ASSERT_EQ(r.exitCode, 0) << entry.name << ": " << r.err;
    EXPECT_NE(r.out.find("technique " + entry.name + " (its logical targets)"), std::string::npos) << r.out;
    for (const auto& t : targets) EXPECT_NE(r.out.find("  " + t.name + " ("), std::string::npos) << entry.name << ": " << t.name;
    if (++explained == 2) break;  // each run is a process; two techniques show the mechanism
  }
}

// Inferred lighting renders its G-buffers and L-buffer at 0.625 of the output (800x450 for
// 1280x720, the paper's figures), and that is where they take EDRAM: 4 x 32-bpp surfaces of
// ceil(800 / 80) x ceil(450 / 16) = 290 tiles and the 64-bpp L-buffer of 580, 1740 tiles in all,
// which fit. Planned at the output size they would need 4320 tiles and overlap.
TEST(ExplainCli, X360InferredTargetsArePlannedAtTheReducedSize) {
  techniques::RenderSettings settings;
  settings.width = 1280;
  settings.height = 720;
  EXPECT_EQ(techniques::createTechnique("inferred")->logicalTargetExtent(settings), (techniques::TargetExtent{800, 450}));
  EXPECT_EQ(techniques::createTechnique("deferred")->logicalTargetExtent(settings), (techniques::TargetExtent{1280, 720}))
      << "techniques without a reduced resolution plan at the output size";

  auto j = parity({"explain", "--platform", "x360", "--technique", "inferred", "--size", "1280x720", "--json"});
  ASSERT_EQ(j.exitCode, 0) << j.err;
  nlohmann::json doc = nlohmann::json::parse(j.out);
  EXPECT_EQ(doc["size"], nlohmann::json({1280, 720}));
  EXPECT_EQ(doc["target_size"], nlohmann::json({800, 450}));
  uint32_t tiles = 0;
  for (const auto& t : doc["targets"]) {
    uint32_t expected = t["name"] == "lbuffer" ? 580u : 290u;
    EXPECT_EQ(t["edram"]["tiles"], expected) << t["name"];
    tiles += t["edram"]["tiles"].get<uint32_t>();
  }
  EXPECT_EQ(tiles, 1740u);
  EXPECT_EQ(doc["edram"]["tiles_total"], 1740);
  EXPECT_TRUE(doc["edram"]["fits"].get<bool>());
  for (const auto& d : doc["diagnostics"]) EXPECT_NE(d["code"], "E_EDRAM_OVERLAP") << d["message"];

  auto r = parity({"explain", "--platform", "x360", "--technique", "inferred", "--size", "1280x720"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("targets planned at 800x450"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("total 1740 of 2048 tiles: fits"), std::string::npos) << r.out;
  // A port pads the 800x450 surfaces to the resolve granularity: no resolve breaks X3's alignment.
  EXPECT_NE(r.out.find("the 800x450 surfaces padded to 800x456"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("E_RESOLVE_ALIGNMENT"), std::string::npos) << r.out;
}

// Targets a technique plans at sizes of their own are shown as they are planned: hdr's five bloom
// levels and its luminance chain (from half size down, each padded to the resolve granularity as a port allocates it, so
// that their resolves raise nothing), the shadow techniques' maps, SSAO's occlusion chain and
// inferred's output.
TEST(ExplainCli, PlansOfTheirOwnSizeAreShownToo) {
  auto j = parity({"explain", "--platform", "x360", "--technique", "hdr", "--size", "320x180", "--json"});
  ASSERT_EQ(j.exitCode, 0) << j.err;
  const nlohmann::json hdr = nlohmann::json::parse(j.out);
  // Five bloom levels, then (x360 has no compute shaders) the luminance chain's 18 levels.
  ASSERT_EQ(hdr["further_plans"].size(), 5u + 18u) << hdr["further_plans"].dump();
  for (size_t i = 0; i < hdr["further_plans"].size(); ++i)
    EXPECT_EQ(hdr["further_plans"][i]["targets"][0]["name"], i < 5 ? "hdr.bloom" : "hdr.luminance") << i;
  EXPECT_EQ(hdr["further_plans"][0]["size"], nlohmann::json({160, 90}));
  EXPECT_EQ(hdr["further_plans"][4]["size"], nlohmann::json({10, 5}));
  EXPECT_EQ(hdr["further_plans"][1]["targets"][0]["console_format"],
            "k_16_16_16_16 (fixed point -32...32, 64 bpp) in EDRAM");
  for (const auto& p : hdr["further_plans"]) EXPECT_TRUE(p["diagnostics"].empty()) << p.dump();
  EXPECT_EQ(hdr["further_plans"][0]["resolve"]["rectangle"], nlohmann::json({160, 96})) << "90 rows padded to 96";
  EXPECT_EQ(hdr["further_plans"][4]["resolve"]["rectangle"], nlohmann::json({16, 8}));
  EXPECT_EQ(hdr["further_plans"][4]["resolve"]["destination"], nlohmann::json({32, 32})) << "no packed mip";
  const std::vector<std::pair<std::string, std::vector<std::string>>> expected = {
      {"forward-shadows", {"shadow directional", "shadow local"}},
      {"deferred-shadows", {"shadow directional", "shadow local"}},
      {"deferred-ssao", {"ssao"}},
      {"inferred", {"material"}},
      {"forward", {}}};
  for (const auto& [technique, roles] : expected) {
    auto r = parity({"explain", "--platform", "ps3", "--technique", technique, "--json"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json doc = nlohmann::json::parse(r.out);
    std::vector<std::string> got;
    for (const auto& p : doc["further_plans"]) got.push_back(p["role"]);
    EXPECT_EQ(got, roles) << technique;
  }
  auto text = parity({"explain", "--platform", "x360", "--technique", "deferred-ssao", "--size", "320x180"});
  ASSERT_EQ(text.exitCode, 0) << text.err;
  EXPECT_NE(text.out.find("planned apart at 160x90 (ssao):"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("ssao.raw (r8_unorm, pass ssao)"), std::string::npos) << text.out;
}

TEST(ExplainCli, X360GBuffersFitAt1024x576) {
  auto j = parity({"explain", "--platform", "x360", "--technique", "gbuffer-test", "--size", "1024x576", "--json"});
  ASSERT_EQ(j.exitCode, 0) << j.err;
  nlohmann::json doc = nlohmann::json::parse(j.out);
  EXPECT_EQ(doc["edram"]["tiles_total"], 1404);
  EXPECT_TRUE(doc["edram"]["fits"].get<bool>());
  for (const auto& d : doc["diagnostics"]) EXPECT_NE(d["code"], "E_EDRAM_OVERLAP");
}

TEST(ExplainCli, ParametersChangeTheAnswer) {
  auto j = parity({"explain", "--platform", "x360", "--technique", "gbuffer-test", "--size", "1024x576", "--json",
                   "--param", "x360.dsf_resolve_path=naive-a"});
  ASSERT_EQ(j.exitCode, 0) << j.err;
  nlohmann::json doc = nlohmann::json::parse(j.out);
  bool precision = false;
  for (const auto& d : doc["diagnostics"]) precision |= d["code"] == "W_RESOLVE_PRECISION";
  EXPECT_TRUE(precision) << j.out;
}

TEST(ExplainCli, ErrorsAreOneLine) {
  for (std::vector<std::string> args : {std::vector<std::string>{"explain", "--platform", "wii"},
                                        {"explain", "--platform", "x360", "--size", "12x"},
                                        {"explain", "--platform", "x360", "--technique", "nope"},
                                        {"explain", "--platform", "x360", "--param", "nope=1"}}) {
    auto r = parity(args);
    EXPECT_NE(r.exitCode, 0) << args.back();
    EXPECT_EQ(r.err.find("parity: error:"), 0u) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  }
}

}  // namespace

namespace {

// The path each console's port takes, and the capability that chose it, for the techniques that
// use compute (hdr, tiled-*) and 4x MSAA (abuffer); the reference takes none. The capability
// table and its formats are in the JSON too.
TEST(ExplainCli, NamesThePortPathAndTheCapabilityThatChoseIt) {
  struct Want {
    std::string technique, platform, pass, capability;  // capability "": no port path there
  };
  const std::vector<Want> wants = {
      {"hdr", "ps3", "luminance", "compute"},          {"hdr", "x360", "luminance", "compute"},
      {"hdr", "dx10", "luminance", "compute"},         {"hdr", "reference", "", ""},
      {"tiled-deferred", "ps3", "light culling", "compute"}, {"tiled-forward", "x360", "light culling", "compute"},
      {"tiled-forward", "dx10", "light culling", "compute"}, {"tiled-forward", "reference", "", ""},
      {"abuffer", "dx10", "store", "multisampling"},   {"abuffer", "ps3", "", ""},
  };
  for (const Want& w : wants) {
    SCOPED_TRACE(w.technique + " on " + w.platform);
    auto r = parity({"explain", "--platform", w.platform, "--technique", w.technique, "--size", "320x180"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("capabilities (a draw or dispatch that needs more raises"), std::string::npos) << r.out;
    auto j = nlohmann::json::parse(
        parity({"explain", "--platform", w.platform, "--technique", w.technique, "--size", "320x180", "--json"}).out,
        nullptr, false);
    ASSERT_TRUE(j.is_object());
    ASSERT_TRUE(j.contains("port_paths") && j.contains("capabilities") && j.contains("formats")) << j.dump();
    EXPECT_EQ(j["capabilities"].size(), 16u);
    if (w.capability.empty()) {
      EXPECT_TRUE(j["port_paths"].empty()) << j["port_paths"].dump();
      EXPECT_EQ(r.out.find("the port's path; capability"), std::string::npos) << r.out;
      continue;
    }
    ASSERT_EQ(j["port_paths"].size(), 1u) << j["port_paths"].dump();
    EXPECT_EQ(j["port_paths"][0]["pass"], w.pass);
    EXPECT_EQ(j["port_paths"][0]["capability"], w.capability);
    EXPECT_NE(r.out.find(w.pass + ": "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("(the port's path; capability " + w.capability + ": "), std::string::npos) << r.out;
  }
}

}  // namespace
