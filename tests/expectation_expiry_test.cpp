// Expectations that age: an entry of the expectations file may carry a bug link and an expiry
// date; once the date has passed the entry is reported (stderr, results.json, junit.xml, the
// report) and fails the run under --strict. The dates are computed from today's, so the test holds
// whatever day it runs.
#include <chrono>
#include <cstdio>

#include "images_run_support.h"

using namespace parity;
namespace fs = std::filesystem;

namespace {

// Today plus `days` (UTC), as YYYY-MM-DD.
std::string dateFromToday(int days) {
  const auto day = std::chrono::floor<std::chrono::days>(std::chrono::system_clock::now()) + std::chrono::days{days};
  const std::chrono::year_month_day ymd{day};
  char text[16];
  std::snprintf(text, sizeof(text), "%04d-%02u-%02u", static_cast<int>(ymd.year()), static_cast<unsigned>(ymd.month()),
                static_cast<unsigned>(ymd.day()));
  return text;
}

class ExpectationExpiry : public test::ImagesRunTest {
 protected:
  void SetUp() override {
    test::ImagesRunTest::SetUp();
    // The engine's image is upside down: a known failure the expectations file expects.
    test::writePicture("engine/lit/default/console/d3d12.png", /*flipped=*/true);
    test::writePicture("golden/lit/default/console.png");
  }
  static void expect(const std::string& expires) {
    std::ofstream("golden/expectations.json")
        << R"({"expectations": [{"case": "lit/default/console/d3d12", "result": "Fail", "reason": "rendered upside down",
                                 "bug": "https://bugs.example.org/42", "expires": ")"
        << expires << "\"}]}\n";
  }
};

TEST_F(ExpectationExpiry, AnEntryExpiredYesterdayIsReportedAndFailsUnderStrict) {
  const std::string yesterday = dateFromToday(-1);
  expect(yesterday);
  harness::ProcessResult r = run("engine", "lenient");
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;  // still expected, but said
  EXPECT_NE(r.err.find("parity run: note: expectation for lit/default/console/d3d12 expired on " + yesterday +
                       " (rendered upside down; bug https://bugs.example.org/42): renew its date or remove it"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("1 ExpectedFail, 1 expired expectation"), std::string::npos) << r.out;

  r = run("engine", "strict", {"--strict"});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("parity run: FAILED: expectation for lit/default/console/d3d12 expired on " + yesterday),
            std::string::npos)
      << r.err;
  const nlohmann::json j = results("strict");
  ASSERT_EQ(j["expired_expectations"].size(), 1u) << j.dump(2);
  EXPECT_EQ(j["expired_expectations"][0]["expires"], yesterday);
  EXPECT_EQ(j["expired_expectations"][0]["bug"], "https://bugs.example.org/42");
  EXPECT_EQ(j["cases"][0]["result"], "ExpectedFail");
  EXPECT_EQ(j["cases"][0]["expectation"]["expired"], true);
  EXPECT_NE(test::readFile("strict/report/index.html").find("<h2>Expired expectations</h2>"), std::string::npos);
  EXPECT_NE(test::readFile("strict/junit.xml").find("<failure type=\"ExpiredExpectation\""), std::string::npos);

  // A merge keeps them, and fails when its inputs ran under --strict.
  r = test::runParity({"merge", "strict", "--out", "merged"});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.out.find("1 ExpectedFail, 1 expired expectation"), std::string::npos) << r.out;
  EXPECT_EQ(results("merged")["expired_expectations"], j["expired_expectations"]);
  EXPECT_EQ(test::runParity({"merge", "lenient", "--out", "merged-lenient"}).exitCode, 0);
}

TEST_F(ExpectationExpiry, AnEntryExpiringTomorrowOrTodayStillHolds) {
  for (int days : {1, 0}) {
    expect(dateFromToday(days));
    const std::string out = "out" + std::to_string(days);
    harness::ProcessResult r = run("engine", out, {"--strict"});
    EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
    EXPECT_EQ(r.err.find("expired"), std::string::npos) << r.err;
    const nlohmann::json j = results(out);
    EXPECT_TRUE(j["expired_expectations"].empty()) << j.dump(2);
    EXPECT_EQ(j["cases"][0]["expectation"]["expired"], false);
  }
}

TEST_F(ExpectationExpiry, AMalformedDateIsOneLineNamingTheFileAndNothingIsWritten) {
  for (const char* bad : {"2026-02-30", "2026-2-01", "next week", "2026-13-01"}) {
    expect(bad);
    harness::ProcessResult r = run("engine", "out");
    EXPECT_NE(r.exitCode, 0) << bad;
    EXPECT_EQ(r.err, std::string("parity: error: golden/expectations.json: expectations[0]: expires '") + bad +
                         "' is not a date YYYY-MM-DD\n");
    EXPECT_FALSE(fs::exists("out")) << bad;
  }
}

}  // namespace
