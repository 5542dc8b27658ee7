// `parity view` under Xvfb: a few frames in a real window, then a screenshot taken through the
// project's readback, which must equal `parity render` of the same settings byte for byte; and
// the viewer's keys, fed as a script (hidden --keys): every key the help names changes exactly
// the state it names, without a window, and under Xvfb the screenshot after a key sequence
// equals `parity render` of the state the keys reached.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "harness/io/image_io.h"
#include "harness/run/process.h"
#include "scene/scene.h"
#include "techniques/technique.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

// The absolute path of a program on PATH (runProcess does not search PATH), or "".
std::string findProgram(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return "";
  std::string p = path;
  for (size_t start = 0; start <= p.size();) {
    size_t end = p.find(':', start);
    if (end == std::string::npos) end = p.size();
    fs::path candidate = fs::path(p.substr(start, end - start)) / program;
    if (!candidate.parent_path().empty() && fs::exists(candidate)) return candidate.string();
    start = end + 1;
  }
  return "";
}

std::vector<uint8_t> pixels(const std::string& path) {
  OIIO::ImageBuf image;
  std::string error;
  EXPECT_TRUE(harness::readImage(path, &image, &error)) << error;
  const OIIO::ImageSpec& spec = image.spec();
  std::vector<uint8_t> out(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  image.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::UINT8, out.data());
  return out;
}

std::vector<float> floatPixels(const std::string& path) {
  OIIO::ImageBuf image;
  std::string error;
  EXPECT_TRUE(harness::readImage(path, &image, &error)) << error;
  const OIIO::ImageSpec& spec = image.spec();
  std::vector<float> out(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  image.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, out.data());
  return out;
}

// The JSON lines --print-states wrote, one per shown frame.
std::vector<nlohmann::json> stateLines(const std::string& out) {
  std::vector<nlohmann::json> lines;
  size_t start = 0;
  while (start < out.size()) {
    size_t end = out.find('\n', start);
    if (end == std::string::npos) end = out.size();
    std::string line = out.substr(start, end - start);
    if (!line.empty() && line[0] == '{') lines.push_back(nlohmann::json::parse(line));
    start = end + 1;
  }
  return lines;
}

std::string cycled(const std::vector<std::string>& list, const std::string& current, int step) {
  auto it = std::find(list.begin(), list.end(), current);
  size_t i = it == list.end() ? 0 : static_cast<size_t>(it - list.begin());
  return list[(i + list.size() + static_cast<size_t>(step + static_cast<int>(list.size()))) % list.size()];
}

// Both backends: the B key switches between them.
bool bothBackendsAvailable() {
  for (const char* backend : {"gl", "vk"})
    if (!test::makeDevice(backend)) return false;  // skipped (or failed where required) with the reason
  return true;
}

// Every key of the help, pressed in turn without a window: each frame's state must be the
// previous one with exactly the documented change, and the frame must show the chosen target.
TEST(ViewerKeys, EveryKeyChangesExactlyTheStateItNames) {
  if (!bothBackendsAvailable()) return;
  const std::vector<std::string> keys = {"T", "shift+T", "G",  "tab", "shift+G", "P", "shift+P", "B", "B",
                                         "C", "N",       "+",  "-",   "L",       "H", "W",       "A", "Q",
                                         "up", "left",   "R",  "S",   "D",       "E", "down",    "right", "Z"};
  std::string script;
  for (const std::string& k : keys) script += k + " ";
  harness::ProcessResult v = harness::runProcess(
      {PARITY_BINARY, "view", "--no-window", "--print-states", "--keys", script, "--technique", "deferred", "--backend",
       "gl", "--platform", "reference", "--lights", "8", "--size", "64x36"},
      240);
  ASSERT_FALSE(v.timedOut || v.crashed) << v.err;
  ASSERT_EQ(v.exitCode, 0) << v.out << v.err;
  std::vector<nlohmann::json> lines = stateLines(v.out);
  ASSERT_EQ(lines.size(), keys.size() + 1) << v.out;

  const std::vector<std::string> techniques = test::techniqueNames(), scenes = scene::sceneNames();
  const std::vector<std::string> platforms = {"reference", "dx10", "ps3", "x360"};
  // The state part of a line (what the keys change), without what the frame reports.
  auto stateOf = [](nlohmann::json j) {
    for (const char* k : {"key", "shown", "targets", "cameras"}) j.erase(k);
    return j;
  };
  EXPECT_EQ(lines[0]["technique"], "deferred");
  EXPECT_EQ(lines[0]["target"], "");
  for (size_t i = 0; i < keys.size(); ++i) {
    const nlohmann::json& before = lines[i];
    const nlohmann::json& after = lines[i + 1];
    const std::string key = keys[i];
    SCOPED_TRACE("key " + key);
    ASSERT_EQ(after["key"].get<std::string>(), key);
    nlohmann::json want = stateOf(before);
    auto targets = before["targets"].get<std::vector<std::string>>();
    auto cameras = before["cameras"].get<std::vector<std::string>>();
    auto offset = [&](int axis, float by) { want["cameraOffset"][axis] = want["cameraOffset"][axis].get<float>() + by; };
    if (key == "T" || key == "shift+T") {
      want["technique"] = cycled(techniques, before["technique"].get<std::string>(), key == "T" ? 1 : -1);
      want["target"] = "";
    } else if (key == "G" || key == "tab" || key == "shift+G") {
      ASSERT_GE(targets.size(), 3u) << "deferred lists its G-buffer targets";
      std::string current = before["target"] == "" ? "color" : before["target"].get<std::string>();
      want["target"] = cycled(targets, current, key == "shift+G" ? -1 : 1);
    } else if (key == "P" || key == "shift+P") {
      want["platform"] = cycled(platforms, before["platform"].get<std::string>(), key == "P" ? 1 : -1);
    } else if (key == "B") {
      want["backend"] = before["backend"] == "gl" ? "vk" : "gl";
    } else if (key == "C") {
      ASSERT_GE(cameras.size(), 2u) << "the default scene has several cameras";
      want["camera"] = cycled(cameras, before["camera"].get<std::string>(), 1);
      want["cameraOffset"] = {0.0f, 0.0f, 0.0f};
      want["cameraYaw"] = 0.0f;
    } else if (key == "N") {
      want["scene"] = cycled(scenes, before["scene"].get<std::string>(), 1);
      want["camera"] = "default";
    } else if (key == "+") {
      want["lights"] = before["lights"].get<uint32_t>() * 2;
    } else if (key == "-") {
      want["lights"] = before["lights"].get<uint32_t>() / 2;
    } else if (key == "L") {
      want["lightSize"] = before["lightSize"] == "small" ? "big" : "small";
    } else if (key == "H") {
      want["allLightsCastShadows"] = !before["allLightsCastShadows"].get<bool>();
    } else if (key == "W" || key == "up") {
      offset(2, -0.25f);
    } else if (key == "S" || key == "down") {
      offset(2, 0.25f);
    } else if (key == "A") {
      offset(0, -0.25f);
    } else if (key == "D") {
      offset(0, 0.25f);
    } else if (key == "Q") {
      offset(1, -0.25f);
    } else if (key == "E") {
      offset(1, 0.25f);
    } else if (key == "left" || key == "right") {
      want["cameraYaw"] = before["cameraYaw"].get<float>() + (key == "left" ? 0.05f : -0.05f);
    } else if (key == "R") {
      want["cameraOffset"] = {0.0f, 0.0f, 0.0f};
      want["cameraYaw"] = 0.0f;
    }  // Z: no meaning, nothing changes
    EXPECT_EQ(stateOf(after), want) << "after " << key;
    // The frame shows the target the state names (the final colour when none is named).
    const std::string target = after["target"].get<std::string>();
    EXPECT_EQ(after["shown"].get<std::string>(), target.empty() ? "color" : target);
  }
  // The sequence went somewhere: the keys are not all no-ops that happen to agree.
  EXPECT_EQ(lines[3]["target"], lines[2]["targets"][1]);
  EXPECT_EQ(lines[10]["camera"], lines[9]["cameras"][1]);
  EXPECT_NE(lines[10]["camera"], "default");
  EXPECT_EQ(lines.back()["lightSize"], "big");
  EXPECT_EQ(lines.back()["allLightsCastShadows"], true);
  EXPECT_NE(lines.back()["cameraOffset"], nlohmann::json({0.0f, 0.0f, 0.0f}));
}

TEST(ViewerKeys, UnknownKeyNameIsRejected) {
  harness::ProcessResult v =
      harness::runProcess({PARITY_BINARY, "view", "--no-window", "--keys", "T ctrl+X", "--size", "32x18"}, 60);
  EXPECT_EQ(v.exitCode, 2);
  EXPECT_NE(v.err.find("unknown key 'ctrl+X'"), std::string::npos) << v.err;
}

// Under Xvfb, in a real window: keys switch technique, platform, backend, camera, light count
// and the target shown; the screenshot then equals what `parity render` writes for that state.
TEST(ViewerKeys, ScriptedKeysUnderXvfbMatchRenderOfTheReachedState) {
  std::string xvfbRun = findProgram("xvfb-run");
  if (xvfbRun.empty()) GTEST_SKIP() << "xvfb-run not installed (package xvfb, scripts/deps.sh)";
  if (!bothBackendsAvailable()) return;
  fs::path dir = fs::temp_directory_path() / ("parity-viewer-keys-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  struct Cleanup {
    fs::path dir;
    ~Cleanup() { fs::remove_all(dir); }
  } cleanup{dir};

  const std::vector<std::string> techniques = test::techniqueNames();
  const std::string start = cycled(techniques, "deferred", 1);  // shift+T comes back to deferred
  std::string shot = (dir / "view.png").string();
  harness::ProcessResult v = harness::runProcess(
      {xvfbRun, "-a", "-s", "-screen 0 640x480x24", PARITY_BINARY, "view", "--frames", "2", "--screenshot", shot,
       "--print-states", "--keys", "shift+T P B C + G G G", "--technique", start, "--backend", "gl", "--platform",
       "reference", "--lights", "8", "--size", "160x90"},
      240);
  ASSERT_FALSE(v.timedOut || v.crashed) << v.err;
  ASSERT_EQ(v.exitCode, 0) << v.out << v.err;
  std::vector<nlohmann::json> lines = stateLines(v.out);
  ASSERT_EQ(lines.size(), 8u + 2u) << v.out;
  const nlohmann::json& last = lines.back();
  EXPECT_EQ(last["technique"], "deferred");
  EXPECT_EQ(last["platform"], "dx10");
  EXPECT_EQ(last["backend"], "vk");
  EXPECT_EQ(last["lights"], 16);
  const std::string camera = last["camera"].get<std::string>(), shown = last["shown"].get<std::string>();
  EXPECT_NE(camera, "default");
  ASSERT_EQ(shown, last["targets"][3].get<std::string>());
  ASSERT_NE(shown, "color");

  fs::path passes = dir / "passes";
  harness::ProcessResult r = harness::runProcess(
      {PARITY_BINARY, "render", "-o", (dir / "render.png").string(), "--passes", passes.string(), "--technique",
       "deferred", "--backend", "vk", "--platform", "dx10", "--lights", "16", "--camera", camera, "--size", "160x90"},
      240);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  fs::path rendered = passes / (shown + ".png");
  if (!fs::exists(rendered)) rendered = passes / (shown + ".exr");
  ASSERT_TRUE(fs::exists(rendered)) << "render --passes wrote no file for " << shown;
  std::vector<float> a = floatPixels(shot), b = floatPixels(rendered.string());
  ASSERT_EQ(a.size(), 160u * 90u * 4u);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b) << "the screenshot after the keys differs from `parity render` of " << shown;
  // Not a blank target: the shown pass has structure.
  EXPECT_NE(*std::min_element(a.begin(), a.end()), *std::max_element(a.begin(), a.end()));
}

class Viewer : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("parity-viewer-test-" + std::to_string(::getpid()) + "-" + GetParam());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_P(Viewer, ScreenshotUnderXvfbEqualsRender) {
  std::string xvfbRun = findProgram("xvfb-run");
  if (xvfbRun.empty()) GTEST_SKIP() << "xvfb-run not installed (package xvfb, scripts/deps.sh)";
  auto device = test::makeDevice(GetParam());  // skips (or fails where required) an unavailable backend
  if (!device) return;
  device.reset();  // the children render; this process only checked availability

  const std::vector<std::string> settings = {"--technique", "deferred", "--backend", GetParam(), "--platform", "dx10",
                                             "--lights", "8", "--size", "160x90"};
  std::string shot = (dir_ / "view.png").string(), rendered = (dir_ / "render.png").string();
  // -a picks a free display number, so parallel tests do not collide.
  std::vector<std::string> view = {xvfbRun, "-a", "-s", "-screen 0 640x480x24", PARITY_BINARY, "view",
                                   "--frames", "3", "--screenshot", shot};
  view.insert(view.end(), settings.begin(), settings.end());
  harness::ProcessResult v = harness::runProcess(view, 240);
  ASSERT_FALSE(v.timedOut || v.crashed) << v.err;
  ASSERT_EQ(v.exitCode, 0) << v.out << v.err;

  std::vector<std::string> render = {PARITY_BINARY, "render", "-o", rendered};
  render.insert(render.end(), settings.begin(), settings.end());
  harness::ProcessResult r = harness::runProcess(render, 240);
  ASSERT_EQ(r.exitCode, 0) << r.err;

  std::vector<uint8_t> a = pixels(shot), b = pixels(rendered);
  ASSERT_EQ(a.size(), 160u * 90u * 4u);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b) << "the viewer's screenshot differs from `parity render`";
  // Not an empty frame: a lit scene has pixels brighter than the clear colour.
  size_t lit = 0;
  for (size_t i = 0; i < a.size(); i += 4) lit += (a[i] + a[i + 1] + a[i + 2]) > 30;
  EXPECT_GT(lit, a.size() / 4 / 10);
}

TEST(ViewerCli, WithoutADisplayFailsWithOneLine) {
  std::string env = findProgram("env");
  ASSERT_FALSE(env.empty());
  harness::ProcessResult v = harness::runProcess({env, "-u", "DISPLAY", "-u", "WAYLAND_DISPLAY", PARITY_BINARY, "view",
                                                  "--frames", "1", "--screenshot", "/nonexistent-dir/x.png"},
                                                 60);
  EXPECT_NE(v.exitCode, 0);
  EXPECT_NE(v.err.find("parity: error: view:"), std::string::npos) << v.err;
  EXPECT_EQ(std::count(v.err.begin(), v.err.end(), '\n'), 1) << v.err;
  EXPECT_FALSE(fs::exists("/nonexistent-dir/x.png"));
}

TEST(ViewerCli, UnknownTechniqueIsRejectedBeforeAWindowOpens) {
  harness::ProcessResult v = harness::runProcess({PARITY_BINARY, "view", "--technique", "no-such-technique"}, 60);
  EXPECT_EQ(v.exitCode, 2);
  EXPECT_NE(v.err.find("unknown technique 'no-such-technique'"), std::string::npos) << v.err;
}

INSTANTIATE_TEST_SUITE_P(Backends, Viewer, ::testing::ValuesIn(test::allBackends()), test::BackendName());

}  // namespace
