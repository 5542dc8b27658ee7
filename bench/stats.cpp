#include "bench/stats.h"

#include <algorithm>
#include <cmath>

namespace parity::bench {

double quantileSorted(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0;
  const double pos = q * static_cast<double>(sorted.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, sorted.size() - 1);
  const double t = pos - static_cast<double>(lo);
  return sorted[lo] + (sorted[hi] - sorted[lo]) * t;
}

Stats summarise(std::vector<double> samples) {
  Stats s;
  if (samples.empty()) return s;
  std::sort(samples.begin(), samples.end());
  s.count = samples.size();
  s.median = quantileSorted(samples, 0.5);
  s.p25 = quantileSorted(samples, 0.25);
  s.p75 = quantileSorted(samples, 0.75);
  s.min = samples.front();
  s.max = samples.back();
  return s;
}

MedianInterval medianInterval(std::vector<double> samples, double level) {
  MedianInterval out;
  const size_t n = samples.size();
  if (n == 0) return out;
  std::sort(samples.begin(), samples.end());
  // P(Binomial(n, 1/2) < k), accumulated k by k.
  double below = 0, term = std::pow(0.5, static_cast<double>(n));  // C(n, 0) / 2^n
  for (size_t k = 1; 2 * k <= n + 1; ++k) {
    below += term;
    term *= static_cast<double>(n - (k - 1)) / static_cast<double>(k);
    const double coverage = 1.0 - 2.0 * below;
    if (coverage < level) break;
    out = {true, samples[k - 1], samples[n - k], coverage};
  }
  return out;
}

std::vector<size_t> outlierIndices(const std::vector<double>& samples, double threshold) {
  std::vector<size_t> out;
  if (samples.size() < 5) return out;
  std::vector<double> sorted = samples;
  std::sort(sorted.begin(), sorted.end());
  const double median = quantileSorted(sorted, 0.5);
  std::vector<double> deviations;
  for (double v : samples) deviations.push_back(std::fabs(v - median));
  std::sort(deviations.begin(), deviations.end());
  const double sigma = 1.4826 * quantileSorted(deviations, 0.5);
  if (sigma <= 0) return out;
  for (size_t i = 0; i < samples.size(); ++i)
    if (std::fabs(samples[i] - median) > threshold * sigma) out.push_back(i);
  return out;
}

std::vector<double> roundRatios(const std::vector<double>& num, const std::vector<double>& den) {
  std::vector<double> out;
  for (size_t i = 0; i < std::min(num.size(), den.size()); ++i)
    if (den[i] > 0) out.push_back(num[i] / den[i]);
  return out;
}

bool withinTolerance(double low, double high, double value, double tolerance) {
  return value > 0 && low >= value * (1 - tolerance) && high <= value * (1 + tolerance);
}

RatioSpread ratioSpread(const std::vector<double>& perRound, double tolerance, double reference) {
  RatioSpread r;
  r.outliers = outlierIndices(perRound);
  std::vector<double> kept;
  for (size_t i = 0; i < perRound.size(); ++i)
    if (!std::count(r.outliers.begin(), r.outliers.end(), i)) kept.push_back(perRound[i]);
  r.kept = kept.size();
  r.median = summarise(kept).median;
  r.interval = medianInterval(kept);
  const double value = reference > 0 ? reference : r.median;
  r.tight = r.interval.valid && withinTolerance(r.interval.low, r.interval.high, value, tolerance);
  return r;
}

ProcessSpread ratioSpread(const std::vector<std::vector<double>>& perProcess, double tolerance, double reference) {
  std::vector<double> pooled;
  for (const auto& rounds : perProcess) pooled.insert(pooled.end(), rounds.begin(), rounds.end());
  ProcessSpread r;
  static_cast<RatioSpread&>(r) = ratioSpread(pooled, tolerance, reference);
  r.roundsInterval = r.interval;
  if (perProcess.size() < 2 || !r.interval.valid) return r;
  size_t first = 0;
  for (const auto& rounds : perProcess) {
    std::vector<double> kept;
    for (size_t i = 0; i < rounds.size(); ++i)
      if (!std::count(r.outliers.begin(), r.outliers.end(), first + i)) kept.push_back(rounds[i]);
    first += rounds.size();
    if (kept.empty()) continue;
    const double median = summarise(kept).median;
    r.processMedians.push_back(median);
    r.interval.low = std::min(r.interval.low, median);
    r.interval.high = std::max(r.interval.high, median);
  }
  const double value = reference > 0 ? reference : r.median;
  r.tight = withinTolerance(r.interval.low, r.interval.high, value, tolerance);
  return r;
}

std::optional<LinearFit> fitLine(const std::vector<double>& x, const std::vector<double>& y) {
  const size_t n = std::min(x.size(), y.size());
  if (n < 2) return std::nullopt;
  double mx = 0, my = 0;
  for (size_t i = 0; i < n; ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxx = 0, sxy = 0, syy = 0;
  for (size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  if (sxx <= 0) return std::nullopt;
  LinearFit f;
  f.points = n;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  f.r2 = syy > 0 ? (sxy * sxy) / (sxx * syy) : 1.0;
  return f;
}

}  // namespace parity::bench
