// Goldens need evidence (harness/run/evidence.h): `parity bless` refuses a golden no claim of
// evidence.json covers (GL and Vulkan agreeing is not evidence), checks each claim that covers
// it (a reference comparison within its bound, tests that exist) and records them in the
// manifest. Any refusal writes nothing. The images here are another engine's (`parity run
// --images`), planted so that each claim holds or breaks by a known amount.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <unistd.h>

#include <algorithm>

#include <filesystem>
#include <fstream>
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
  return harness::runProcess(args, 120);
}

// A 32x32 gradient, `delta` (in 8-bit steps) added to the red channel of `pixels` pixels.
void writeImage(const fs::path& path, int delta = 0, int pixels = 0) {
  OIIO::ImageSpec spec(32, 32, 4, OIIO::TypeDesc::UINT8);
  OIIO::ImageBuf img(spec);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const int i = y * 32 + x;
      const float v[4] = {(x * 4 + (i < pixels ? delta : 0)) / 255.0f, y * 4 / 255.0f, 0.5f, 1.0f};
      img.setpixel(x, y, v);
    }
  fs::create_directories(path.parent_path());
  ASSERT_TRUE(img.write(path.string()));
}

class GoldenEvidence : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("parity-evidence-" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_ / "golden");
  }
  void TearDown() override { fs::remove_all(root_); }

  // The other engine's forward/default/{reference, dx10}, both backends alike; dx10 differs from
  // the reference by `delta` steps at `pixels` pixels. Returns the run's folder.
  fs::path runOf(int delta, int pixels) {
    for (const char* b : {"gl", "vk"}) {
      writeImage(root_ / "engine" / "forward" / "default" / "reference" / (std::string(b) + ".png"));
      writeImage(root_ / "engine" / "forward" / "default" / "dx10" / (std::string(b) + ".png"), delta, pixels);
    }
    const fs::path out = root_ / "run";
    fs::remove_all(out);
    harness::ProcessResult r = parity({"run", "--images", (root_ / "engine").string(), "--golden",
                                       (root_ / "golden").string(), "--out", out.string(), "--no-progress"});
    EXPECT_TRUE(fs::exists(out / "results.json")) << r.out << r.err;
    return out;
  }
  void writeEvidence(const std::string& claims) {
    std::ofstream(root_ / "golden" / "evidence.json")
        << "{\"tests_root\": \"" << PARITY_SOURCE_DIR << "\", \"evidence\": [" << claims << "]}\n";
  }
  harness::ProcessResult bless(const fs::path& run) {
    return parity({"bless", "--from", run.string(), "--golden", (root_ / "golden").string()});
  }
  // Nothing but evidence.json in the golden folder.
  void expectNothingWritten() {
    for (const auto& e : fs::recursive_directory_iterator(root_ / "golden"))
      EXPECT_EQ(e.path().filename(), "evidence.json") << e.path() << " was written by a refused bless";
  }

  static constexpr const char* kTests =
      R"({"case": "forward/*/reference", "tests": ["tests/golden_evidence_test.cpp: GoldenEvidence.ReferenceBoundAndTestsAreCheckedAndRecorded"], "why": "planted"})";
  static constexpr const char* kBound =
      R"({"case": "*/*/dx10", "reference": "{technique}/{scene}/reference", "bound": {"max": 0.004, "percent": 1, "threshold": 0.002}, "why": "one step at a few pixels"})";
  fs::path root_;
};

TEST_F(GoldenEvidence, AGroupWithoutEvidenceIsRefusedAndNothingIsWritten) {
  const fs::path run = runOf(0, 0);
  harness::ProcessResult r = bless(run);  // no evidence.json at all
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("forward/default/reference refused: no evidence covers it (GL and Vulkan agreeing is not evidence"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("nothing written"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(root_ / "golden" / "manifest.json"));
  EXPECT_FALSE(fs::exists(root_ / "golden" / "forward"));

  // One group covered, the other not: still nothing is written.
  writeEvidence(kTests);
  r = bless(run);
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("forward/default/dx10 refused: no evidence covers it"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("forward/default/reference refused"), std::string::npos) << r.err;
  expectNothingWritten();
}

TEST_F(GoldenEvidence, ReferenceBoundAndTestsAreCheckedAndRecorded) {
  writeEvidence(std::string(kTests) + ", " + kBound);
  harness::ProcessResult r = bless(runOf(1, 5));  // one step at 5 of 1024 pixels: within the bound
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("evidence: reference forward/default/reference"), std::string::npos) << r.out;
  const nlohmann::json m = nlohmann::json::parse(test::readFile(root_ / "golden" / "manifest.json"));
  const nlohmann::json& dx10 = m["goldens"]["forward/default/dx10"]["evidence"];
  ASSERT_EQ(dx10.size(), 1u) << dx10.dump();
  EXPECT_EQ(dx10[0]["kind"], "reference");
  EXPECT_EQ(dx10[0]["reference"], "forward/default/reference");
  EXPECT_NEAR(dx10[0]["measured"]["max"].get<double>(), 1.0 / 255.0, 1e-6);
  EXPECT_NEAR(dx10[0]["measured"]["percent"].get<double>(), 100.0 * 5 / 1024, 1e-6);
  EXPECT_EQ(dx10[0]["bound"]["max"], 0.004);
  const nlohmann::json& ref = m["goldens"]["forward/default/reference"]["evidence"];
  ASSERT_EQ(ref.size(), 1u);
  EXPECT_EQ(ref[0]["kind"], "tests");
  EXPECT_EQ(ref[0]["found"], true);
}

TEST_F(GoldenEvidence, AReferenceComparisonBeyondItsBoundIsRefused) {
  writeEvidence(std::string(kTests) + ", " + kBound);
  harness::ProcessResult r = bless(runOf(3, 5));  // three steps: beyond max 0.004
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("forward/default/dx10 refused: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("evidence[1]: against forward/default/reference: max 0.0117647 > 0.004"), std::string::npos)
      << r.err;
  expectNothingWritten();
  r = bless(runOf(1, 40));  // one step, but at 3.9% of the pixels: beyond percent 1
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("% of pixels over 0.002 > 1%"), std::string::npos) << r.err;
  expectNothingWritten();
}

TEST_F(GoldenEvidence, TestsThatDoNotExistAreRefused) {
  writeEvidence(R"({"case": "*", "tests": ["tests/golden_evidence_test.cpp: GoldenEvidence.NoSuchTest"], "why": "x"})");
  harness::ProcessResult r = bless(runOf(0, 0));
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("tests/golden_evidence_test.cpp has no test GoldenEvidence.NoSuchTest"), std::string::npos) << r.err;
  expectNothingWritten();
  writeEvidence(R"({"case": "*", "tests": ["tests/no_such_test.cpp: A.B"], "why": "x"})");
  r = bless(runOf(0, 0));
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("test file tests/no_such_test.cpp not found"), std::string::npos) << r.err;
  expectNothingWritten();
}

TEST_F(GoldenEvidence, ABadEvidenceFileIsOneLineNamingItAndWritesNothing) {
  const fs::path run = runOf(0, 0);
  const std::vector<std::pair<std::string, std::string>> bad = {
      {R"({"case": "*", "why": "no claim"})", "give either \"reference\" (with \"bound\") or \"tests\""},
      {R"({"case": "*", "reference": "{technique}/{scene}/reference", "why": "x"})", "a reference claim needs a \"bound\""},
      {R"({"case": "*", "reference": "r", "bound": {"maximum": 1}, "why": "x"})", "unknown bound \"maximum\""},
      {R"({"case": "*", "reference": "r", "bound": {"percent": 1}, "why": "x"})", "bound \"percent\" and \"threshold\" go together"},
      {R"({"case": "*", "tests": ["no suite here"], "why": "x"})", "\"tests\": \"no suite here\" is not \"FILE: Suite.Name\""},
      {R"({"case": "*", "tests": ["tests/a.cpp: A.B"]})", "\"why\" is required"},
      {R"({"case": "*", "tests": ["tests/a.cpp: A.B"], "why": "x", "reason": "y"})", "unknown key \"reason\""},
  };
  for (const auto& [claim, message] : bad) {
    SCOPED_TRACE(claim);
    writeEvidence(claim);
    harness::ProcessResult r = bless(run);
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.err.find("evidence.json: evidence[0]: " + message), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    expectNothingWritten();
  }
}

}  // namespace
