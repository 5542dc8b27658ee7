// The HTML report as people see it: opened from disk in headless Chromium (Debian `chromium`),
// which must lay out the result grid with one coloured cell per case.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "harness/run/process.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

TEST(HarnessReport, HeadlessChromiumRendersTheResultGrid) {
  std::string chromium = test::findExecutable({"chromium", "chromium-browser"});
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (scripts/deps.sh installs it)";
  fs::path root = fs::temp_directory_path() / ("parity-report-test-" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "golden");
  // One technique and scene on every platform: all eight cases render and fail for want of a
  // golden in the empty golden folder.
  auto run = harness::runProcess({PARITY_BINARY, "run", "--technique", "forward", "--scene", "default", "--size", "96x64",
                                  "--out", (root / "out").string(), "--golden", (root / "golden").string(), "--no-progress"},
                                 120);
  ASSERT_TRUE(run.exitCode == 0 || run.exitCode == 2) << run.out << run.err;
  std::ifstream resultsFile(root / "out" / "results.json");
  nlohmann::json results;
  resultsFile >> results;
  size_t cases = results["cases"].size();
  ASSERT_EQ(cases, 8u);

  std::string url = "file://" + (root / "out" / "report" / "index.html").string();
  std::vector<std::string> common = {chromium, "--headless", "--no-sandbox", "--disable-gpu",
                                     "--user-data-dir=" + (root / "chromium-profile").string(), "--window-size=1200,900"};
  std::vector<std::string> dump = common;
  dump.insert(dump.end(), {"--dump-dom", url});
  auto dom = harness::runProcess(dump, 60);
  ASSERT_EQ(dom.exitCode, 0) << dom.err;
  size_t cells = 0;
  for (size_t at = 0; (at = dom.out.find("class=\"cell\"", at)) != std::string::npos; ++at) ++cells;
  EXPECT_EQ(cells, cases) << "one grid cell per case in the rendered DOM";

  std::string shot = (root / "shot.png").string();
  std::vector<std::string> screenshot = common;
  screenshot.insert(screenshot.end(), {"--screenshot=" + shot, url});
  auto s = harness::runProcess(screenshot, 60);
  ASSERT_EQ(s.exitCode, 0) << s.err;
  OIIO::ImageBuf img(shot);
  ASSERT_TRUE(img.read(0, 0, true)) << img.geterror();
  // The grid's cells are painted in their result colour: Fail #d2402f.
  size_t failPixels = 0;
  const int w = img.spec().width, h = img.spec().height, n = img.spec().nchannels;
  std::vector<float> px(static_cast<size_t>(w) * h * n);
  ASSERT_TRUE(img.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data()));
  auto near = [](float v, int want) { return std::abs(static_cast<int>(v * 255.0f + 0.5f) - want) <= 2; };
  for (size_t i = 0; i + 2 < px.size(); i += static_cast<size_t>(n))
    if (near(px[i], 0xd2) && near(px[i + 1], 0x40) && near(px[i + 2], 0x2f)) ++failPixels;
  EXPECT_GT(failPixels, 8u * 500u) << "eight red Fail cells";

  // A case page: the grid links to it, and it lays out its title, images, metrics and the
  // technique's per-pass targets.
  fs::path page = root / "out" / "report" / "cases" / "g-forward-default-dx10.html";
  ASSERT_TRUE(fs::exists(page));
  std::vector<std::string> pageDump = common;
  pageDump.insert(pageDump.end(), {"--dump-dom", "file://" + page.string()});
  auto pd = harness::runProcess(pageDump, 60);
  ASSERT_EQ(pd.exitCode, 0) << pd.err;
  EXPECT_NE(pd.out.find("<h1 class=\"case\">forward/default/dx10</h1>"), std::string::npos) << pd.out.substr(0, 2000);
  EXPECT_NE(pd.out.find("class=\"metrics\""), std::string::npos);
  size_t images = 0;
  for (size_t at = 0; (at = pd.out.find("<img src=\"../../cases/forward/default/dx10/", at)) != std::string::npos; ++at)
    ++images;
  EXPECT_GE(images, 2u) << "both backends' images";
  for (const auto& c : results["cases"])
    EXPECT_NE(dom.out.find("cases/" + std::string("g-") + c["technique"].get<std::string>() + "-" +
                           c["scene"].get<std::string>() + "-" + c["platform"].get<std::string>() + ".html"),
              std::string::npos)
        << "the grid links each case to its page";
  fs::remove_all(root);
}

}  // namespace
