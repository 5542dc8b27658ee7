// The outputs of one study run: CSV of every measurement, plots, the summary (per-light cost
// slopes and the seeds' ratios) and index.html linking them.
#pragma once

#include <string>
#include <vector>

#include "bench/bench.h"
#include "bench/csv.h"

namespace parity::bench {

// One backend as the run found it.
struct BackendRun {
  std::string backend;
  bool ran = false;
  std::string device;  // renderer / API line, or why it did not run
  double seconds = 0;  // wall time of its child process
};

struct SlopeRow {
  std::string scenario, backend, technique;
  double wallSlope = 0, gpuSlope = 0;  // ms per light
  bool gpu = false;                    // gpuSlope valid
  double r2 = 0;
  size_t points = 0;
};

struct RatioRow {
  std::string name, backend;
  bool available = false;
  double value = 0;
  std::string seed;  // the seed's value, e.g. "4.9x (thesis 4.2)"
  std::string note;  // how it was computed, or why not available
  // From its per-round values: the 95% order-statistic interval of their median
  // (stats.h's medianInterval), after leaving out the rounds outlierIndices finds (0, 0: none).
  double intervalLow = 0, intervalHigh = 0;
  size_t rounds = 0;                 // per-round values the interval is over
  std::vector<size_t> outlierRounds;  // left out of it (0-based)
  // Several processes (StudyPlan::processes): each one's median; the interval reaches all of them.
  std::vector<double> processMedians;
  // Rounds added past the planned ones (lockstep, over every point the ratio pools) and why they
  // ended: "tight", "budget", "round limit" (the worst of its points), empty when none could be added.
  size_t addedRounds = 0;
  std::string roundsStop;
  // The interval reaches further than kRatioTolerance from the value, or the rounds are too few
  // for one: the ratio is not stated as a number (`available` stays true).
  bool inconclusive = false;
};

// How far (relatively) a ratio's interval may reach from its value for the ratio to be stated.
constexpr double kRatioTolerance = 0.05;

struct Summary {
  std::vector<SlopeRow> slopes;
  std::vector<RatioRow> ratios;
};

CsvTable measurementsCsv(const StudyPlan& plan, const std::vector<Measurement>& rows);
Summary summariseStudy(const StudyPlan& plan, const std::vector<Measurement>& rows);
std::string summaryMarkdown(const StudyPlan& plan, const Summary& summary, const std::vector<BackendRun>& backends);
// The ratios as STUDY.json keeps them: value (null when inconclusive or not available), interval,
// rounds kept, outlier rounds (1-based), rounds added and why they ended.
nlohmann::json ratiosJson(const Summary& summary);

// Writes OUT/<study>.csv, OUT/<study>-summary.md, OUT/<study>-summary.csv, one plot per scenario
// and backend (OUT/<study>-<scenario>-<backend>.svg and .png), OUT/<study>.json (what the index
// reads) and regenerates OUT/index.html over every study in OUT. Appends the files written.
bool writeStudyOutputs(const std::string& outDir, const StudyPlan& plan, const std::vector<Measurement>& rows,
                       const std::vector<BackendRun>& backends, std::vector<std::string>* written, std::string* error);

// A ratio of this run against the same ratio of a baseline run (`parity bench --baseline DIR`).
struct RatioChange {
  std::string name, backend;
  RatioRow before, now;
  // Both have an interval and the two do not overlap: the ratio moved by more than either run
  // can tell apart.
  bool moved = false;
  bool judged = false;  // false: an interval is missing, so nothing is claimed
};
// Reads DIR/<study>.json of an earlier run; false with a one-line reason naming the file.
bool readBaseline(const std::string& dir, const std::string& study, StudyPlan* plan, std::vector<Measurement>* rows,
                  std::string* error);
std::vector<RatioChange> compareRatios(const Summary& before, const Summary& now);
std::string baselineMarkdown(const std::string& dir, const std::vector<RatioChange>& changes);

// File-name-safe form of a scenario: "mixed 1:10" -> "mixed-1x10", "big+shadows" -> "big-shadows".
std::string slug(const std::string& text);

}  // namespace parity::bench
