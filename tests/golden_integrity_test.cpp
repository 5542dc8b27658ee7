// What the checked-in goldens must be to be worth comparing with: no target of any technique is
// one constant value (a constant target checks nothing: the default scene gives every pass
// something to do), except the lost-light counts, which are 0 wherever no light is lost; the
// transparency techniques differ from the opaque reference technique and agree with each other;
// and every golden but the reference technique's records its comparison with its reference image
// (docs/HARNESS.md, "Goldens").
#include <gtest/gtest.h>

#include <OpenImageIO/imagebufalgo.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "harness/compare/diff.h"
#include "harness/run/golden.h"
#include "harness/io/image_io.h"
#include "harness/run/run.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

nlohmann::json manifest() {
  std::ifstream in(fs::path(harness::defaultGoldenDir()) / "manifest.json");
  nlohmann::json j;
  in >> j;
  return j;
}

bool constant(const std::string& path, std::string* error) {
  OIIO::ImageBuf image;
  if (!harness::readImage(path, &image, error)) return false;
  OIIO::ImageBufAlgo::PixelStats stats = OIIO::ImageBufAlgo::computePixelStats(image);
  for (size_t c = 0; c < stats.min.size(); ++c)
    if (stats.min[c] != stats.max[c]) return false;
  return true;
}

bool isLostLightCount(const std::string& file) { return file.find(".dropped.") != std::string::npos; }

TEST(Goldens, NoTargetIsConstant) {
  const nlohmann::json m = manifest();
  ASSERT_TRUE(m.contains("goldens")) << "golden/manifest.json has no goldens";
  size_t checked = 0;
  for (const auto& [key, entry] : m["goldens"].items()) {
    std::vector<std::string> files = {entry.value("file", "")};
    for (const auto& t : entry.value("targets", nlohmann::json::array())) files.push_back(t.get<std::string>());
    for (const std::string& file : files) {
      if (isLostLightCount(file)) continue;
      std::string error;
      const std::string path = (fs::path(harness::defaultGoldenDir()) / file).string();
      EXPECT_FALSE(constant(path, &error)) << file << " is one constant value";
      EXPECT_TRUE(error.empty()) << error;
      ++checked;
    }
  }
  EXPECT_GT(checked, 400u) << "the manifest lists fewer golden images than the matrix has";
}

TEST(Goldens, TransparencyDiffersFromForwardAndAgreesWithDepthPeeling) {
  const std::string dir = harness::defaultGoldenDir();
  harness::DiffThresholds exact;
  exact.fail = exact.warn = 0.0;
  // Beyond the rounding of the opaque image, which is a Rgba16Hdr target (RGBA16F on dx10 and
  // ps3, k_16_16_16_16 on x360: up to 1/255 in 5078 pixels against forward's colour).
  harness::DiffThresholds panes;
  panes.fail = panes.warn = 2.0 / 255.0;
  for (const char* platform : {"reference", "dx10", "ps3", "x360"}) {
    auto path = [&](const char* technique) { return harness::goldenPath(dir, technique, "default", platform); };
    // Where the panes are blended over the opaque image. Measured on the default scene at
    // 320x180: 551 pixels (0.96%) on every platform, 552 on x360.
    harness::DiffResult opaque = harness::diffFiles(path("forward"), path("abuffer"), panes);
    EXPECT_GT(opaque.failShare(), 0.005) << platform << ": the A-buffer renders the panes as forward does";
    // The stencil-routed A-buffer keeps 4 fragments per pixel and so does depth peeling with 4
    // layers: they may differ only where the blend order of equal depths or the sample routing
    // differs. Measured on the default scene at 320x180: 113 pixels (0.20%), mean 2.3e-5 on the
    // reference; 108 on dx10 and ps3; 282 (0.49%) on x360, whose layers are k_16_16_16_16.
    harness::DiffResult peeled = harness::diffFiles(path("depth-peeling"), path("abuffer"), exact);
    EXPECT_LT(peeled.failShare(), 0.01) << platform << ": " << harness::summaryLine(peeled);
    EXPECT_LT(peeled.meanError, 2e-4) << platform << ": " << harness::summaryLine(peeled);
  }
}

TEST(Goldens, EveryGoldenRecordsItsComparisonWithItsReference) {
  const nlohmann::json m = manifest();
  for (const auto& [key, entry] : m["goldens"].items()) {
    if (key == "forward/default/reference") continue;  // the reference technique on the reference platform
    ASSERT_TRUE(entry.contains("reference_comparison") && entry["reference_comparison"].is_object()) << key;
    const nlohmann::json& c = entry["reference_comparison"];
    EXPECT_TRUE(c.contains("identical") && c.contains("summary") && c.contains("reference")) << key << ": " << c.dump();
    // x360's D3D9 centres are named for every technique whose x360 image has no other quirk.
    if (key.size() > 5 && key.compare(key.size() - 5, 5, "/x360") == 0 && c.contains("diagnosis") && !c["diagnosis"].is_null()) {
      EXPECT_EQ(c["diagnosis"].value("cause", ""), "half-pixel shift by (-0.5, -0.5) in rasterisation") << key;
    }
  }
}

}  // namespace

// Every golden names the evidence bless checked (golden/evidence.json): at least one claim, each
// a reference comparison with what it measured or tests that were found. No golden rests on GL
// and Vulkan agreeing alone.
TEST(Goldens, EveryGoldenNamesTheEvidenceBlessChecked) {
  const nlohmann::json m = manifest();
  size_t references = 0, tests = 0;
  for (const auto& [key, entry] : m["goldens"].items()) {
    SCOPED_TRACE(key);
    ASSERT_TRUE(entry.contains("evidence") && entry["evidence"].is_array() && !entry["evidence"].empty());
    for (const auto& claim : entry["evidence"]) {
      EXPECT_FALSE(claim.value("why", "").empty());
      if (claim.value("kind", "") == "reference") {
        ++references;
        EXPECT_TRUE(claim.contains("bound") && claim.contains("measured")) << claim.dump();
        EXPECT_NE(claim.value("reference", ""), key);
      } else {
        ++tests;
        EXPECT_EQ(claim.value("kind", ""), "tests") << claim.dump();
        EXPECT_EQ(claim.value("found", false), true) << claim.dump();
      }
    }
  }
  EXPECT_GT(references, 72u) << "every console golden is checked against its reference golden";
  EXPECT_GT(tests, 10u);
}
