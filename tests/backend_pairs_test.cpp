// `parity run --images`: every pair of a group's backends is compared, whatever their names, and
// the one whose image differs from all the others (which agree) is named with the diagnosis of its
// difference. The images are drawn here; one of them is planted upside down.
#include "images_run_support.h"

using namespace parity;
namespace fs = std::filesystem;

namespace {

using BackendPairs = test::ImagesRunTest;

TEST_F(BackendPairs, NameTheOddOneOutOfThreeOtherEngineBackendsWithItsDiagnosis) {
  const std::string group = "lit/default/console";
  for (const char* b : {"d3d12", "vulkan"}) test::writePicture(fs::path("engine") / group / (std::string(b) + ".png"));
  test::writePicture(fs::path("engine") / group / "metal.png", /*flipped=*/true);
  test::writePicture(fs::path("golden") / "lit" / "default" / "console.png");

  harness::ProcessResult r = run("engine", "out");
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;  // metal differs from its golden
  const nlohmann::json g = groupOf(test::ImagesRunTest::results("out"), group);
  ASSERT_TRUE(g.contains("pairs")) << g.dump(2);
  ASSERT_EQ(g["pairs"].size(), 3u) << g.dump(2);
  for (const auto& p : g["pairs"]) {
    const bool withMetal = p["backends"][0] == "metal" || p["backends"][1] == "metal";
    EXPECT_EQ(p["agree"].get<bool>(), !withMetal) << p.dump();
  }
  ASSERT_TRUE(g.contains("odd_one_out")) << g.dump(2);
  EXPECT_EQ(g["odd_one_out"]["backend"], "metal");
  EXPECT_EQ(g["odd_one_out"]["differs_from"], (nlohmann::json{"d3d12", "vulkan"}));
  EXPECT_EQ(g["odd_one_out"].value("diagnosis", nlohmann::json::object()).value("cause", ""), "vertical flip") << g.dump(2);
  const std::string verdict = g.value("verdict", "");
  EXPECT_EQ(verdict, "metal differs from d3d12 and vulkan, which agree (likely cause: vertical flip)");

  // The summary, the report and JUnit say it too.
  EXPECT_NE(r.out.find("parity run: lit/default/console: odd one out metal: " + verdict), std::string::npos) << r.out;
  const std::string html = test::readFile("out/report/index.html");
  EXPECT_NE(html.find("odd one out: <b>metal</b>, likely cause <b>vertical flip</b>"), std::string::npos);
  EXPECT_NE(html.find("d3d12 vs vulkan</td><td>agree"), std::string::npos);
  EXPECT_NE(test::readFile("out/junit.xml").find("verdict: " + verdict), std::string::npos);
}

TEST_F(BackendPairs, AgreeingBackendsHaveNoOddOneOutAndTwoThatDifferCannotTellWhich) {
  for (const char* b : {"d3d12", "metal", "vulkan"}) test::writePicture(fs::path("engine/lit/default/console") / (std::string(b) + ".png"));
  test::writePicture("engine/lit/default/handheld/d3d12.png");
  test::writePicture("engine/lit/default/handheld/metal.png", /*flipped=*/true);
  run("engine", "out");
  const nlohmann::json j = test::ImagesRunTest::results("out");
  const nlohmann::json same = groupOf(j, "lit/default/console");
  EXPECT_EQ(same.value("verdict", ""), "backends agree (d3d12, metal and vulkan)");
  EXPECT_FALSE(same.contains("odd_one_out"));
  const nlohmann::json two = groupOf(j, "lit/default/handheld");
  EXPECT_EQ(two.value("verdict", ""), "backends differ (no odd one out)");
  EXPECT_FALSE(two.contains("odd_one_out"));
}

TEST_F(BackendPairs, GlAndVulkanKeepTheirVerdictAndAThirdBackendIsJudgedBesideThem) {
  for (const char* b : {"gl", "vk"}) test::writePicture(fs::path("engine/lit/default/console") / (std::string(b) + ".png"));
  test::writePicture("engine/lit/default/console/d3d12.png", /*flipped=*/true);
  run("engine", "out");
  const nlohmann::json g = groupOf(test::ImagesRunTest::results("out"), "lit/default/console");
  EXPECT_TRUE(g.contains("parity")) << g.dump(2);  // the GL/Vulkan comparison as before
  EXPECT_EQ(g.value("verdict", ""),
            "no golden (backends agree); d3d12 differs from gl and vk, which agree (likely cause: vertical flip)");
  for (const auto& p : g["pairs"]) {
    if (p["backends"] == nlohmann::json{"gl", "vk"}) {
      EXPECT_EQ(p["rule"], "parity budget (one Mesa compiler behind both)");
    }
  }
}

}  // namespace
