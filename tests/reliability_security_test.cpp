// Files from strangers: scenes that reach outside their folder, resource requests that would
// exhaust memory, and names or messages that would run script in the HTML report.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "harness/run/process.h"
#include "harness/run/report.h"
#include "scene/scene.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

void writeBytes(const fs::path& p, const std::string& bytes) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << bytes;
}

std::string triangleBytes() {
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  return std::string(reinterpret_cast<const char*>(p), sizeof p);
}

// A one-triangle glTF whose buffer lives at `uri` (relative to the .gltf, or absolute).
std::string gltfWithBuffer(const std::string& uri, const std::string& count = "3") {
  return R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" +
         count + R"(, "type": "VEC3"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}], "buffers": [{"uri": ")" +
         uri + R"(", "byteLength": 36}]})";
}

const char* kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n";

class SceneConfinement : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("parity-confinement-" + std::to_string(::getpid()));
    fs::remove_all(root_);
    scenes_ = root_ / "scenes";
    fs::create_directories(scenes_);
    writeBytes(root_ / "outside.bin", triangleBytes());  // next to the scene folder, not inside
  }
  void TearDown() override { fs::remove_all(root_); }

  // Loads a scene file; returns the error ("" when it loaded).
  std::string load(const fs::path& file) {
    scene::SceneParams params;
    params.lightCount = 2;
    scene::Scene s;
    std::string error;
    bool ok = scene::loadSceneFile(file.string(), params, &s, &error);
    if (ok) {
      EXPECT_FALSE(s.meshes.empty());
    }
    return ok ? "" : (error.empty() ? "failed without a message" : error);
  }

  fs::path root_, scenes_;
};

TEST_F(SceneConfinement, GltfBufferInsideTheFolderTreeLoads) {
  writeBytes(scenes_ / "data" / "tri.bin", triangleBytes());
  writeBytes(scenes_ / "s.gltf", gltfWithBuffer("data/tri.bin"));
  EXPECT_EQ(load(scenes_ / "s.gltf"), "");
}

TEST_F(SceneConfinement, GltfBufferThroughAnInnerSymlinkLoads) {
  writeBytes(scenes_ / "data" / "tri.bin", triangleBytes());
  fs::create_symlink("data/tri.bin", scenes_ / "link.bin");
  writeBytes(scenes_ / "s.gltf", gltfWithBuffer("link.bin"));
  EXPECT_EQ(load(scenes_ / "s.gltf"), "");
}

TEST_F(SceneConfinement, GltfDotDotEscapeIsRefused) {
  writeBytes(scenes_ / "s.gltf", gltfWithBuffer("../outside.bin"));
  std::string error = load(scenes_ / "s.gltf");
  EXPECT_NE(error.find("s.gltf"), std::string::npos) << error;
  EXPECT_NE(error.find("outside the scene's folder"), std::string::npos) << error;
}

TEST_F(SceneConfinement, GltfPercentEncodedDotDotIsRefused) {
  writeBytes(scenes_ / "s.gltf", gltfWithBuffer("%2e%2e/outside.bin"));
  std::string error = load(scenes_ / "s.gltf");
  EXPECT_NE(error, "");
  EXPECT_NE(error.find("s.gltf"), std::string::npos) << error;
}

TEST_F(SceneConfinement, GltfAbsolutePathIsRefused) {
  writeBytes(scenes_ / "s.gltf", gltfWithBuffer((root_ / "outside.bin").string()));
  std::string error = load(scenes_ / "s.gltf");
  EXPECT_NE(error, "") << "an absolute URI was read";
  EXPECT_NE(error.find("s.gltf"), std::string::npos) << error;
}

TEST_F(SceneConfinement, GltfSymlinkOutOfTheTreeIsRefused) {
  fs::create_symlink(root_ / "outside.bin", scenes_ / "escape.bin");
  writeBytes(scenes_ / "s.gltf", gltfWithBuffer("escape.bin"));
  std::string error = load(scenes_ / "s.gltf");
  EXPECT_NE(error.find("outside the scene's folder"), std::string::npos) << error;
}

TEST_F(SceneConfinement, GltfSymlinkedFolderOutOfTheTreeIsRefused) {
  fs::create_symlink(root_, scenes_ / "up");
  writeBytes(scenes_ / "s.gltf", gltfWithBuffer("up/outside.bin"));
  std::string error = load(scenes_ / "s.gltf");
  EXPECT_NE(error.find("outside the scene's folder"), std::string::npos) << error;
}

TEST_F(SceneConfinement, ObjMaterialLibraryEscapeIsRefused) {
  writeBytes(root_ / "evil.mtl", "newmtl m\nKd 1 0 0\n");
  writeBytes(scenes_ / "s.obj", std::string("mtllib ../evil.mtl\n") + kTriangleObj);
  std::string error = load(scenes_ / "s.obj");
  EXPECT_NE(error.find("s.obj"), std::string::npos) << error;
  EXPECT_NE(error.find("outside the scene's folder"), std::string::npos) << error;
}

TEST_F(SceneConfinement, ObjAbsoluteTextureIsRefused) {
  writeBytes(scenes_ / "s.mtl", "newmtl m\nKd 1 1 1\nmap_Kd " + (root_ / "t.png").string() + "\n");
  writeBytes(root_ / "t.png", "whatever");
  writeBytes(scenes_ / "s.obj", std::string("mtllib s.mtl\n") + kTriangleObj);
  std::string error = load(scenes_ / "s.obj");
  EXPECT_NE(error.find("absolute path"), std::string::npos) << error;
}

TEST_F(SceneConfinement, ObjTextureSymlinkOutOfTheTreeIsRefused) {
  writeBytes(root_ / "t.png", "whatever");
  fs::create_symlink(root_ / "t.png", scenes_ / "t.png");
  writeBytes(scenes_ / "s.mtl", "newmtl m\nKd 1 1 1\nmap_Kd t.png\n");
  writeBytes(scenes_ / "s.obj", std::string("mtllib s.mtl\n") + kTriangleObj);
  std::string error = load(scenes_ / "s.obj");
  EXPECT_NE(error.find("outside the scene's folder"), std::string::npos) << error;
}

TEST_F(SceneConfinement, ObjWithMaterialInsideLoads) {
  writeBytes(scenes_ / "s.mtl", "newmtl m\nKd 1 0 0\n");
  writeBytes(scenes_ / "s.obj", std::string("mtllib s.mtl\n") + kTriangleObj);
  EXPECT_EQ(load(scenes_ / "s.obj"), "");
}

// ---- resource limits: refused from the declared size, before allocating ----

TEST_F(SceneConfinement, GltfHugeAccessorCountFailsCleanly) {
  writeBytes(scenes_ / "tri.bin", triangleBytes());
  writeBytes(scenes_ / "s.gltf", gltfWithBuffer("tri.bin", "2000000000"));
  std::string error = load(scenes_ / "s.gltf");
  EXPECT_NE(error.find("limit"), std::string::npos) << error;
}

TEST_F(SceneConfinement, TextureDeclaringAHugeSizeFailsCleanly) {
  // A PNG signature and an IHDR claiming 100000 x 100000 (40 GB as RGBA8), nothing after it.
  std::string png("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\x01\x86\xa0\0\x01\x86\xa0\x08\x06\0\0\0", 29);
  writeBytes(scenes_ / "huge.png", png);
  writeBytes(scenes_ / "s.mtl", "newmtl m\nKd 1 1 1\nmap_Kd huge.png\n");
  writeBytes(scenes_ / "s.obj", std::string("mtllib s.mtl\n") + kTriangleObj);
  std::string error = load(scenes_ / "s.obj");
  EXPECT_NE(error.find("100000x100000"), std::string::npos) << error;
}

TEST(SceneLimits, TooManyLightsFailCleanly) {
  scene::SceneParams params;
  params.lightCount = 1u << 30;
  scene::Scene s;
  std::string error;
  EXPECT_FALSE(scene::makeScene("default", params, &s, &error));
  EXPECT_NE(error.find("lights"), std::string::npos) << error;
}

// ---- the HTML report escapes every string it shows ----

const std::string kHostile = R"hostile(x"'><script>alert(1)</script></td></tr><img src=x onerror="alert(2)">)hostile";

nlohmann::json resultsWith(const std::string& text, const std::string& result) {
  nlohmann::json c = {{"id", "forward/" + text + "/reference/gl"},
                      {"technique", "forward"},
                      {"scene", text},
                      {"platform", "reference"},
                      {"backend", "gl"},
                      {"result", result},
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
          {"groups", {{{"group", "forward/" + text + "/reference"}, {"verdict", text}}}},
          {"counts", {{result, 1}}}};
}

size_t countOf(const std::string& haystack, const std::string& needle) {
  size_t n = 0;
  for (size_t at = haystack.find(needle); at != std::string::npos; at = haystack.find(needle, at + 1)) ++n;
  return n;
}

// The page's own markup is the same whatever the strings: each tag that a hostile string could
// open or close appears as often as with a harmless one.
void expectSameMarkup(const std::string& benign, const std::string& hostile) {
  // (The word "onerror" itself may appear as escaped text; an attribute would need a raw quote,
  // which the last check below rules out.)
  for (const char* tag : {"<script", "</script", "<img", "</td>", "</tr>", "<td", "<tr"})
    EXPECT_EQ(countOf(hostile, tag), countOf(benign, tag)) << "tag " << tag;
  EXPECT_EQ(hostile.find("alert(1)</script>"), std::string::npos);
  EXPECT_EQ(hostile.find("onerror=\"alert"), std::string::npos);
}

TEST(ReportEscaping, NamesMessagesAndLogsAreEscaped) {
  std::string benign = harness::reportHtml(resultsWith("harmless", "Fail"));
  std::string hostile = harness::reportHtml(resultsWith(kHostile, "Fail"));
  expectSameMarkup(benign, hostile);
  std::string junit = harness::junitXml(resultsWith(kHostile, "Fail"));
  EXPECT_EQ(junit.find("<script>"), std::string::npos);
  // The case pages too (they show the child's stderr in full).
  auto benignPages = harness::casePages(resultsWith("harmless", "Crash"));
  auto hostilePages = harness::casePages(resultsWith(kHostile, "Crash"));
  ASSERT_EQ(benignPages.size(), 1u);
  ASSERT_EQ(hostilePages.size(), 1u);
  EXPECT_NE(benignPages.begin()->second.find("stderr:"), std::string::npos);
  expectSameMarkup(benignPages.begin()->second, hostilePages.begin()->second);
}

TEST(ReportEscaping, ResultNamesFromAMergedResultsFileAreEscaped) {
  // `parity merge` reads results.json files that may come from elsewhere, result names included.
  std::string benign = harness::reportHtml(resultsWith("harmless", "Fail"));
  std::string hostile = harness::reportHtml(resultsWith("harmless", kHostile));
  EXPECT_EQ(hostile.find("<script>alert(1)"), std::string::npos);
  expectSameMarkup(benign, hostile);
}

TEST(ReportEscaping, CasePageNamesAreBoundedAndDistinct) {
  // A long hostile scene name once made the case page's file name too long to write; two names
  // that differ only in characters a file name cannot hold must not share a page.
  auto pages = harness::casePages(resultsWith(kHostile + kHostile + kHostile, "Fail"));
  ASSERT_EQ(pages.size(), 1u);
  EXPECT_LE(pages.begin()->first.size(), 120u) << pages.begin()->first;
  auto a = harness::casePages(resultsWith("a b", "Fail")), b = harness::casePages(resultsWith("a_b", "Fail"));
  EXPECT_NE(a.begin()->first, b.begin()->first);
  EXPECT_EQ(harness::casePages(resultsWith("default", "Fail")).begin()->first, "g-forward-default-reference.html");
}

// A report made of hostile strings, opened as a user would. These try every way out of a text
// node and an attribute; each way, if it worked, would mark the document.
const std::string kHostileDom =
    R"h(x"'><script>document.documentElement.setAttribute('data-pwned','script')</script></td></tr>)h"
    R"h(<img src=x onerror="document.documentElement.setAttribute('data-pwned','onerror')">)h"
    R"h(<svg onload="document.documentElement.setAttribute('data-pwned','svg')"></svg>)h";

// The element structure of a DOM dump: tag names in document order. Serialised attribute values
// never hold a raw quote, so quoted values are skipped whole; escaped text holds no '<'.
std::string tagSequence(const std::string& dom) {
  static const std::regex tag(R"(<(/?[a-zA-Z][a-zA-Z0-9-]*)(?:[^>"]|"[^"]*")*>)");
  std::string seq;
  for (std::sregex_iterator it(dom.begin(), dom.end(), tag), end; it != end; ++it) seq += (*it)[1].str() + " ";
  return seq;
}

TEST(ReportEscaping, HostileStringsRunNoScriptInChromiumAndKeepTheLayout) {
  std::string chromium = test::findExecutable({"chromium", "chromium-browser"});
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
  std::ofstream(root / "unescaped.html") << "<!DOCTYPE html><html><body><table><tr><td>" << kHostileDom
                                          << "</td></tr></table></body></html>";
  std::string control = dumpDom(root / "unescaped.html");
  ASSERT_NE(control.find("data-pwned=\""), std::string::npos) << "the control page ran no script:\n" << control;

  // The report and its case page, written as `parity run` writes them, once with harmless
  // strings and once with the hostile ones.
  std::map<std::string, std::string> doms[2];
  const std::string texts[2] = {"harmless", kHostileDom};
  for (int i = 0; i < 2; ++i) {
    fs::path out = root / (i == 0 ? "benign" : "hostile");
    nlohmann::json results = resultsWith(texts[i], "Crash");
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
