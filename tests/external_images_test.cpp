// `parity run --images DIR`: renders another program made, laid out as
// <technique>/<scene>/<platform>/<backend>.png, get the treatment of parity's own cases. parity
// render stands in for the other engine here; the planted differences are what a port gets
// wrong: one backend's image changed (a Vulkan regression), both changed (a technique regression),
// two renders of one case that differ (nondeterminism), an x360 image with D3D9 pixel centres
// (the diagnosis names the half-pixel shift).
#include <gtest/gtest.h>

#include <unistd.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/run/process.h"
#include "test_support.h"

using namespace parity;
namespace fs = std::filesystem;

namespace {

harness::ProcessResult parity(std::vector<std::string> args) {
  args.insert(args.begin(), PARITY_BINARY);
  return harness::runProcess(args, 280);
}

// A dark block in the middle of an image: the kind of regression a port introduces.
void plantBlock(const fs::path& png) {
  OIIO::ImageBuf img(png.string());
  ASSERT_TRUE(img.read(0, 0, true, OIIO::TypeDesc::UINT8));
  const int w = img.spec().width, h = img.spec().height;
  OIIO::ImageBuf copy;
  copy.copy(img);
  const float black[4] = {0, 0, 0, 1};
  OIIO::ImageBufAlgo::fill(copy, black, OIIO::ROI(w / 3, w / 2, h / 3, h / 2, 0, 1, 0, 4));
  ASSERT_TRUE(copy.write(png.string()));
}

class ExternalImages : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!test::makeDevice("vk", false) || !test::makeDevice("gl", false)) GTEST_SKIP() << "needs both backends";
    root_ = fs::temp_directory_path() / ("parity-images-" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_ / "golden");
    std::ofstream(root_ / "golden" / "manifest.json") << "{\"goldens\": {}}\n";
    cwd_ = fs::current_path();
    fs::current_path(root_);
  }
  void TearDown() override {
    if (root_.empty()) return;
    fs::current_path(cwd_);
    fs::remove_all(root_);
  }
  // The other engine's render of `technique` on `backend`, at the layout's place.
  void render(const std::string& dir, const std::string& technique, const std::string& backend,
              const std::string& platform = "reference", const std::string& as = "") {
    const fs::path out = fs::path(dir) / technique / "default" / (as.empty() ? platform : as) / (backend + ".png");
    fs::create_directories(out.parent_path());
    harness::ProcessResult r =
        parity({"render", "--technique", technique, "--backend", backend, "--platform", platform, "-o", out.string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
  }
  nlohmann::json run(const std::string& images, const std::string& out, int expectExit,
                     std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"run", "--images", images, "--golden", "golden", "--out", out, "--no-progress"};
    args.insert(args.end(), extra.begin(), extra.end());
    harness::ProcessResult r = parity(args);
    EXPECT_EQ(r.exitCode, expectExit) << r.out << r.err;
    return nlohmann::json::parse(test::readFile(fs::path(out) / "results.json"), nullptr, false);
  }
  static std::map<std::string, std::string> results(const nlohmann::json& j) {
    std::map<std::string, std::string> m;
    for (const auto& c : j["cases"]) m[c["id"]] = c["result"];
    return m;
  }
  static std::string verdict(const nlohmann::json& j, const std::string& group) {
    for (const auto& g : j["groups"])
      if (g["group"] == group) return g.value("verdict", "");
    return "";
  }
  fs::path root_, cwd_;
};

TEST_F(ExternalImages, AreBlessedWithProvenanceAndJudgedLikeRenders) {
  for (const char* b : {"gl", "vk"}) render("engine", "forward", b);
  std::ofstream("engine/devices.json") << R"({"gl": {"renderer": "engine GL renderer", "driver": "engine 1.0"},
                                           "vk": {"renderer": "engine VK renderer", "driver": "engine 1.0"}})";
  nlohmann::json first = run("engine", "first", 2);
  EXPECT_EQ(verdict(first, "forward/default/reference"), "no golden (backends agree)");
  test::writeEvidence("golden", "tests/external_images_test.cpp: ExternalImages.AreBlessedWithProvenanceAndJudgedLikeRenders");
  harness::ProcessResult r = parity({"bless", "--golden", "golden", "--from", "first"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const nlohmann::json manifest = nlohmann::json::parse(test::readFile("golden/manifest.json"));
  const nlohmann::json& entry = manifest["goldens"]["forward/default/reference"];
  EXPECT_EQ(entry["backends"]["vk"]["renderer"], "engine VK renderer");
  EXPECT_NE(entry.value("reason", "").find("bit-identical"), std::string::npos) << entry.dump();

  nlohmann::json again = run("engine", "again", 0);
  EXPECT_EQ(results(again), (std::map<std::string, std::string>{{"forward/default/reference/gl", "Pass"},
                                                                 {"forward/default/reference/vk", "Pass"}}));
  EXPECT_NE(test::readFile("again/junit.xml").find("forward/default/reference/vk"), std::string::npos);
  EXPECT_TRUE(fs::exists("again/report/index.html"));

  // One backend regressed: the triangulated verdict names it.
  fs::create_directories("planted");
  fs::copy("engine", "planted", fs::copy_options::recursive);
  plantBlock("planted/forward/default/reference/vk.png");
  nlohmann::json planted = run("planted", "planted-run", 2);
  EXPECT_EQ(results(planted)["forward/default/reference/gl"], "Pass");
  EXPECT_EQ(results(planted)["forward/default/reference/vk"], "Fail");
  EXPECT_EQ(verdict(planted, "forward/default/reference"), "vk regression");
  // Both: the technique changed (same driver as the golden's).
  plantBlock("planted/forward/default/reference/gl.png");
  nlohmann::json both = run("planted", "both-run", 2);
  EXPECT_EQ(verdict(both, "forward/default/reference"), "technique regression");

  // An expectation applies to an external case as to a render.
  std::ofstream("golden/expectations.json")
      << R"({"expectations": [{"case": "forward/default/reference/*", "result": "Fail", "reason": "known"}]})";
  nlohmann::json expected = run("planted", "expected-run", 0);
  EXPECT_EQ(results(expected)["forward/default/reference/vk"], "ExpectedFail");
}

TEST_F(ExternalImages, NondeterminismShardsAndTheDiagnosisOfAPixelCentreShift) {
  for (const char* b : {"gl", "vk"}) {
    render("engine", "forward", b);
    // An x360 port that kept D3D9 pixel centres, filed under the reference platform's name.
    render("engine", "forward", b, "x360", "port");
  }
  fs::copy_file("engine/forward/default/reference/gl.png", "golden-ref.png");
  fs::create_directories("golden/forward/default");
  fs::copy_file("golden-ref.png", "golden/forward/default/port.png");
  fs::copy_file("golden-ref.png", "golden/forward/default/reference.png");
  nlohmann::json j = run("engine", "run", 2);
  for (const auto& c : j["cases"])
    if (c["platform"] == "port") {
      EXPECT_EQ(c["result"], "Fail");
      EXPECT_NE(c.dump().find("half-pixel"), std::string::npos) << c.dump();
    }
  EXPECT_EQ(results(j)["forward/default/reference/vk"], "Pass");

  // Two renders of one case that differ.
  fs::copy_file("engine/forward/default/reference/vk.png", "engine/forward/default/reference/vk.repeat.png");
  plantBlock("engine/forward/default/reference/vk.repeat.png");
  j = run("engine", "nondeterministic", 2, {"--platform", "reference"});
  EXPECT_EQ(results(j)["forward/default/reference/vk"], "Nondeterministic");
  EXPECT_EQ(results(j)["forward/default/reference/gl"], "Pass");

  // Shards split by group and merge back into the whole.
  run("engine", "shard0", 2, {"--shard", "0/2"});
  run("engine", "shard1", 2, {"--shard", "1/2"});
  harness::ProcessResult r = parity({"merge", "shard0", "shard1", "--out", "merged"});
  EXPECT_NE(r.exitCode, 4) << r.err;
  nlohmann::json merged = nlohmann::json::parse(test::readFile("merged/results.json"));
  EXPECT_EQ(merged["cases"].size(), 4u);
}

TEST_F(ExternalImages, ALayoutItCannotReadIsOneLineAndNoOutput) {
  fs::create_directories("flat");
  render("deep", "forward", "vk");
  fs::copy_file("deep/forward/default/reference/vk.png", "flat/vk.png");
  harness::ProcessResult r = parity({"run", "--images", "flat", "--golden", "golden", "--out", "out", "--no-progress"});
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("flat/vk.png: not at <technique>/<scene>/<platform>/<backend>.png"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists("out"));
  std::ofstream("deep/devices.json") << "[1, 2]";
  r = parity({"run", "--images", "deep", "--golden", "golden", "--out", "out", "--no-progress"});
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("devices.json: not a JSON object"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists("out"));
}

}  // namespace
