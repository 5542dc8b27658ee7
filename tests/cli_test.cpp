// The `parity` command as a user runs it.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <nlohmann/json.hpp>

#include <algorithm>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

#include "harness/run/process.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

harness::ProcessResult parity(std::vector<std::string> args) {
  args.insert(args.begin(), PARITY_BINARY);
  return harness::runProcess(args, 120);
}

using parity::test::requiredBackend;

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("parity-cli-test-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(Cli, ListJsonNamesBackendsTechniquesAndScenes) {
  auto r = parity({"list", "--json"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["backends"].size(), 2u);
  for (const auto& b : j["backends"]) {
    std::string name = b["name"];
    if (b["available"].get<bool>()) {
      EXPECT_FALSE(b["renderer"].get<std::string>().empty()) << name;
      EXPECT_FALSE(b["api"].get<std::string>().empty()) << name;
    } else {
      EXPECT_FALSE(b["reason"].get<std::string>().empty()) << name;
      EXPECT_FALSE(requiredBackend(name)) << name << " is required but unavailable: " << b["reason"];
    }
  }
  EXPECT_EQ(j["techniques"][0]["name"], "forward");
  EXPECT_EQ(j["scenes"][0]["name"], "default");
}

// Devices: a backend with one of its drivers, named stably from the driver. Here Mesa gives GL
// through llvmpipe and through Zink (OpenGL over lavapipe) and Vulkan through lavapipe; a driver
// asked for that does not load is a device with a reason, never another driver under its name.
TEST_F(Cli, ListJsonNamesEveryDeviceWithItsDriver) {
  auto r = parity({"list", "--json"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  std::map<std::string, nlohmann::json> byName;
  for (const auto& d : j["devices"]) {
    const std::string name = d["name"], backend = d["backend"];
    EXPECT_TRUE(byName.emplace(name, d).second) << "two devices named " << name;
    EXPECT_EQ(name.rfind(backend + "-", 0), 0u) << name;
    if (d["available"].get<bool>()) {
      EXPECT_FALSE(d["renderer"].get<std::string>().empty()) << name;
      EXPECT_FALSE(d["driver"].get<std::string>().empty()) << name;
    } else {
      EXPECT_FALSE(d["reason"].get<std::string>().empty()) << name;
    }
  }
  if (requiredBackend("gl")) {
    ASSERT_TRUE(byName.count("gl-llvmpipe")) << j["devices"].dump(2);
    EXPECT_EQ(byName["gl-llvmpipe"]["renderer"].get<std::string>().rfind("llvmpipe", 0), 0u);
  }
  if (requiredBackend("gl") && requiredBackend("vk")) {
    ASSERT_TRUE(byName.count("gl-zink")) << j["devices"].dump(2);
    EXPECT_TRUE(byName["gl-zink"]["available"].get<bool>()) << byName["gl-zink"].dump();
    EXPECT_EQ(byName["gl-zink"]["renderer"].get<std::string>().rfind("zink", 0), 0u) << byName["gl-zink"].dump();
    ASSERT_TRUE(byName.count("vk-lavapipe")) << j["devices"].dump(2);
    EXPECT_TRUE(byName["vk-lavapipe"]["available"].get<bool>());
  }
  auto missing = parity({"probe", "--backend", "gl", "--adapter", "nosuchdriver"});
  ASSERT_EQ(missing.exitCode, 0) << missing.err;
  nlohmann::json m = nlohmann::json::parse(missing.out);
  EXPECT_FALSE(m["available"].get<bool>()) << m.dump();
  EXPECT_NE(m.value("reason", "").find("'nosuchdriver'"), std::string::npos) << m.dump();
}

// `parity run --devices`: the devices are the matrix's backend axis, each case names its device
// and the driver it rendered with, a group compares every pair of them, and a named device is
// required: one that is not here fails the run with its reason; a name of no backend is a
// one-line error before anything is written.
TEST_F(Cli, RunOnNamedDevicesNamesEachCasesDevice) {
  if (!requiredBackend("gl") || !requiredBackend("vk")) GTEST_SKIP() << "needs GL and Vulkan (Zink runs GL over Vulkan)";
  const fs::path out = dir_ / "devices";
  auto r = parity({"run", "--devices", "gl-llvmpipe,gl-zink", "--technique", "forward", "--platform", "reference", "--out",
                   out.string(), "--no-progress"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  std::ifstream in(out / "results.json");
  nlohmann::json results = nlohmann::json::parse(in);
  std::map<std::string, nlohmann::json> byDevice;
  for (const auto& c : results["cases"]) byDevice[c.value("device", "")] = c;
  ASSERT_EQ(byDevice.size(), 2u) << results["cases"].dump(2);
  EXPECT_EQ(byDevice["gl-llvmpipe"].value("renderer", "").rfind("llvmpipe", 0), 0u) << byDevice["gl-llvmpipe"].dump();
  EXPECT_EQ(byDevice["gl-zink"].value("renderer", "").rfind("zink", 0), 0u) << byDevice["gl-zink"].dump();
  EXPECT_EQ(byDevice["gl-zink"]["id"], "forward/default/reference/gl-zink");
  for (const auto& g : results["groups"]) {
    ASSERT_EQ(g["pairs"].size(), 1u) << g.dump(2);
    EXPECT_TRUE(g["pairs"][0]["agree"].get<bool>()) << g.dump(2);
  }

  auto missing = parity({"run", "--devices", "gl-nosuchdriver", "--technique", "forward", "--platform", "reference", "--out",
                         (dir_ / "missing").string(), "--no-progress"});
  EXPECT_NE(missing.exitCode, 0);
  EXPECT_NE(missing.out.find("FAILED: required backend gl-nosuchdriver unavailable: unknown device 'gl-nosuchdriver'"),
            std::string::npos) << missing.out;
  auto bad = parity({"run", "--devices", "nosuchbackend", "--out", (dir_ / "bad").string()});
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_EQ(bad.err, "parity: error: unknown device 'nosuchbackend' (devices are named BACKEND-DRIVER, e.g. gl-zink; `parity list` lists them)\n");
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

TEST_F(Cli, ListReportsAMissingVulkanDriverWithAReason) {
  // Point the loader at no ICD: the backend must be reported unavailable, not crash.
  setenv("VK_ICD_FILENAMES", "/nonexistent/icd.json", 1);
  setenv("VK_DRIVER_FILES", "/nonexistent/icd.json", 1);
  auto r = parity({"list", "--json"});
  unsetenv("VK_ICD_FILENAMES");
  unsetenv("VK_DRIVER_FILES");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  for (const auto& b : j["backends"])
    if (b["name"] == "vk") {
      EXPECT_FALSE(b["available"].get<bool>());
      EXPECT_FALSE(b["reason"].get<std::string>().empty());
    }
}

TEST_F(Cli, RenderWritesAnImageOfTheRequestedSize) {
  for (const std::string backend : {"gl", "vk"}) {
    std::string out = (dir_ / (backend + ".png")).string();
    auto r = parity({"render", "--technique", "forward", "--backend", backend, "--size", "64x40", "-o", out});
    if (r.exitCode != 0 && !requiredBackend(backend) && r.err.find("unavailable") != std::string::npos) continue;
    ASSERT_EQ(r.exitCode, 0) << r.err;
    OIIO::ImageBuf img(out);
    ASSERT_TRUE(img.read());
    EXPECT_EQ(img.spec().width, 64);
    EXPECT_EQ(img.spec().height, 40);
  }
}

// Where the platform lacks compute, tiled shading and hdr take the port's path: `render` says so
// in a note naming the capability, and the platform raises no capability error; on the reference
// they run their compute passes, with no note.
TEST_F(Cli, RenderNotesThePortPathAndTheCapability) {
  struct Case {
    std::string technique, platform, note;  // note "": none
  };
  const std::vector<Case> cases = {
      {"tiled-deferred", "ps3", "parity: note: light culling: on the CPU"},
      {"tiled-forward", "x360", "parity: note: light culling: on the CPU"},
      {"hdr", "ps3", "parity: note: luminance: pixel passes"},
      {"hdr", "x360", "parity: note: luminance: pixel passes"},
      {"hdr", "dx10", "parity: note: luminance: pixel passes"},
      {"tiled-forward", "reference", ""},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.technique + " on " + c.platform);
    const std::string out = (dir_ / (c.technique + "-" + c.platform + ".png")).string();
    auto r = parity({"render", "--technique", c.technique, "--platform", c.platform, "--backend", "vk", "--size",
                     "160x96", "-o", out});
    if (r.exitCode != 0 && !requiredBackend("vk") && r.err.find("unavailable") != std::string::npos) return;
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.find("E_CAP_"), std::string::npos) << r.err;
    if (c.note.empty()) {
      EXPECT_EQ(r.err.find("parity: note:"), std::string::npos) << r.err;
    } else {
      EXPECT_NE(r.err.find(c.note), std::string::npos) << r.err;
      const std::string value = c.platform == "dx10" ? "yes (optional) on dx10" : "none on " + c.platform;
      EXPECT_NE(r.err.find("(the port's path; capability compute: " + value), std::string::npos) << r.err;
    }
  }
}

TEST_F(Cli, BadInputIsOneLineErrorAndNoOutput) {
  struct Case {
    std::vector<std::string> args;
    std::string mentions;
  };
  std::string out = (dir_ / "never.png").string();
  const Case cases[] = {
      {{"render", "--backend", "gl", "--size", "0x0", "-o", out}, "0x0"},
      {{"render", "--backend", "gl", "--size", "100000x10", "-o", out}, "100000x10"},
      {{"render", "--backend", "gl", "--size", "big", "-o", out}, "big"},
      {{"render", "--backend", "gl", "--technique", "nope", "-o", out}, "nope"},
      {{"render", "--backend", "metal", "-o", out}, "metal"},
      {{"render", "--backend", "gl", "--scene", "nowhere", "-o", out}, "nowhere"},
      {{"render", "--backend", "gl", "--camera", "nocam", "-o", out}, "nocam"},
      {{"render", "--backend", "gl", "-o", (dir_ / "image.bmpx").string()}, "image.bmpx"},
      {{"render", "--backend", "gl", "-o", (dir_ / "no-such-folder" / "x.png").string()}, "no-such-folder"},
  };
  for (const Case& c : cases) {
    auto r = parity(c.args);
    std::string joined;
    for (const auto& a : c.args) joined += a + " ";
    EXPECT_NE(r.exitCode, 0) << joined;
    EXPECT_NE(r.err.find("parity: error:"), std::string::npos) << joined << "\n" << r.err;
    EXPECT_NE(r.err.find(c.mentions), std::string::npos) << joined << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << joined << "\n" << r.err;
    EXPECT_FALSE(r.crashed) << joined;
  }
  EXPECT_FALSE(fs::exists(out));
  for (const auto& e : fs::directory_iterator(dir_)) ADD_FAILURE() << "left behind: " << e.path();
}

}  // namespace
