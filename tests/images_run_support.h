// For tests of `parity run --images` that need no device: images drawn here (no render), laid
// out as another engine's (<technique>/<scene>/<platform>/<backend>.png), and the run's
// outputs read back.
#pragma once

#include <gtest/gtest.h>

#include <unistd.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/run/process.h"
#include "test_support.h"

namespace parity::test {

inline harness::ProcessResult runParity(std::vector<std::string> args) {
  args.insert(args.begin(), PARITY_BINARY);
  return harness::runProcess(args, 280);
}

// A 320x180 picture with nothing symmetric in it (gradients, a block off centre), so that a
// flipped copy differs everywhere and the diagnosis can name the flip. `flipped`: upside down.
inline void writePicture(const std::filesystem::path& png, bool flipped = false) {
  std::filesystem::create_directories(png.parent_path());
  OIIO::ImageSpec spec(320, 180, 4, OIIO::TypeDesc::UINT8);
  OIIO::ImageBuf img(spec);
  for (int y = 0; y < 180; ++y)
    for (int x = 0; x < 320; ++x) {
      const bool block = x >= 40 && x < 120 && y >= 20 && y < 70;
      const float px[4] = {x / 319.0f, y / 179.0f, block ? 0.9f : 0.2f, 1.0f};
      img.setpixel(x, flipped ? 179 - y : y, px);
    }
  ASSERT_TRUE(img.write(png.string())) << png;
}

// A folder of its own under the temporary folder, with an empty golden/ (manifest only), the
// working directory while the test runs.
class ImagesRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = std::filesystem::temp_directory_path() /
            (std::string("parity-") + info->test_suite_name() + "-" + info->name() + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(root_);
    std::filesystem::create_directories(root_ / "golden");
    std::ofstream(root_ / "golden" / "manifest.json") << "{\"goldens\": {}}\n";
    cwd_ = std::filesystem::current_path();
    std::filesystem::current_path(root_);
  }
  void TearDown() override {
    std::filesystem::current_path(cwd_);
    std::filesystem::remove_all(root_);
  }
  // `parity run --images images --golden golden --out out` plus `extra`; the process's result.
  harness::ProcessResult run(const std::string& images, const std::string& out, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"run", "--images", images, "--golden", "golden", "--out", out, "--no-progress"};
    args.insert(args.end(), extra.begin(), extra.end());
    return runParity(args);
  }
  static nlohmann::json results(const std::string& out) {
    return nlohmann::json::parse(readFile(out + "/results.json"), nullptr, false);
  }
  static nlohmann::json groupOf(const nlohmann::json& results, const std::string& name) {
    for (const auto& g : results.value("groups", nlohmann::json::array()))
      if (g.value("group", "") == name) return g;
    return nlohmann::json::object();
  }
  std::filesystem::path root_, cwd_;
};

}  // namespace parity::test
