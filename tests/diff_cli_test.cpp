// `parity diff` follows idiff's exit codes: 0 pass, 1 warn, 2 fail, 3 size mismatch,
// 4 file error. Images are made here with OpenImageIO, values chosen by hand.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <filesystem>

#include "harness/compare/diff.h"
#include "harness/run/process.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

class DiffCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("parity-diff-test-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    // A 16x8 gradient whose top and bottom halves differ, so a vertical flip changes every row.
    OIIO::ImageBuf img(OIIO::ImageSpec(16, 8, 3, OIIO::TypeDesc::UINT8));
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 16; ++x) {
        float v[3] = {x / 15.0f, y / 7.0f, y < 4 ? 1.0f : 0.0f};
        img.setpixel(x, y, v);
      }
    ASSERT_TRUE(img.write(path("a.png")));
    ASSERT_TRUE(img.write(path("a_copy.png")));
    ASSERT_TRUE(OIIO::ImageBufAlgo::flip(img).write(path("a_flipped.png")));
    OIIO::ImageBuf small(OIIO::ImageSpec(8, 8, 3, OIIO::TypeDesc::UINT8));
    ASSERT_TRUE(small.write(path("small.png")));
    // One pixel off by exactly 2/255 in red.
    OIIO::ImageBuf nudged;
    nudged.copy(img);
    float p[3];
    nudged.getpixel(3, 2, p);
    p[0] += 2.0f / 255.0f;
    nudged.setpixel(3, 2, p);
    ASSERT_TRUE(nudged.write(path("a_nudged.png")));
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  harness::ProcessResult diff(std::vector<std::string> args) {
    args.insert(args.begin(), {PARITY_BINARY, "diff"});
    return harness::runProcess(args, 60);
  }
  fs::path dir_;
};

TEST_F(DiffCli, IdenticalImagesPassWithExit0) {
  auto r = diff({path("a.png"), path("a_copy.png")});
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("PASS"), std::string::npos);
}

TEST_F(DiffCli, VerticalFlipFailsWithExit2) {
  auto r = diff({path("a.png"), path("a_flipped.png")});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.out.find("FAILURE"), std::string::npos);
}

TEST_F(DiffCli, DifferentSizesExit3) {
  auto r = diff({path("a.png"), path("small.png")});
  EXPECT_EQ(r.exitCode, 3) << r.out << r.err;
}

TEST_F(DiffCli, MissingFileExit4NamingTheFile) {
  auto r = diff({path("a.png"), path("nope.png")});
  EXPECT_EQ(r.exitCode, 4) << r.out << r.err;
  EXPECT_NE(r.out.find(path("nope.png")), std::string::npos) << r.out;
}

TEST_F(DiffCli, NotAnImageExit4) {
  { std::ofstream(path("junk.png")) << "not a png"; }
  auto r = diff({path("a.png"), path("junk.png")});
  EXPECT_EQ(r.exitCode, 4) << r.out << r.err;
}

TEST_F(DiffCli, ThresholdsDecidePassWarnFail) {
  // One pixel differs by 2/255 = 0.00784 in one channel; 1 of 128 pixels = 0.78%.
  EXPECT_EQ(diff({path("a.png"), path("a_nudged.png")}).exitCode, 2);
  EXPECT_EQ(diff({path("a.png"), path("a_nudged.png"), "--fail", "0.01", "--warn", "0.01"}).exitCode, 0);
  EXPECT_EQ(diff({path("a.png"), path("a_nudged.png"), "--fail", "0.01"}).exitCode, 1);
  EXPECT_EQ(diff({path("a.png"), path("a_nudged.png"), "--failpercent", "1", "--warnpercent", "1"}).exitCode, 0);
  EXPECT_EQ(diff({path("a.png"), path("a_nudged.png"), "--failpercent", "1", "--warnpercent", "1", "--hardfail",
                  "0.005"}).exitCode, 2);
}

TEST_F(DiffCli, JsonReportsStatistics) {
  auto r = diff({path("a.png"), path("a_nudged.png"), "--json"});
  EXPECT_EQ(r.exitCode, 2);
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["verdict"], "FAILURE");
  EXPECT_EQ(j["pixels"], 128);
  EXPECT_EQ(j["pixels_over_fail"], 1);
  EXPECT_NEAR(j["max_error"].get<double>(), 2.0 / 255.0, 1e-6);
  EXPECT_EQ(j["max_error_at"]["x"], 3);
  EXPECT_EQ(j["max_error_at"]["y"], 2);
  EXPECT_EQ(j["max_error_at"]["channel"], 0);
}

TEST_F(DiffCli, HeatmapIsWrittenAndBrightestAtTheDifference) {
  auto r = diff({path("a.png"), path("a_nudged.png"), "--heatmap", path("heat.png")});
  EXPECT_EQ(r.exitCode, 2);
  OIIO::ImageBuf heat(path("heat.png"));
  ASSERT_TRUE(heat.read());
  float hot[3], cold[3];
  heat.getpixel(3, 2, hot);
  heat.getpixel(0, 0, cold);
  EXPECT_GT(hot[0] + hot[1] + hot[2], 1.5f);
  EXPECT_LT(cold[0] + cold[1] + cold[2], 0.1f);
}

}  // namespace
