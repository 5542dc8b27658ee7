// `parity run --baseline DIR` (and `parity merge --baseline DIR`): this run against an earlier
// one. Between two `--images` runs one case regresses (its image turned upside down), one is
// fixed, one is new and one vanished.
#include <algorithm>

#include "images_run_support.h"

using namespace parity;
namespace fs = std::filesystem;

namespace {

using RunBaseline = test::ImagesRunTest;

TEST_F(RunBaseline, ListsRegressionsFixesNewAndVanishedCases) {
  for (const char* t : {"kept", "broken", "mended", "gone", "added"}) test::writePicture(fs::path("golden") / t / "default/console.png");
  test::writePicture("before/kept/default/console/d3d12.png");
  test::writePicture("before/broken/default/console/d3d12.png");
  test::writePicture("before/mended/default/console/d3d12.png", /*flipped=*/true);
  test::writePicture("before/gone/default/console/d3d12.png");
  ASSERT_EQ(run("before", "first").exitCode, 2);  // mended still fails
  test::writePicture("after/kept/default/console/d3d12.png");
  test::writePicture("after/broken/default/console/d3d12.png", /*flipped=*/true);
  test::writePicture("after/mended/default/console/d3d12.png");
  test::writePicture("after/added/default/console/d3d12.png");

  harness::ProcessResult r = run("after", "second", {"--baseline", "first"});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;  // broken fails now
  EXPECT_NE(r.out.find("; against baseline first: 1 regression, 1 fix, 1 new, 1 vanished; report"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("parity run: regression broken/default/console/d3d12: Pass before, Fail now (differs from golden"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("parity run: fix mended/default/console/d3d12: Fail before, Pass now"), std::string::npos) << r.out;
  const nlohmann::json b = results("second")["baseline"];
  EXPECT_EQ(b["dir"], "first");
  EXPECT_EQ(b["run_id"], results("first")["run_id"]);
  ASSERT_EQ(b["regressions"].size(), 1u) << b.dump(2);
  EXPECT_EQ(b["regressions"][0]["id"], "broken/default/console/d3d12");
  EXPECT_EQ(b["regressions"][0]["now"], "Fail");
  ASSERT_EQ(b["fixes"].size(), 1u) << b.dump(2);
  EXPECT_EQ(b["fixes"][0]["id"], "mended/default/console/d3d12");
  EXPECT_EQ(b["new"], (nlohmann::json{{{"id", "added/default/console/d3d12"}, {"now", "Pass"}}}));
  EXPECT_EQ(b["vanished"], (nlohmann::json{{{"id", "gone/default/console/d3d12"}, {"before", "Pass"}}}));
  const std::string junit = test::readFile("second/junit.xml");
  EXPECT_NE(junit.find("<property name=\"baseline\" value=\"regression: Pass before, Fail now\"/>"), std::string::npos) << junit;
  EXPECT_NE(junit.find("<property name=\"baseline\" value=\"fix: Fail before, Pass now\"/>"), std::string::npos);
  EXPECT_NE(junit.find("<property name=\"vanished\" value=\"gone/default/console/d3d12 (Pass before)\"/>"), std::string::npos);
  const std::string html = test::readFile("second/report/index.html");
  EXPECT_NE(html.find("<h2>Against baseline</h2>"), std::string::npos);
  EXPECT_NE(html.find("<td>regression</td><td>broken/default/console/d3d12</td>"), std::string::npos);

  // The same through merge.
  r = harness::runProcess({PARITY_BINARY, "merge", "second", "--out", "merged", "--baseline", "first"}, 120);
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.out.find("; against baseline first: 1 regression, 1 fix, 1 new, 1 vanished"), std::string::npos) << r.out;
  EXPECT_EQ(results("merged")["baseline"]["regressions"], b["regressions"]);
}

TEST_F(RunBaseline, AMissingOrMalformedBaselineIsOneLineAndNothingIsWritten) {
  test::writePicture("engine/lit/default/console/d3d12.png");
  ASSERT_EQ(run("engine", "first").exitCode, 2);  // no golden
  fs::create_directories("broken");
  std::ofstream("broken/results.json") << "{\"cases\": ";
  fs::create_directories("shapeless");
  std::ofstream("shapeless/results.json") << R"({"cases": [{"id": 7, "result": "Pass"}]})";
  const std::pair<const char*, const char*> bad[] = {
      {"nowhere", "parity: error: nowhere/results.json: no such file (--baseline needs the output folder of an earlier `parity run`)\n"},
      {"broken", "parity: error: broken/results.json: not valid JSON: "},
      {"shapeless", "parity: error: shapeless/results.json: cases[0] needs a string id and result\n"}};
  for (const auto& [dir, message] : bad) {
    harness::ProcessResult r = run("engine", "out", {"--baseline", dir});
    EXPECT_NE(r.exitCode, 0) << dir;
    EXPECT_EQ(r.err.rfind(message, 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists("out")) << dir;
    r = harness::runProcess({PARITY_BINARY, "merge", "first", "--out", "merged", "--baseline", dir}, 120);
    EXPECT_NE(r.exitCode, 0) << dir;
    EXPECT_EQ(r.err.rfind(message, 0), 0u) << r.err;
    EXPECT_FALSE(fs::exists("merged")) << dir;
  }
}

}  // namespace
