// The HTML report as people see it: opened from disk in headless Chromium (Debian `chromium`),
// which must lay out the result grid with one coloured cell per case.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "harness/process.h"
#include "harness/report.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

std::string findChromium() {
  const char* path = std::getenv("PATH");
  std::stringstream s(path ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(s, dir, ':');)
    for (const char* name : {"chromium", "chromium-browser"}) {
      fs::path p = fs::path(dir) / name;
      if (::access(p.c_str(), X_OK) == 0) return p.string();
    }
  return "";
}

TEST(HarnessReport, HeadlessChromiumRendersTheResultGrid) {
  std::string chromium = findChromium();
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

// ---- a report made of hostile strings, opened as a user would ----

// Scene names, messages and logs come from files in pull requests. This one tries every way out
// of a text node and an attribute; each way, if it worked, would mark the document.
const std::string kHostile =
    R"h(x"'><script>document.documentElement.setAttribute('data-pwned','script')</script></td></tr>)h"
    R"h(<img src=x onerror="document.documentElement.setAttribute('data-pwned','onerror')">)h"
    R"h(<svg onload="document.documentElement.setAttribute('data-pwned','svg')"></svg>)h";

nlohmann::json resultsNamed(const std::string& text) {
  nlohmann::json c = {{"id", "forward/" + text + "/reference/gl"},
                      {"technique", "forward"},
                      {"scene", text},
                      {"platform", "reference"},
                      {"backend", "gl"},
                      {"result", "Crash"},
                      {"reason", "shader info log: " + text},
                      {"stderr", text},
                      {"renderer", text},
                      {"image", "cases/" + text + ".png"},
                      {"render_ms", {1.0}},
                      {"golden", {{"golden_copy", "cases/" + text + "-golden.png"}, {"metrics", {{"max_error", 0.5}}}}}};
  return {{"run_id", text},
          {"project_commit", text},
          {"size", "320x180"},
          {"finished", text},
          {"backends", {{{"name", "gl"}, {"available", true}, {"renderer", text}, {"driver", text}}}},
          {"cases", {c}},
          {"groups", {{{"group", "forward/" + text + "/reference"}, {"verdict", text}}}}};
}

// The element structure of a DOM dump: tag names in document order. Serialised attribute values
// never hold a raw quote, so quoted values are skipped whole; escaped text holds no '<'.
std::string tagSequence(const std::string& dom) {
  static const std::regex tag(R"(<(/?[a-zA-Z][a-zA-Z0-9-]*)(?:[^>"]|"[^"]*")*>)");
  std::string seq;
  for (std::sregex_iterator it(dom.begin(), dom.end(), tag), end; it != end; ++it) seq += (*it)[1].str() + " ";
  return seq;
}

TEST(HarnessReport, HostileStringsRunNoScriptInChromiumAndKeepTheLayout) {
  std::string chromium = findChromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (scripts/deps.sh installs it)";
  fs::path root = fs::temp_directory_path() / ("parity-hostile-report-" + std::to_string(::getpid()));
  fs::remove_all(root);
  std::vector<std::string> common = {chromium, "--headless", "--no-sandbox", "--disable-gpu",
                                     "--user-data-dir=" + (root / "chromium-profile").string()};
  auto dumpDom = [&](const fs::path& page) {
    std::vector<std::string> args = common;
    args.insert(args.end(), {"--dump-dom", "file://" + page.string()});
    auto r = harness::runProcess(args, 60);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return r.out;
  };

  // The control: the same strings in a page that does not escape them do run here (scripts run
  // in file:// pages of this Chromium), so the checks below can see a script that ran.
  fs::create_directories(root);
  std::ofstream(root / "unescaped.html") << "<!DOCTYPE html><html><body><table><tr><td>" << kHostile
                                          << "</td></tr></table></body></html>";
  std::string control = dumpDom(root / "unescaped.html");
  ASSERT_NE(control.find("data-pwned=\""), std::string::npos) << "the control page ran no script:\n" << control;

  // The report and its case page, written as `parity run` writes them, once with harmless
  // strings and once with the hostile ones.
  std::map<std::string, std::string> doms[2];
  const std::string texts[2] = {"harmless", kHostile};
  for (int i = 0; i < 2; ++i) {
    fs::path out = root / (i == 0 ? "benign" : "hostile");
    nlohmann::json results = resultsNamed(texts[i]);
    std::string error;
    ASSERT_TRUE(harness::writeReports(out.string(), results, &error)) << error;
    doms[i]["index"] = dumpDom(out / "report" / "index.html");
    size_t pages = 0;
    for (const auto& e : fs::directory_iterator(out / "report" / "cases")) {
      doms[i]["case page"] = dumpDom(e.path());
      ++pages;
    }
    ASSERT_EQ(pages, 1u);
  }
  for (const char* page : {"index", "case page"}) {
    const std::string& benign = doms[0][page];
    const std::string& hostile = doms[1][page];
    EXPECT_EQ(hostile.find("data-pwned=\""), std::string::npos) << page << ": a hostile string ran a script";
    // The layout: the same elements in the same order as with harmless strings (a string that
    // closed a cell or a row, or opened an element, would change it).
    EXPECT_EQ(tagSequence(hostile), tagSequence(benign)) << page;
    EXPECT_GT(tagSequence(benign).size(), 40u) << page << ": the DOM dump is not the page\n" << benign;
    // The strings are there, as text.
    EXPECT_NE(hostile.find("&lt;script&gt;document.documentElement"), std::string::npos) << page;
  }
  fs::remove_all(root);
}

}  // namespace
