// Baselines per device (docs/HARNESS.md, "Accepted images and budgets per device"): renders of
// two named devices fed to `parity run --images`, with differences planted inside and beyond an
// accepted image of their device and a named budget, and `parity bless --device`.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "images_run_support.h"

using namespace parity;
namespace fs = std::filesystem;

namespace {

// `from` with `pixels` pixels (rows of 100 from (150, row)) moved by `steps` 8-bit steps in
// channel `channel`, written to `to`.
void plant(const fs::path& from, const fs::path& to, int pixels, int steps, int row, int channel = 0) {
  OIIO::ImageBuf img(from.string());
  ASSERT_TRUE(img.read(0, 0, true, OIIO::TypeDesc::UINT8)) << from;
  OIIO::ImageBuf copy;
  copy.copy(img);
  for (int i = 0; i < pixels; ++i) {
    const int x = 150 + i % 100, y = row + i / 100;
    float px[4];
    copy.getpixel(x, y, px, 4);
    px[channel] = std::clamp((std::round(px[channel] * 255.0f) + static_cast<float>(steps)) / 255.0f, 0.0f, 1.0f);
    copy.setpixel(x, y, px, 4);
  }
  fs::create_directories(to.parent_path());
  ASSERT_TRUE(copy.write(to.string())) << to;
}

// `from` with the rows [row, row + rows) black: a difference FLIP sees at once.
void blackRows(const fs::path& from, const fs::path& to, int row, int rows) {
  OIIO::ImageBuf img(from.string());
  ASSERT_TRUE(img.read(0, 0, true, OIIO::TypeDesc::UINT8));
  OIIO::ImageBuf copy;
  copy.copy(img);
  const float black[4] = {0, 0, 0, 1};
  OIIO::ImageBufAlgo::fill(copy, black, OIIO::ROI(0, img.spec().width, row, row + rows, 0, 1, 0, 4));
  fs::create_directories(to.parent_path());
  ASSERT_TRUE(copy.write(to.string()));
}

std::string bytes(const fs::path& p) { return test::readFile(p.string()); }

class DeviceBaselines : public test::ImagesRunTest {
 protected:
  // The reference device's picture, and the images accepted on two other devices.
  void SetUp() override {
    ImagesRunTest::SetUp();
    test::writePicture("src/p.png");
    plant("src/p.png", "src/nvidia.png", 400, 20, 100);         // vk-nvidia's accepted image
    plant("src/p.png", "src/amd.png", 400, -20, 140, 1);        // d3d12-amd's accepted image
  }
  // A group's primary golden, and optionally the accepted images in the manifest.
  void golden(const std::string& group, bool accepted) {
    fs::create_directories(fs::path("golden") / group);
    fs::copy_file("src/p.png", "golden/" + group + ".png", fs::copy_options::overwrite_existing);
    if (!accepted) return;
    fs::copy_file("src/nvidia.png", "golden/" + group + ".vk-nvidia.png", fs::copy_options::overwrite_existing);
    fs::copy_file("src/amd.png", "golden/" + group + ".d3d12-amd.png", fs::copy_options::overwrite_existing);
    manifest_["accepted"][group] = {{"vk-nvidia", {{"devices", {"vk-nvidia*"}}}}, {"d3d12-amd", {{"devices", {"d3d12-amd"}}}}};
  }
  void writeManifest() { std::ofstream("golden/manifest.json") << manifest_.dump(2); }
  static std::map<std::string, nlohmann::json> byId(const nlohmann::json& results) {
    std::map<std::string, nlohmann::json> m;
    for (const auto& c : results["cases"]) m[c["id"]] = c;
    return m;
  }
  nlohmann::json manifest_ = {{"goldens", nlohmann::json::object()}};
};

TEST_F(DeviceBaselines, ACaseMatchesAnAcceptedImageOfItsDeviceWithinItsBudget) {
  std::ofstream("golden/tolerances.json") << R"({"budgets": [
    {"name": "nvidia", "devices": "vk-nvidia*", "fuzzy": {"max_difference": 3, "pixels": 100}, "reason": "its filtering"},
    {"name": "amd-fuzzy", "devices": "d3d12-*", "cases": "t/fuzzy-*", "fuzzy": {"max_difference": 4, "pixels": 30},
     "reason": "its rounding"},
    {"name": "nvidia-flip", "devices": "vk-nvidia*", "cases": "t/flip-*", "flip_percentile": {"p": 90, "max": 0.05},
     "reason": "its edges"}]})";
  for (const char* g : {"t/variant-inside/console", "t/variant-beyond/console"}) golden(g, true);
  for (const char* g : {"t/fuzzy-inside/console", "t/fuzzy-beyond/console", "t/fuzzy-max/console", "t/flip-inside/console",
                        "t/flip-beyond/console"})
    golden(g, false);
  writeManifest();
  const fs::path e = "engine/t";
  plant("src/nvidia.png", e / "variant-inside/console/vk-nvidia.png", 50, 2, 20);     // (a) inside its budget
  fs::copy_file("src/nvidia.png", e / "variant-inside/console/d3d12-amd.png");        // (c) the other device's image
  plant("src/nvidia.png", e / "variant-beyond/console/vk-nvidia.png", 50, 6, 20);     // (b) beyond it
  fs::copy_file("src/amd.png", e / "variant-beyond/console/d3d12-amd.png");           // its own accepted image
  plant("src/p.png", e / "fuzzy-inside/console/d3d12-amd.png", 30, 4, 20);            // (d) at the budget's edge
  plant("src/p.png", e / "fuzzy-inside/console/vk-nvidia.png", 101, 1, 20);           //     one pixel too many
  plant("src/p.png", e / "fuzzy-beyond/console/d3d12-amd.png", 31, 4, 20);            //     one pixel too many
  plant("src/p.png", e / "fuzzy-beyond/console/vk-nvidia.png", 10, 4, 20);            //     one step too far
  plant("src/p.png", e / "fuzzy-max/console/d3d12-amd.png", 10, 5, 20);               //     one step too far
  fs::copy_file("src/p.png", e / "fuzzy-max/console/vk-nvidia.png");
  blackRows("src/p.png", e / "flip-inside/console/vk-nvidia.png", 60, 5);             // ~3% of the pixels
  blackRows("src/p.png", e / "flip-beyond/console/vk-nvidia.png", 60, 45);            // 25%
  harness::ProcessResult r = run("engine", "out");
  ASSERT_EQ(r.exitCode, 2) << r.out << r.err;
  std::map<std::string, nlohmann::json> c = byId(results("out"));
  ASSERT_EQ(c.size(), 12u) << r.out;
  struct Want {
    std::string id, result, budget, matched;  // budget "": the tolerance judged; matched "": none
  };
  const std::vector<Want> want = {
      {"t/variant-inside/console/vk-nvidia", "Pass", "nvidia", "vk-nvidia"},
      {"t/variant-inside/console/d3d12-amd", "Fail", "", ""},
      {"t/variant-beyond/console/vk-nvidia", "Fail", "nvidia", ""},
      {"t/variant-beyond/console/d3d12-amd", "Pass", "", "d3d12-amd"},
      {"t/fuzzy-inside/console/d3d12-amd", "Pass", "amd-fuzzy", "primary"},
      {"t/fuzzy-inside/console/vk-nvidia", "Fail", "nvidia", ""},
      {"t/fuzzy-beyond/console/d3d12-amd", "Fail", "amd-fuzzy", ""},
      {"t/fuzzy-beyond/console/vk-nvidia", "Fail", "nvidia", ""},
      {"t/fuzzy-max/console/d3d12-amd", "Fail", "amd-fuzzy", ""},
      {"t/fuzzy-max/console/vk-nvidia", "Pass", "nvidia", "primary"},
      {"t/flip-inside/console/vk-nvidia", "Pass", "nvidia-flip", "primary"},
      {"t/flip-beyond/console/vk-nvidia", "Fail", "nvidia-flip", ""},
  };
  for (const Want& w : want) {
    SCOPED_TRACE(w.id);
    const nlohmann::json& g = c[w.id]["golden"];
    EXPECT_EQ(c[w.id]["result"], w.result) << c[w.id].dump(2);
    EXPECT_EQ(g.contains("budget") ? g["budget"].value("name", "") : "", w.budget) << g.dump(2);
    const std::string matched = !g.contains("matched") ? ""
                                : g["matched"]["image"] == "primary" ? "primary"
                                                                     : g["matched"].value("name", "");
    EXPECT_EQ(matched, w.matched) << g.dump(2);
  }
  // (c): only the accepted images of the case's own device are tried.
  const nlohmann::json& other = c["t/variant-inside/console/d3d12-amd"]["golden"]["accepted"];
  ASSERT_EQ(other.size(), 1u) << other.dump();
  EXPECT_EQ(other[0]["name"], "d3d12-amd");
  // What each budget measured, and the reason a failure gives.
  EXPECT_EQ(c["t/fuzzy-inside/console/d3d12-amd"]["golden"]["budget"]["measured"]["fuzzy"],
            nlohmann::json({{"max_difference", 4}, {"pixels", 30}}));
  EXPECT_NE(c["t/fuzzy-beyond/console/d3d12-amd"].value("reason", "").find("31 differing pixels > 30"), std::string::npos);
  EXPECT_NE(c["t/fuzzy-max/console/d3d12-amd"].value("reason", "").find("max difference 5 > 4"), std::string::npos);
  EXPECT_NE(c["t/variant-beyond/console/vk-nvidia"].value("reason", "").find("nor accepted image vk-nvidia: budget nvidia: "
                                                                             "max difference 6 > 3"),
            std::string::npos)
      << c["t/variant-beyond/console/vk-nvidia"].dump();
}

TEST_F(DeviceBaselines, BlessDeviceAddsAnAcceptedImageWithEvidenceAndLeavesThePrimary) {
  golden("t/s/console", false);
  manifest_["goldens"]["t/s/console"] = {{"file", "t/s/console.png"}, {"reason", "the reference device"}};
  writeManifest();
  fs::create_directories("engine/t/s/console");
  fs::copy_file("src/nvidia.png", "engine/t/s/console/vk-nvidia.png");
  fs::copy_file("src/p.png", "engine/t/s/console/d3d12-amd.png");
  ASSERT_EQ(run("engine", "first").exitCode, 2);
  const std::string primary = bytes("golden/t/s/console.png"), manifest = bytes("golden/manifest.json");
  auto bless = [](std::vector<std::string> extra) {
    std::vector<std::string> args = {"bless", "--golden", "golden", "--from", "first"};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::runParity(args);
  };
  auto unchanged = [&] {
    EXPECT_EQ(bytes("golden/manifest.json"), manifest);
    EXPECT_FALSE(fs::exists("golden/t/s/console.vk-nvidia.png"));
  };
  // Refused, one line, nothing written: a device the run did not render on, no reason, and an
  // image identical to the primary golden.
  harness::ProcessResult r = bless({"--device", "gl-zink", "--reason", "x"});
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("device 'gl-zink' is not a device of the run's cases (its devices: d3d12-amd, vk-nvidia)"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  unchanged();
  r = bless({"--device", "vk-nvidia"});
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("--device needs --reason"), std::string::npos) << r.err;
  unchanged();
  r = bless({"--device", "d3d12-amd", "--reason", "x"});
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("identical to the primary golden"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists("golden/t/s/console.d3d12-amd.png"));
  unchanged();

  // An image that is the primary golden upside down: the diagnosis names a porting mistake, which
  // no device difference is, whatever the reason says.
  {
    OIIO::ImageBuf flipped;
    ASSERT_TRUE(OIIO::ImageBufAlgo::flip(flipped, OIIO::ImageBuf("src/p.png")));
    ASSERT_TRUE(flipped.write("engine/t/s/console/d3d12-amd.png"));
    ASSERT_EQ(run("engine", "flipped").exitCode, 2);
    fs::copy_file("src/p.png", "engine/t/s/console/d3d12-amd.png", fs::copy_options::overwrite_existing);
    harness::ProcessResult wrong = test::runParity({"bless", "--golden", "golden", "--from", "flipped", "--device", "d3d12-amd", "--reason", "x"});
    EXPECT_NE(wrong.exitCode, 0);
    EXPECT_NE(wrong.err.find("is a porting mistake, vertical flip"), std::string::npos) << wrong.err;
    unchanged();
  }

  r = bless({"--device", "vk-nvidia", "--reason", "the vendor's texture filtering"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_EQ(bytes("golden/t/s/console.png"), primary);
  EXPECT_EQ(bytes("golden/t/s/console.vk-nvidia.png"), bytes("first/" + byId(results("first"))["t/s/console/vk-nvidia"]["image"].get<std::string>()));
  const nlohmann::json m = nlohmann::json::parse(bytes("golden/manifest.json"));
  EXPECT_EQ(m["goldens"], nlohmann::json::parse(manifest)["goldens"]);
  const nlohmann::json& a = m["accepted"]["t/s/console"]["vk-nvidia"];
  EXPECT_EQ(a["devices"], nlohmann::json({"vk-nvidia"}));
  EXPECT_EQ(a["reason"], "the vendor's texture filtering");
  EXPECT_EQ(a["blessed_from"]["case"], "t/s/console/vk-nvidia");
  EXPECT_EQ(a["blessed_from"]["run"], results("first")["run_id"]);
  EXPECT_EQ(a["evidence"]["against"], "t/s/console.png");
  EXPECT_EQ(a["evidence"]["diff"]["differing_pixels"], 400);
  EXPECT_EQ(a["evidence"]["diff"]["max_difference"], 20);
  EXPECT_GT(a["evidence"]["flip"]["mean"].get<double>(), 0.0);
  EXPECT_GE(a["evidence"]["flip"]["p99"].get<double>(), a["evidence"]["flip"]["p50"].get<double>());
  EXPECT_TRUE(a["evidence"].contains("diagnosis"));

  // The next run: the device's image matches its accepted image, the other device the primary.
  ASSERT_EQ(run("engine", "again").exitCode, 0);
  std::map<std::string, nlohmann::json> c = byId(results("again"));
  EXPECT_EQ(c["t/s/console/vk-nvidia"]["golden"]["matched"]["name"], "vk-nvidia");
  EXPECT_EQ(c["t/s/console/d3d12-amd"]["golden"]["matched"]["image"], "primary");
}

TEST_F(DeviceBaselines, ABadBudgetOrAcceptedEntryIsOneLineBeforeAnythingRenders) {
  test::writePicture("engine/t/s/console/vk-nvidia.png");
  const std::vector<std::pair<std::string, std::string>> bad = {
      {R"({"budgets": [{"name": "a", "devices": "vk-*", "fuzzy": {"max_difference": 2.5, "pixels": 1}, "reason": "r"}]})",
       "tolerances.json: budgets[0] (a): fuzzy: max_difference is 2.5; it must be an integer in [0, 255]"},
      {R"({"budgets": [{"name": "a", "devices": "vk-*", "fuzzy": {"max_difference": 2, "pixels": 1}}]})",
       "tolerances.json: budgets[0] (a): reason must be a non-empty string"},
      {R"({"budgets": [{"name": "a", "devices": "vk-*", "flip_percentile": {"p": 0, "max": 0.1}, "reason": "r"}]})",
       "tolerances.json: budgets[0] (a): flip_percentile: p is 0; it must be a number in (0, 100]"},
      {R"({"budgets": [{"name": "a", "device": "vk-*", "fuzzy": {"max_difference": 2, "pixels": 1}, "reason": "r"}]})",
       "tolerances.json: budgets[0] (a): unknown key 'device'"},
      {R"({"budgets": [{"name": "a", "devices": "vk-*", "reason": "r"}]})",
       "tolerances.json: budgets[0] (a): needs flip_percentile or fuzzy"},
  };
  for (const auto& [text, message] : bad) {
    std::ofstream("golden/tolerances.json") << text;
    harness::ProcessResult r = run("engine", "out");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists("out"));
  }
  fs::remove("golden/tolerances.json");
  std::ofstream("golden/manifest.json") << R"({"goldens": {}, "accepted": {"t/s/console": {"vk-nvidia": {"devices": []}}}})";
  harness::ProcessResult r = run("engine", "out");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("manifest.json: accepted: t/s/console: vk-nvidia: needs \"devices\""), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists("out"));
}

}  // namespace
