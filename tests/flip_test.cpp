// LDR-FLIP against the reference tool's published values for the tree pair in
// ../shared/assets/flip (its README), plus properties any FLIP must have, and `parity diff --flip`.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "harness/compare/flip.h"
#include "harness/io/image_io.h"
#include "harness/run/process.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

fs::path flipAssets() { return fs::path(PARITY_SOURCE_DIR) / ".." / "shared" / "assets" / "flip"; }

TEST(Flip, TreePairMatchesTheReferenceTool) {
  fs::path dir = flipAssets();
  if (!fs::exists(dir / "tree-ref.png") || !fs::exists(dir / "tree-test.png"))
    GTEST_SKIP() << "../shared/assets/flip is absent (optional shared assets); nothing to validate against";
  OIIO::ImageBuf ref, test;
  std::string error;
  ASSERT_TRUE(harness::readImage((dir / "tree-ref.png").string(), &ref, &error)) << error;
  ASSERT_TRUE(harness::readImage((dir / "tree-test.png").string(), &test, &error)) << error;
  harness::FlipResult r = harness::computeLdrFlip(ref, test);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_NEAR(r.pixelsPerDegree, 67.0206, 1e-4);
  // Published by the reference tool at 67 pixels per degree (the README of the assets).
  EXPECT_NEAR(r.mean, 0.133285, 1e-4);
  // The weighted percentiles sit on a steep part of the sorted errors, where the reference
  // tool's float arithmetic moves single pixels across them: within 1e-3.
  EXPECT_NEAR(r.weightedQuartile1, 0.184586, 1e-3);
  EXPECT_NEAR(r.weightedMedian, 0.333096, 1e-3);
  EXPECT_NEAR(r.weightedQuartile3, 0.503230, 1e-3);
  EXPECT_NEAR(r.min, 0.0, 1e-6);
  EXPECT_NEAR(r.max, 0.983044, 1e-4);
}

OIIO::ImageBuf gradient(int w, int h) {
  OIIO::ImageBuf img(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float v[3] = {x / float(w - 1), y / float(h - 1), ((x / 4 + y / 4) % 2) ? 0.9f : 0.1f};
      img.setpixel(x, y, v);
    }
  return img;
}

TEST(Flip, IdenticalImagesHaveZeroErrorAndDifferencesRaiseIt) {
  OIIO::ImageBuf a = gradient(64, 48);
  harness::FlipResult same = harness::computeLdrFlip(a, a);
  ASSERT_TRUE(same.ok) << same.error;
  EXPECT_EQ(same.mean, 0.0);
  EXPECT_EQ(same.max, 0.0);
  OIIO::ImageBuf b;
  b.copy(a);
  float black[3] = {0, 0, 0};
  OIIO::ImageBufAlgo::fill(b, black, OIIO::ROI(10, 30, 10, 30, 0, 1, 0, 3));
  harness::FlipResult diff = harness::computeLdrFlip(a, b);
  ASSERT_TRUE(diff.ok);
  EXPECT_GT(diff.mean, 0.05);
  EXPECT_LE(diff.max, 1.0);
  EXPECT_LE(diff.weightedQuartile1, diff.weightedMedian);
  EXPECT_LE(diff.weightedMedian, diff.weightedQuartile3);
  // Error stays where the images differ (plus the filters' reach).
  EXPECT_EQ(diff.errorMap[static_cast<size_t>(47) * 64 + 63], 0.0f);
  OIIO::ImageBuf small = gradient(32, 48);
  EXPECT_FALSE(harness::computeLdrFlip(a, small).ok);
}

TEST(Flip, DiffCommandPrintsFlipAndWritesItsMap) {
  fs::path dir = fs::temp_directory_path() / ("parity-flip-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  OIIO::ImageBuf a = gradient(48, 32), b;
  b.copy(a);
  float white[3] = {1, 1, 1};
  OIIO::ImageBufAlgo::fill(b, white, OIIO::ROI(5, 15, 5, 15, 0, 1, 0, 3));
  ASSERT_TRUE(a.write((dir / "a.png").string()));
  ASSERT_TRUE(b.write((dir / "b.png").string()));
  auto r = harness::runProcess({PARITY_BINARY, "diff", (dir / "a.png").string(), (dir / "b.png").string(), "--flip",
                                "--flip-map", (dir / "map.png").string(), "--json"},
                               120);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("flip")) << r.out;
  EXPECT_GT(j["flip"]["mean"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(dir / "map.png"));
  // Threshold on the FLIP mean alone: identical images pass, different ones fail.
  r = harness::runProcess({PARITY_BINARY, "diff", (dir / "a.png").string(), (dir / "a.png").string(), "--flip",
                           "--flip-fail", "0.01"},
                          120);
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("FLIP mean 0"), std::string::npos) << r.out;
  fs::remove_all(dir);
}

}  // namespace
