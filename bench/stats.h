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

struct LinearFit {
  double slope = 0, intercept = 0;
  double r2 = 0;  // coefficient of determination; 1 when every point lies on the line
  size_t points = 0;
};

// Ordinary least squares y = slope * x + intercept. nullopt for fewer than two distinct x.
std::optional<LinearFit> fitLine(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace parity::bench
