// `parity view` under Xvfb: a few frames in a real window, then a screenshot taken through the
// project's readback, which must equal `parity render` of the same settings byte for byte.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "harness/image_io.h"
#include "harness/process.h"
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
