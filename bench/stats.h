// Order statistics of repeated frame timings and least-squares fits of cost against light count.
#pragma once

#include <optional>
#include <vector>

namespace parity::bench {

// Summary of N samples (milliseconds). Median and quartiles by linear interpolation between
// order statistics, so that three frames already give a usable spread.
struct Stats {
  size_t count = 0;
  double median = 0, p25 = 0, p75 = 0, min = 0, max = 0;
};

Stats summarise(std::vector<double> samples);

// Value of the sorted samples at quantile q in [0, 1] (linear interpolation).
double quantileSorted(const std::vector<double>& sorted, double q);

// A distribution-free confidence interval for the median of independent samples: the order
// statistics X(k) and X(n+1-k) with the largest k whose coverage, 1 - 2 P(Binomial(n, 1/2) < k),
// is at least `level`. Not valid for fewer samples than any k covers (5 for 95%: all of them
// cover only 93.75%).
struct MedianInterval {
  bool valid = false;
  double low = 0, high = 0;
  double coverage = 0;  // the interval's own coverage, >= the level asked for
};
MedianInterval medianInterval(std::vector<double> samples, double level = 0.95);

// Indices of the samples farther from the median than `threshold` scaled median absolute
// deviations (1.4826 MAD estimates a normal distribution's sigma): a round that paused, compiled
// or was preempted. None among fewer than 5 samples, or when the MAD is 0.
std::vector<size_t> outlierIndices(const std::vector<double>& samples, double threshold = 3.5);

// num[i] / den[i] for the rounds both have, where den[i] > 0: a ratio round by round.
std::vector<double> roundRatios(const std::vector<double>& num, const std::vector<double>& den);

// Whether [low, high] lies within +-tolerance (relative) of value, value > 0.
bool withinTolerance(double low, double high, double value, double tolerance);

// A ratio's per-round values judged: the outlier rounds left out, the median of the rest and its
// 95% interval, and whether that interval lies within +-tolerance of `reference` (the median when
// 0). The summary states a ratio only when `tight`; `parity bench` adds rounds until it is.
struct RatioSpread {
  std::vector<size_t> outliers;  // indices into the per-round values
  size_t kept = 0;
  double median = 0;
  MedianInterval interval;
  bool tight = false;
};
RatioSpread ratioSpread(const std::vector<double>& perRound, double tolerance, double reference = 0);

// The same over rounds measured in several processes (parity bench --processes), each process's
// rounds in its own vector. A process can be slower or faster as a whole (its heap, its threads'
// placement: docs/BENCH.md, "Several processes a run"), which no interval over one process's rounds
// shows. So the outliers, median and interval of the pooled rounds are widened to reach every
// process's own median (over its kept rounds): the range of K process medians covers the median
// process's ratio with probability 1 - 2^(1-K) (87.5% for 4), and the pooled interval covers the
// rounds' spread. One process: the same as ratioSpread.
struct ProcessSpread : RatioSpread {
  std::vector<double> processMedians;  // one per process with rounds, in order
  MedianInterval roundsInterval;       // the pooled rounds' interval, before it was widened
};
ProcessSpread ratioSpread(const std::vector<std::vector<double>>& perProcess, double tolerance, double reference = 0);

struct LinearFit {
  double slope = 0, intercept = 0;
  double r2 = 0;  // coefficient of determination; 1 when every point lies on the line
  size_t points = 0;
};

// Ordinary least squares y = slope * x + intercept. nullopt for fewer than two distinct x.
std::optional<LinearFit> fitLine(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace parity::bench
