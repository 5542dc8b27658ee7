// `parity bench`: the building blocks (statistics, CSV, plots) and a tiny run of the lights
// study per backend that checks what a user gets: CSV, summary, plots with one curve per
// technique, index.html.
#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <thread>
#include <tuple>

#include "bench/bench.h"
#include "bench/csv.h"
#include "bench/plot.h"
#include "bench/report.h"
#include "bench/stats.h"
#include "bench/pass_groups.h"
#include "harness/io/atomic_file.h"
#include "harness/run/expectations.h"
#include "harness/run/devices.h"
#include "harness/run/process.h"
#include "rhi/rhi.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

TEST(BenchStats, MedianQuartilesAndLeastSquares) {
  bench::Stats s = bench::summarise({5, 1, 4, 2, 3});
  EXPECT_DOUBLE_EQ(s.median, 3);
  EXPECT_DOUBLE_EQ(s.p25, 2);
  EXPECT_DOUBLE_EQ(s.p75, 4);
  EXPECT_DOUBLE_EQ(s.min, 1);
  EXPECT_DOUBLE_EQ(s.max, 5);
  EXPECT_DOUBLE_EQ(bench::summarise({1, 2}).median, 1.5);

  auto fit = bench::fitLine({1, 2, 3, 4}, {3.5, 5.5, 7.5, 9.5});
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->slope, 2.0, 1e-12);
  EXPECT_NEAR(fit->intercept, 1.5, 1e-12);
  EXPECT_NEAR(fit->r2, 1.0, 1e-12);
  EXPECT_FALSE(bench::fitLine({2, 2}, {1, 3}));  // one distinct x: no slope
}

TEST(BenchCsv, RoundTripsQuotedFieldsAndRejectsRaggedRows) {
  bench::CsvTable t;
  t.header = {"a", "b", "c"};
  t.rows = {{"1", "x,y", "say \"hi\""}, {"", "line\nbreak", "z"}};
  bench::CsvTable back;
  std::string error;
  ASSERT_TRUE(bench::parseCsv(bench::formatCsv(t), &back, &error)) << error;
  EXPECT_EQ(back.header, t.header);
  EXPECT_EQ(back.rows, t.rows);
  EXPECT_FALSE(bench::parseCsv("a,b\n1,2,3\n", &back, &error));
  EXPECT_NE(error.find("record 2"), std::string::npos) << error;
  EXPECT_FALSE(bench::parseCsv("a,b\n\"1,2\n", &back, &error));
}

TEST(BenchPlot, OneCurvePerSeries) {
  bench::Plot plot{"t", "lights", "ms", {{"forward", {{1, 2}, {10, 5}}}, {"deferred", {{1, 3, 2.5, 3.5}, {10, 4}}}}};
  std::string svg = bench::renderSvg(plot);
  std::regex curve("<polyline class=\"curve\" data-series=\"([^\"]+)\"");
  std::set<std::string> names;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), curve); it != std::sregex_iterator(); ++it) names.insert((*it)[1]);
  EXPECT_EQ(names, (std::set<std::string>{"forward", "deferred"}));
}

TEST(BenchPassNames, MultiPassLabelsGroup) {
  EXPECT_EQ(bench::passGroupName("light 12"), "light");
  EXPECT_EQ(bench::passGroupName("ambient+directional"), "ambient+directional");
  EXPECT_EQ(bench::passGroupName(""), "(unnamed)");
}

// The software rasterisers' threads: none (the rasteriser on the API's thread) by default,
// LP_NUM_THREADS when the user set it, --raster-threads above both; the plan carries the number to
// the children (a number other than the struct's default 0, so that a field not read would show).
TEST(BenchPlan, TheRasteriserRunsOnTheApisThreadUnlessAsked) {
  const char* userSet = std::getenv("LP_NUM_THREADS");
  const std::string kept = userSet ? userSet : "";
  bench::StudyOptions o;
  o.study = "tiled";
  o.quick = true;
  bench::StudyPlan plan;
  std::string error;
  ::unsetenv("LP_NUM_THREADS");
  ASSERT_TRUE(bench::makeStudyPlan(o, &plan, &error)) << error;
  EXPECT_EQ(plan.rasterThreads, 0u);
  ::setenv("LP_NUM_THREADS", "5", 1);
  ASSERT_TRUE(bench::makeStudyPlan(o, &plan, &error)) << error;
  EXPECT_EQ(plan.rasterThreads, 5u);
  o.rasterThreads = 0;
  ASSERT_TRUE(bench::makeStudyPlan(o, &plan, &error)) << error;
  EXPECT_EQ(plan.rasterThreads, 0u);
  o.rasterThreads = 3;
  ASSERT_TRUE(bench::makeStudyPlan(o, &plan, &error)) << error;
  EXPECT_EQ(bench::planFromJson(bench::toJson(plan)).rasterThreads, 3u);
  if (userSet)
    ::setenv("LP_NUM_THREADS", kept.c_str(), 1);
  else
    ::unsetenv("LP_NUM_THREADS");
}

TEST(BenchPlan, UnregisteredTechniquesAreRecordedAndShadowedPointsMeasureOnlyShadowTechniques) {
  bench::StudyOptions o;
  o.study = "lights";
  o.quick = true;
  o.techniques = {"forward", "no-such-technique", "forward-shadows", "deferred-shadows"};
  bench::StudyPlan plan;
  std::string error;
  ASSERT_TRUE(bench::makeStudyPlan(o, &plan, &error)) << error;
  EXPECT_EQ(plan.techniques, (std::vector<std::string>{"forward", "forward-shadows", "deferred-shadows"}));
  ASSERT_EQ(plan.skipped.size(), 1u);
  EXPECT_EQ(plan.skipped[0].first, "no-such-technique");
  size_t shadowed = 0;
  for (const bench::BenchPoint& p : plan.points) {
    // Thesis 4.1 / 4.3: the big lights of "big+shadows" and of the mixed scenes cast shadows.
    const bool wantShadows = p.scenario == "big+shadows" || p.scenario.rfind("mixed", 0) == 0;
    EXPECT_EQ(p.shadows, wantShadows) << p.scenario;
    EXPECT_TRUE(p.unavailable.empty()) << p.scenario;
    if (p.shadows) {
      ++shadowed;
      EXPECT_EQ(bench::techniquesAt(plan, p), (std::vector<std::string>{"forward-shadows", "deferred-shadows"}));
    } else {
      EXPECT_EQ(bench::techniquesAt(plan, p), std::vector<std::string>{"forward"});
    }
  }
  EXPECT_GT(shadowed, 0u);
  o.study = "no-such-study";
  EXPECT_FALSE(bench::makeStudyPlan(o, &plan, &error));
  EXPECT_NE(error.find("unknown study"), std::string::npos);
}

class BenchCli : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("parity-bench-test-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_P(BenchCli, TinyLightsStudyWritesCsvPlotsAndSummary) {
  const std::string backend = GetParam();
  bool timestamps = false;
  {
    auto device = test::makeDevice(backend, false);  // skips (or fails when required) if unavailable
    if (!device) return;
    timestamps = device->info().caps.timestamps;
  }
  const std::vector<std::string> measured = {"forward", "forward-multipass"};
  const std::vector<std::string> measuredWithShadows = {"forward-shadows", "deferred-shadows"};
  harness::ProcessResult r = harness::runProcess(
      {PARITY_BINARY, "bench", "lights", "--backend", backend, "--size", "64x36", "--frames", "2", "--warmup", "0", "--lights",
       "1,3", "--techniques", "forward,forward-multipass,no-such-technique,forward-shadows,deferred-shadows",
       "--raster-threads", "1", "--processes", "1", "--out", dir_.string()},
      240);
  ASSERT_FALSE(r.timedOut);
  ASSERT_EQ(r.exitCode, 0) << r.err;

  for (const char* f : {"lights.csv", "lights-summary.md", "lights-summary.csv", "lights.json", "index.html"})
    EXPECT_TRUE(fs::is_regular_file(dir_ / f)) << f;
  for (const auto& e : fs::directory_iterator(dir_)) EXPECT_NE(e.path().filename().string()[0], '.') << "left over: " << e.path();

  std::string text, error;
  ASSERT_TRUE(harness::readTextFile((dir_ / "lights.csv").string(), &text, &error)) << error;
  bench::CsvTable csv;
  ASSERT_TRUE(bench::parseCsv(text, &csv, &error)) << error;
  const int tech = csv.column("technique"), status = csv.column("status"), scen = csv.column("scenario"),
            wall = csv.column("wall_median_ms"), note = csv.column("note"), back = csv.column("backend");
  ASSERT_GE(std::min({tech, status, scen, wall, note, back}), 0);
  size_t ok = 0, shadowRows = 0, skipped = 0;
  for (const auto& row : csv.rows) {
    EXPECT_EQ(row[back], backend);
    if (row[status] == "ok") {
      ++ok;
      EXPECT_GT(std::stod(row[wall]), 0.0) << row[tech] << " " << row[scen];
    }
    if (row[scen] == "big+shadows" || row[scen].rfind("mixed", 0) == 0) {
      ++shadowRows;
      EXPECT_EQ(row[status], "ok") << row[note];
      EXPECT_NE(std::find(measuredWithShadows.begin(), measuredWithShadows.end(), row[tech]), measuredWithShadows.end()) << row[tech];
    }
    if (row[tech] == "no-such-technique") {
      ++skipped;
      EXPECT_EQ(row[status], "skipped");
    }
  }
  // small and big at 1 and 3 lights: 4 points x 2 techniques; big+shadows at 1 and 3, mixed 1:10
  // and 1:5 at k = 1 and 3: 6 points x the 2 shadow techniques.
  EXPECT_EQ(ok, 20u);
  EXPECT_EQ(shadowRows, 12u);
  EXPECT_EQ(skipped, 1u);

  // Wall times come from the 2 measured rounds, GPU and per-pass times from the timestamped
  // rounds before them, which the measured rounds do not repeat.
  ASSERT_TRUE(harness::readTextFile((dir_ / "lights.json").string(), &text, &error)) << error;
  const nlohmann::json study = nlohmann::json::parse(text);
  size_t timedRows = 0;
  for (const auto& row : study.at("rows")) {
    if (row.at("status") != "ok") continue;
    ++timedRows;
    EXPECT_EQ(row.at("wall").at("n"), 2) << row.at("technique");
    EXPECT_EQ(row.at("gpu").at("n"), timestamps ? bench::kTimestampRounds : 0) << row.at("technique");
    EXPECT_EQ(row.at("passes").empty(), !timestamps) << row.at("technique");
  }
  EXPECT_EQ(timedRows, ok);

  // One curve per measured technique in every plot; the PNG has the same content drawn.
  for (const char* scenario : {"small", "big", "big-shadows", "mixed-1x10", "mixed-1x5"}) {
    const bool shadows = std::string(scenario) != "small" && std::string(scenario) != "big";
    const fs::path svgPath = dir_ / ("lights-" + std::string(scenario) + "-" + backend + ".svg");
    ASSERT_TRUE(harness::readTextFile(svgPath.string(), &text, &error)) << error;
    std::regex curve("<polyline class=\"curve\" data-series=\"([^\"]+)\"");
    std::vector<std::string> names;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), curve); it != std::sregex_iterator(); ++it) names.push_back((*it)[1]);
    EXPECT_EQ(names, shadows ? measuredWithShadows : measured) << svgPath;
    OIIO::ImageBuf png((dir_ / ("lights-" + std::string(scenario) + "-" + backend + ".png")).string());
    ASSERT_TRUE(png.read()) << png.geterror();
    EXPECT_EQ(png.spec().width, 720);
    auto stats = OIIO::ImageBufAlgo::computePixelStats(png);
    EXPECT_LT(stats.min[0], 0.5f) << "the PNG has no lines";
  }

  ASSERT_TRUE(harness::readTextFile((dir_ / "lights-summary.md").string(), &text, &error)) << error;
  EXPECT_NE(text.find("| small | " + backend + " | forward-multipass |"), std::string::npos) << text;
  // The child created its device with the plan's rasteriser threads (a GPU driver ignores them).
  EXPECT_NE(text.find("- `" + backend + "`: "), std::string::npos) << text;
  EXPECT_NE(text.find("| LP_NUM_THREADS=1 ("), std::string::npos) << text;
  EXPECT_NE(text.find("forward-multipass / deferred per-light cost, small lights"), std::string::npos) << text;
  EXPECT_NE(text.find("forward-shadows / deferred-shadows per-light cost, big+shadows lights"), std::string::npos) << text;
  ASSERT_TRUE(harness::readTextFile((dir_ / "index.html").string(), &text, &error)) << error;
  EXPECT_NE(text.find("lights-small-" + backend + ".svg"), std::string::npos);
  EXPECT_NE(text.find("lights.csv"), std::string::npos);
}

// Both backends in lockstep (the default): their children take turns round by round, so round i
// of Vulkan starts after round i of GL ends and before round i + 1 of GL; the summary's ratio
// pairs those rounds. --sequential runs every GL round before the first Vulkan one.
TEST(BenchLockstep, BackendsTakeTurnsRoundByRound) {
  for (const std::string b : {"gl", "vk"}) {
    auto device = test::makeDevice(b, false);  // skips (or fails when required) if unavailable
    if (!device) return;
  }
  const fs::path dir = fs::temp_directory_path() / ("parity-bench-lockstep-" + std::to_string(::getpid()));
  for (const bool lockstep : {true, false}) {
    SCOPED_TRACE(lockstep ? "lockstep" : "sequential");
    // --max-rounds 4: no round added past the planned ones (BenchRounds checks those).
    std::vector<std::string> args = {PARITY_BINARY, "bench", "tiled", "--size", "64x36", "--frames", "4", "--max-rounds", "4",
                                     "--warmup", "0", "--lights", "64", "--techniques", "deferred", "--processes", "1",
                                     "--out", dir.string()};
    if (!lockstep) args.push_back("--sequential");
    harness::ProcessResult r = harness::runProcess(args, 240);
    ASSERT_FALSE(r.timedOut);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const auto& e : fs::directory_iterator(dir)) EXPECT_NE(e.path().filename().string()[0], '.') << "left over: " << e.path();
    std::string text, error;
    ASSERT_TRUE(harness::readTextFile((dir / "tiled.json").string(), &text, &error)) << error;
    const nlohmann::json study = nlohmann::json::parse(text);
    EXPECT_EQ(study["lockstep"], lockstep);
    std::map<std::string, bench::Measurement> byBackend;
    for (const auto& row : study["rows"]) {
      bench::Measurement m = bench::measurementFromJson(row);
      if (m.technique == "deferred" && m.status == "ok") byBackend[m.backend] = m;
    }
    ASSERT_EQ(byBackend.size(), 2u);
    const bench::Measurement &gl = byBackend["gl"], &vk = byBackend["vk"];
    ASSERT_EQ(gl.frameStarts.size(), 4u);
    ASSERT_EQ(vk.frameStarts.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
      if (lockstep) {
        EXPECT_GE(vk.frameStarts[i], gl.frameStarts[i] + gl.frames[i]) << "round " << i;
        if (i + 1 < 4) {
          EXPECT_GE(gl.frameStarts[i + 1], vk.frameStarts[i] + vk.frames[i]) << "round " << i;
        }
      } else {
        EXPECT_GT(vk.frameStarts[0], gl.frameStarts[3] + gl.frames[3]);
      }
    }
    ASSERT_TRUE(harness::readTextFile((dir / "tiled-summary.md").string(), &text, &error)) << error;
    EXPECT_EQ(text.find("lockstep: median of the per-round ratios") != std::string::npos, lockstep) << text;
    if (lockstep) {
      EXPECT_NE(text.find("4 rounds are too few for a 95% interval"), std::string::npos) << text;
    }
    fs::remove_all(dir);
  }
}

// The interval of a median: the order statistics the binomial distribution gives. 5 samples
// cannot give 95% (each interval of them covers at most 93.75%), 6 give their range (96.9%), 20
// give the 6th to the 15th (95.9%; the 7th to the 14th would cover 88.5%).
TEST(BenchIntervals, MedianIntervalIsTheBinomialOrderStatistics) {
  std::vector<double> samples;
  for (int i = 1; i <= 20; ++i) samples.push_back(i);
  bench::MedianInterval twenty = bench::medianInterval(samples);
  ASSERT_TRUE(twenty.valid);
  EXPECT_EQ(twenty.low, 6);
  EXPECT_EQ(twenty.high, 15);
  EXPECT_NEAR(twenty.coverage, 0.9586, 1e-4);
  EXPECT_FALSE(bench::medianInterval({5, 1, 4, 2, 3}).valid);
  bench::MedianInterval six = bench::medianInterval({6, 1, 5, 2, 4, 3});
  ASSERT_TRUE(six.valid);
  EXPECT_EQ(six.low, 1);
  EXPECT_EQ(six.high, 6);
  EXPECT_EQ(bench::outlierIndices({1.0, 1.01, 0.99, 1.0, 9.0, 1.02}), (std::vector<size_t>{4}));
  EXPECT_TRUE(bench::outlierIndices({1.0, 9.0, 1.0, 1.0}).empty()) << "too few to tell";
}

// A planted noisy backend, round by round (the rows a lockstep run records): a quiet run states
// its Vulkan / GL ratio with an interval; two rounds that paused are named and left out, and the
// ratio stays; rounds that swing by a factor of two give an interval too wide to state a number.
// Frames of technique "deferred" at one point: GL's 10 ms a round, Vulkan's 10 ms times each
// round's ratio (both with the same 0-2 us wobble), in processes of the given rounds (one: {}).
struct DeferredPoint {
  double x = 64;
  std::vector<double> ratios;
  std::vector<size_t> processRounds;
};

// The Vulkan / GL frame time of deferred that the summary of those points gives.
bench::RatioRow deferredVkOverGl(const bench::StudyPlan& plan, const std::vector<DeferredPoint>& points) {
  std::vector<bench::Measurement> rows;
  for (const DeferredPoint& point : points)
    for (const std::string backend : {"gl", "vk"}) {
      bench::Measurement m;
      m.backend = backend;
      m.technique = "deferred";
      m.scenario = "small";
      m.x = point.x;
      m.status = "ok";
      m.processRounds = point.processRounds;
      for (size_t i = 0; i < point.ratios.size(); ++i)
        m.frames.push_back((backend == "gl" ? 10.0 : 10.0 * point.ratios[i]) + 0.001 * (i % 3));
      m.wall = bench::summarise(m.frames);
      rows.push_back(m);
    }
  for (const bench::RatioRow& r : bench::summariseStudy(plan, rows).ratios)
    if (r.name == "vk / gl frame time, deferred") return r;
  ADD_FAILURE() << "no vk / gl ratio";
  return bench::RatioRow{};
}

bench::StudyPlan deferredPlan(uint32_t frames, uint32_t processes) {
  bench::StudyPlan plan;
  plan.study = "tiled";
  plan.techniques = {"deferred"};
  plan.lockstep = true;
  plan.frames = frames;
  plan.processes = processes;
  return plan;
}

// A ratio over several points weighs every point the same: a point that needed more rounds to
// tighten does not pull the ratio towards its own. Point A: 30 rounds at 1.00, point B: 10 rounds
// at 1.20; the ratio is the geometric mean of the two, sqrt(1.2). And independent points tell
// more together than one: nine points whose rounds alternate 0.9 and 1.1 each have an interval of
// 0.9-1.1, too wide to state; together the interval is a third as wide.
TEST(BenchIntervals, EveryPointWeighsTheSameInAPooledRatio) {
  const bench::StudyPlan plan = deferredPlan(10, 1);
  const bench::RatioRow two = deferredVkOverGl(plan, {{64, std::vector<double>(30, 1.0)}, {1024, std::vector<double>(10, 1.2)}});
  EXPECT_EQ(two.rounds, 40u) << two.note;
  EXPECT_NEAR(two.value, std::sqrt(1.2), 0.001) << two.note;
  EXPECT_FALSE(two.inconclusive) << two.note;
  EXPECT_NEAR(two.intervalLow, std::sqrt(1.2), 0.001) << two.note;
  EXPECT_NEAR(two.intervalHigh, std::sqrt(1.2), 0.001) << two.note;
  EXPECT_NE(two.note.find("geometric mean of 2 points' medians"), std::string::npos) << two.note;

  // Nine points of 12 rounds alternating 0.9 and 1.1: each point's interval is 0.9-1.1 around
  // 1.0, log(1 / 0.9) on its wider side; together sqrt(9 * log(1 / 0.9)^2) / 9, a third of
  // that, each side of 1.
  std::vector<DeferredPoint> nine;
  for (int p = 0; p < 9; ++p) {
    nine.push_back({64.0 * (p + 1), {}});
    for (int i = 0; i < 12; ++i) nine.back().ratios.push_back(i % 2 ? 1.1 : 0.9);
  }
  const bench::RatioRow together = deferredVkOverGl(plan, nine);
  EXPECT_NEAR(together.value, 1.0, 0.001) << together.note;
  EXPECT_NEAR(together.intervalHigh, std::pow(1 / 0.9, 1.0 / 3), 0.002) << together.note;
  EXPECT_NEAR(together.intervalLow, std::pow(0.9, 1.0 / 3), 0.002) << together.note;
  EXPECT_FALSE(together.inconclusive) << together.note;
}

// A process that runs slower as a whole (its heap, its threads' placement) is not an outlier
// round: the rounds of four processes, three at 1.00 and one at 1.12, give a pooled interval of
// the median at 1.00 alone, which a run of other processes would not repeat. The interval reaches
// every process's median, so the ratio is inconclusive until the processes agree.
TEST(BenchIntervals, AProcessThatRunsSlowerWidensTheIntervalToItsMedian) {
  const bench::StudyPlan plan = deferredPlan(48, 4);
  auto inProcesses = [&](const std::vector<double>& processRatios) {
    DeferredPoint point;
    for (double ratio : processRatios) {
      point.ratios.insert(point.ratios.end(), 12, ratio);
      point.processRounds.push_back(12);
    }
    return deferredVkOverGl(plan, {point});
  };
  const bench::RatioRow agreeing = inProcesses({1.0, 1.0, 1.02, 1.0});
  EXPECT_FALSE(agreeing.inconclusive) << agreeing.note;
  EXPECT_EQ(agreeing.processMedians.size(), 4u) << agreeing.note;
  EXPECT_NEAR(agreeing.intervalHigh, 1.02, 0.001) << agreeing.note;

  const bench::RatioRow oneSlow = inProcesses({1.0, 1.0, 1.12, 1.0});
  EXPECT_NEAR(oneSlow.value, 1.0, 0.001) << oneSlow.note;
  EXPECT_TRUE(oneSlow.outlierRounds.empty()) << oneSlow.note;
  ASSERT_EQ(oneSlow.processMedians.size(), 4u) << oneSlow.note;
  EXPECT_NEAR(oneSlow.processMedians[2], 1.12, 0.001);
  EXPECT_NEAR(oneSlow.intervalHigh, 1.12, 0.001) << oneSlow.note;
  EXPECT_TRUE(oneSlow.inconclusive) << oneSlow.note;
  EXPECT_NE(oneSlow.note.find("48 rounds in 4 processes (medians 1.000 1.000 1.120 1.000)"), std::string::npos)
      << oneSlow.note;
}

TEST(BenchIntervals, PausesAreLeftOutAndNoiseIsInconclusive) {
  bench::StudyPlan plan;
  plan.study = "tiled";
  plan.techniques = {"deferred"};
  plan.lockstep = true;
  auto rows = [](const std::vector<double>& vkFrames) {
    std::vector<bench::Measurement> out;
    for (const std::string backend : {"gl", "vk"}) {
      bench::Measurement m;
      m.backend = backend;
      m.technique = "deferred";
      m.scenario = "small";
      m.x = 1024;
      m.status = "ok";
      m.frames = backend == "gl" ? std::vector<double>(vkFrames.size(), 10.0) : vkFrames;
      m.wall = bench::summarise(m.frames);
      out.push_back(m);
    }
    return out;
  };
  auto vkOverGl = [&](const std::vector<double>& vkFrames) {
    bench::Summary s = bench::summariseStudy(plan, rows(vkFrames));
    for (const bench::RatioRow& r : s.ratios)
      if (r.name == "vk / gl frame time, deferred") return std::make_pair(r, bench::summaryMarkdown(plan, s, {}));
    ADD_FAILURE() << "no vk / gl ratio";
    return std::make_pair(bench::RatioRow{}, std::string());
  };
  const std::vector<double> quiet = {9.0, 9.02, 8.98, 9.01, 8.99, 9.0, 9.03, 8.97, 9.0, 9.01, 8.99, 9.0};
  auto [steady, steadyText] = vkOverGl(quiet);
  EXPECT_FALSE(steady.inconclusive) << steady.note;
  EXPECT_NEAR(steady.value, 0.9, 0.005);
  EXPECT_LE(steady.intervalHigh - steady.intervalLow, 0.01) << steady.note;
  EXPECT_NE(steadyText.find("| vk / gl frame time, deferred | vk/gl | 0.90x (0.90-0.90) |"), std::string::npos) << steadyText;

  std::vector<double> paused = quiet;
  paused[2] = 40.0, paused[7] = 35.0;
  auto [withPauses, pausedText] = vkOverGl(paused);
  EXPECT_FALSE(withPauses.inconclusive) << withPauses.note;
  EXPECT_NEAR(withPauses.value, 0.9, 0.005);
  EXPECT_EQ(withPauses.outlierRounds, (std::vector<size_t>{2, 7}));
  EXPECT_NE(withPauses.note.find("rounds 3 (4.00) 8 (3.50) left out as outliers"), std::string::npos) << withPauses.note;
  EXPECT_EQ(withPauses.rounds, 10u);

  std::vector<double> noisy;
  for (int i = 0; i < 12; ++i) noisy.push_back(i % 2 ? 12.0 : 6.0);
  auto [swinging, noisyText] = vkOverGl(noisy);
  EXPECT_TRUE(swinging.inconclusive) << swinging.note;
  EXPECT_GT(swinging.intervalHigh - swinging.intervalLow, 0.5) << swinging.note;
  EXPECT_NE(noisyText.find("| vk / gl frame time, deferred | vk/gl | inconclusive (0.60-1.20) |"), std::string::npos) << noisyText;
}

// A ratio moved when the two runs' intervals do not overlap; without an interval nothing is
// claimed.
TEST(BenchBaseline, MovedOnlyWhereTheIntervalsDoNotOverlap) {
  auto ratio = [](double value, double lo, double hi) {
    bench::RatioRow r;
    r.name = "vk / gl frame time, forward";
    r.backend = "vk/gl";
    r.available = true;
    r.value = value;
    r.intervalLow = lo;
    r.intervalHigh = hi;
    return r;
  };
  bench::Summary before, overlapping, apart, noSpread;
  before.ratios = {ratio(1.0, 0.9, 1.1)};
  overlapping.ratios = {ratio(1.15, 1.05, 1.3)};
  apart.ratios = {ratio(1.4, 1.2, 1.6)};
  noSpread.ratios = {ratio(3.0, 0, 0)};
  auto changes = bench::compareRatios(before, overlapping);
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_TRUE(changes[0].judged);
  EXPECT_FALSE(changes[0].moved);
  changes = bench::compareRatios(before, apart);
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_TRUE(changes[0].moved);
  EXPECT_NE(bench::baselineMarkdown("old", changes).find("**MOVED**"), std::string::npos);
  changes = bench::compareRatios(before, noSpread);
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_FALSE(changes[0].judged);
  EXPECT_FALSE(changes[0].moved);
}

// End to end: a baseline whose Vulkan rounds took a hundredth of the time (far beyond what rounds
// of tiny frames vary on a busy machine) flags the Vulkan / GL ratio as moved (16 rounds: a busy
// machine's outlier rounds left out, enough remain for both intervals); a missing baseline is a one-line error before any
// measurement, and nothing is written.
TEST(BenchBaseline, ARegressionAgainstTheBaselineIsFlagged) {
  for (const std::string b : {"gl", "vk"}) {
    auto device = test::makeDevice(b, false);
    if (!device) return;
  }
  const fs::path base = fs::temp_directory_path() / ("parity-bench-base-" + std::to_string(::getpid()));
  const fs::path now = fs::temp_directory_path() / ("parity-bench-now-" + std::to_string(::getpid()));
  const std::vector<std::string> args = {PARITY_BINARY, "bench", "tiled", "--size", "64x36", "--frames", "16", "--warmup", "0",
                                         "--budget", "0", "--lights", "64", "--techniques", "deferred"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = args;
    a.insert(a.end(), extra.begin(), extra.end());
    return harness::runProcess(a, 240);
  };
  harness::ProcessResult r = with({"--out", base.string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  std::string text, error;
  ASSERT_TRUE(harness::readTextFile((base / "tiled.json").string(), &text, &error)) << error;
  nlohmann::json study = nlohmann::json::parse(text);
  for (auto& row : study["rows"])
    if (row["backend"] == "vk")
      for (auto& f : row["frames"]) f = f.get<double>() / 100.0;
  ASSERT_TRUE(harness::writeFileAtomic((base / "tiled.json").string(), study.dump(), &error)) << error;

  r = with({"--out", now.string(), "--baseline", base.string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("| vk / gl frame time, deferred | vk/gl |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("**MOVED**"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("vk / gl frame time, deferred (vk/gl) moved"), std::string::npos) << r.err;

  const fs::path nowhere = fs::temp_directory_path() / ("parity-bench-none-" + std::to_string(::getpid()));
  fs::remove_all(now);
  r = with({"--out", now.string(), "--baseline", nowhere.string()});
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find((nowhere / "tiled.json").string()), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(now));
  fs::remove_all(base);
}

TEST(BenchCliErrors, BadInputIsOneLineAndWritesNothing) {
  fs::path dir = fs::temp_directory_path() / ("parity-bench-bad-" + std::to_string(::getpid()));
  harness::ProcessResult r =
      harness::runProcess({PARITY_BINARY, "bench", "lights", "--size", "0x9", "--out", dir.string()}, 60);
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("--size"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir));
  r = harness::runProcess({PARITY_BINARY, "bench", "lights", "--scene", "no/such/file.obj", "--out", dir.string()}, 60);
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("no/such/file.obj"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir));
}

// The environment variable a test plants for the children of `parity bench` (inherited), removed
// again when the scope ends.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) { ::setenv(name, value.c_str(), 1); }
  ~ScopedEnv() { ::unsetenv(name_); }

 private:
  const char* name_;
};

// A tiny lockstep run (one technique at 64x36: rounds of a few ms) and its ratios from STUDY.json.
struct TinyRun {
  harness::ProcessResult process;
  nlohmann::json study;
  std::string summary;
  const nlohmann::json* ratio(const std::string& name) const {
    for (const auto& r : study["ratios"])
      if (r["name"] == name) return &r;
    return nullptr;
  }
};
TinyRun tinyTiledRun(const fs::path& dir, const std::vector<std::string>& extra) {
  std::vector<std::string> args = {PARITY_BINARY, "bench", "tiled", "--size", "64x36", "--warmup", "0", "--lights", "64",
                                   "--techniques", "deferred", "--out", dir.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  TinyRun run;
  run.process = harness::runProcess(args, 240);
  std::string text, error;
  if (harness::readTextFile((dir / "tiled.json").string(), &text, &error)) run.study = nlohmann::json::parse(text, nullptr, false);
  harness::readTextFile((dir / "tiled-summary.md").string(), &run.summary, &error);
  return run;
}

// A planted noisy Vulkan backend (PARITY_BENCH_PLANT_SLEEP: a sleep inside the timed frames of
// some rounds). One round that sleeps 300 ms is named as an outlier and left out of the Vulkan /
// GL ratio; a sleep of a random 0-30 ms in every round swings the ratio by far more than +-5%, so
// the bench adds rounds past the 12 planned until its budget is spent, and then reports the ratio
// inconclusive with an interval wider than the single pause left.
TEST(BenchRounds, APlantedPauseIsLeftOutAndPlantedNoiseAddsRoundsUntilTheBudget) {
  for (const std::string b : {"gl", "vk"}) {
    auto device = test::makeDevice(b, false);
    if (!device) return;
  }
  const fs::path dir = fs::temp_directory_path() / ("parity-bench-rounds-" + std::to_string(::getpid()));
  const std::string name = "vk / gl frame time, deferred";
  double pauseWidth = 0;
  {
    ScopedEnv plant("PARITY_BENCH_PLANT_SLEEP", "vk:300:3");
    TinyRun run = tinyTiledRun(dir, {"--budget", "2"});
    ASSERT_EQ(run.process.exitCode, 0) << run.process.err;
    const nlohmann::json* r = run.ratio(name);
    ASSERT_TRUE(r) << run.study.dump();
    const std::vector<size_t> outliers = (*r)["outlier_rounds"].get<std::vector<size_t>>();
    EXPECT_NE(std::find(outliers.begin(), outliers.end(), 3u), outliers.end()) << r->dump();
    std::smatch named;
    ASSERT_TRUE(std::regex_search(run.summary, named, std::regex(R"(rounds( \d+ \([0-9.]+\))* 3 \(([0-9.]+)\)[^|]* left out as outliers)")))
        << run.summary;
    EXPECT_GT(std::stod(named[2]), 5.0) << "round 3's ratio: 300 ms over a few";
    ASSERT_TRUE((*r)["interval"].is_array()) << r->dump();
    pauseWidth = (*r)["interval"][1].get<double>() - (*r)["interval"][0].get<double>();
    fs::remove_all(dir);
  }
  {
    ScopedEnv plant("PARITY_BENCH_PLANT_SLEEP", "vk:~30:%1");
    TinyRun run = tinyTiledRun(dir, {"--budget", "1", "--max-rounds", "1000"});
    ASSERT_EQ(run.process.exitCode, 0) << run.process.err;
    const nlohmann::json* r = run.ratio(name);
    ASSERT_TRUE(r) << run.study.dump();
    EXPECT_GT((*r)["added_rounds"].get<size_t>(), 0u) << r->dump();
    EXPECT_EQ((*r)["rounds_stop"], "budget") << r->dump();
    EXPECT_TRUE((*r)["inconclusive"].get<bool>()) << r->dump();
    EXPECT_TRUE((*r)["value"].is_null()) << r->dump();
    ASSERT_TRUE((*r)["interval"].is_array()) << r->dump();
    EXPECT_GT((*r)["interval"][1].get<double>() - (*r)["interval"][0].get<double>(), 2 * pauseWidth) << r->dump();
    for (const auto& row : run.study["rows"])
      if (row["technique"] == "deferred") {
        EXPECT_GT(row["frames"].size(), 12u) << row["backend"];
      }
    EXPECT_NE(run.summary.find("| " + name + " | vk/gl | inconclusive ("), std::string::npos) << run.summary;
    EXPECT_NE(run.summary.find("then the budget was spent"), std::string::npos) << run.summary;
    fs::remove_all(dir);
  }
  ScopedEnv bad("PARITY_BENCH_PLANT_SLEEP", "vk:twenty:%2");
  TinyRun run = tinyTiledRun(dir, {});
  EXPECT_NE(run.process.exitCode, 0);
  EXPECT_EQ(std::count(run.process.err.begin(), run.process.err.end(), '\n'), 1) << run.process.err;
  EXPECT_NE(run.process.err.find("PARITY_BENCH_PLANT_SLEEP"), std::string::npos) << run.process.err;
  EXPECT_FALSE(fs::exists(dir));
}

// `--processes 2`: each device measured in two processes side by side, all four in lockstep (round
// by round: GL's first process, Vulkan's first, GL's second, Vulkan's second), their rounds merged
// into one row per point. Vulkan's second process planted slower (a 20 ms sleep in each of its
// frames) shows as that process's median, and the Vulkan / GL interval reaches it.
TEST(BenchProcesses, EveryDeviceIsMeasuredInSeveralProcessesAndASlowOneShows) {
  for (const std::string b : {"gl", "vk"}) {
    auto device = test::makeDevice(b, false);
    if (!device) return;
  }
  const fs::path dir = fs::temp_directory_path() / ("parity-bench-processes-" + std::to_string(::getpid()));
  ScopedEnv plant("PARITY_BENCH_PLANT_SLEEP", "vk#2:20:%1");
  TinyRun run = tinyTiledRun(dir, {"--processes", "2", "--frames", "6", "--max-rounds", "6"});
  ASSERT_EQ(run.process.exitCode, 0) << run.process.err;
  for (const auto& e : fs::directory_iterator(dir)) EXPECT_NE(e.path().filename().string()[0], '.') << "left over: " << e.path();
  std::map<std::string, bench::Measurement> byBackend;
  for (const auto& row : run.study["rows"]) {
    bench::Measurement m = bench::measurementFromJson(row);
    if (m.technique == "deferred" && m.status == "ok") byBackend[m.backend] = m;
  }
  ASSERT_EQ(byBackend.size(), 2u);
  const bench::Measurement &gl = byBackend["gl"], &vk = byBackend["vk"];
  EXPECT_EQ(gl.processRounds, (std::vector<size_t>{3, 3}));
  EXPECT_EQ(vk.processRounds, (std::vector<size_t>{3, 3}));
  ASSERT_EQ(gl.frameStarts.size(), 6u);
  ASSERT_EQ(vk.frameStarts.size(), 6u);
  for (size_t j = 0; j < 3; ++j) {
    // Round j: GL process 1, Vulkan process 1, GL process 2, Vulkan process 2, then round j + 1.
    const double order[] = {gl.frameStarts[j], vk.frameStarts[j], gl.frameStarts[3 + j], vk.frameStarts[3 + j]};
    EXPECT_TRUE(std::is_sorted(std::begin(order), std::end(order))) << "round " << j;
    if (j + 1 < 3) {
      EXPECT_LT(vk.frameStarts[3 + j], gl.frameStarts[j + 1]) << "round " << j;
    }
  }
  for (size_t j = 0; j < 3; ++j) {
    EXPECT_LT(vk.frames[j], 15.0) << "process 1 was not planted";
    EXPECT_GT(vk.frames[3 + j], 20.0) << "process 2 sleeps 20 ms in each frame";
  }
  const nlohmann::json* r = run.ratio("vk / gl frame time, deferred");
  ASSERT_TRUE(r) << run.study["ratios"].dump();
  const std::vector<double> medians = (*r)["process_medians"].get<std::vector<double>>();
  ASSERT_EQ(medians.size(), 2u) << r->dump();
  EXPECT_GT(medians[1], 2 * medians[0]) << r->dump();
  ASSERT_TRUE((*r)["interval"].is_array()) << r->dump();
  EXPECT_GE((*r)["interval"][1].get<double>(), medians[1]) << r->dump();
  EXPECT_TRUE((*r)["inconclusive"].get<bool>()) << r->dump();
  EXPECT_NE(run.summary.find("2 processes a device, each with 0 warm-up, 2 timestamped"), std::string::npos) << run.summary;
  fs::remove_all(dir);

  ScopedEnv bad("PARITY_BENCH_PLANT_SLEEP", "vk#0:20:%1");
  run = tinyTiledRun(dir, {"--processes", "2"});
  EXPECT_NE(run.process.exitCode, 0);
  EXPECT_EQ(std::count(run.process.err.begin(), run.process.err.end(), '\n'), 1) << run.process.err;
  EXPECT_FALSE(fs::exists(dir));
  run = tinyTiledRun(dir, {"--processes", "7", "--frames", "6"});
  EXPECT_NE(run.process.exitCode, 0);
  EXPECT_NE(run.process.err.find("--processes 7 must be 1..6"), std::string::npos) << run.process.err;
  EXPECT_FALSE(fs::exists(dir));
}

// `--devices`: one child per device in lockstep, rows, plots and ratios labelled by device, each
// device's frame time over the first one's. An unknown device is a one-line error before anything
// is written; a device that cannot be created (Zink without a Vulkan driver) fails the run with
// its reason.
TEST(BenchDevices, RowsAreLabelledByDeviceWithRatiosToTheFirst) {
  for (const std::string d : {"gl-llvmpipe", "vk-lavapipe"}) {
    rhi::DeviceDesc desc;
    std::string why;
    if (!harness::resolveDevice(d, &desc, &why)) GTEST_SKIP() << why;
    desc.validation = false;
    if (!rhi::createDevice(desc, &why)) GTEST_SKIP() << d << ": " << why;
  }
  const fs::path dir = fs::temp_directory_path() / ("parity-bench-devices-" + std::to_string(::getpid()));
  TinyRun run = tinyTiledRun(dir, {"--devices", "gl-llvmpipe,vk-lavapipe", "--budget", "1"});
  ASSERT_EQ(run.process.exitCode, 0) << run.process.err;
  std::set<std::string> labels;
  for (const auto& row : run.study["rows"])
    if (row["status"] == "ok") labels.insert(row["backend"].get<std::string>());
  EXPECT_EQ(labels, (std::set<std::string>{"gl-llvmpipe", "vk-lavapipe"}));
  for (const char* d : {"gl-llvmpipe", "vk-lavapipe"}) EXPECT_TRUE(fs::is_regular_file(dir / ("tiled-small-" + std::string(d) + ".svg"))) << d;
  const nlohmann::json* r = run.ratio("vk-lavapipe / gl-llvmpipe frame time, deferred");
  ASSERT_TRUE(r) << run.study["ratios"].dump();
  EXPECT_EQ((*r)["backend"], "vk-lavapipe/gl-llvmpipe");
  EXPECT_TRUE((*r)["available"].get<bool>());
  EXPECT_GT((*r)["median"].get<double>(), 0.0);
  EXPECT_NE(run.summary.find("| vk-lavapipe / gl-llvmpipe frame time, deferred | vk-lavapipe/gl-llvmpipe | "), std::string::npos)
      << run.summary;
  fs::remove_all(dir);

  run = tinyTiledRun(dir, {"--devices", "gl-llvmpipe,gl-nosuchdriver"});
  EXPECT_NE(run.process.exitCode, 0);
  EXPECT_EQ(std::count(run.process.err.begin(), run.process.err.end(), '\n'), 1) << run.process.err;
  EXPECT_NE(run.process.err.find("unknown device 'gl-nosuchdriver'"), std::string::npos) << run.process.err;
  EXPECT_FALSE(fs::exists(dir));

  {
    ScopedEnv noVulkan("VK_ICD_FILENAMES", (dir / "no-such-icd.json").string());
    run = tinyTiledRun(dir, {"--devices", "gl-llvmpipe,gl-zink", "--budget", "0"});
  }
  EXPECT_EQ(run.process.exitCode, 1) << run.process.err;
  EXPECT_NE(run.process.err.find("gl-zink did not run: device not created: GL driver 'zink'"), std::string::npos) << run.process.err;
  EXPECT_NE(run.summary.find("`gl-zink`: not run: device not created"), std::string::npos) << run.summary;
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Backends, BenchCli, ::testing::ValuesIn(test::allBackends()), test::BackendName());

}  // namespace
