#include "bench/report.h"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "bench/plot.h"
#include "harness/io/atomic_file.h"
#include "harness/run/expectations.h"

namespace fs = std::filesystem;

namespace parity::bench {

namespace {

std::string fmt(double v, const char* f = "%.4g") {
  char buf[64];
  std::snprintf(buf, sizeof(buf), f, v);
  return buf;
}

std::string passesText(const std::vector<std::pair<std::string, double>>& passes) {
  std::string s;
  for (const auto& [n, v] : passes) s += (s.empty() ? "" : ";") + n + "=" + fmt(v, "%.4f");
  return s;
}

bool lightAxis(const StudyPlan& plan) { return plan.xLabel == "lights"; }

const Measurement* find(const std::vector<Measurement>& rows, const std::string& backend, const std::string& technique,
                        const std::string& scenario, double x) {
  for (const Measurement& m : rows)
    if (m.status == "ok" && m.backend == backend && m.technique == technique && m.scenario == scenario && std::fabs(m.x - x) < 1e-9)
      return &m;
  return nullptr;
}

const SlopeRow* findSlope(const Summary& s, const std::string& scenario, const std::string& backend, const std::string& technique) {
  for (const SlopeRow& r : s.slopes)
    if (r.scenario == scenario && r.backend == backend && r.technique == technique) return &r;
  return nullptr;
}

std::vector<std::string> backendsOf(const std::vector<Measurement>& rows) {
  std::vector<std::string> out;
  for (const Measurement& m : rows)
    if (std::find(out.begin(), out.end(), m.backend) == out.end()) out.push_back(m.backend);
  return out;
}

std::vector<std::string> scenariosOf(const StudyPlan& plan) {
  std::vector<std::string> out;
  for (const BenchPoint& p : plan.points)
    if (std::find(out.begin(), out.end(), p.scenario) == out.end()) out.push_back(p.scenario);
  return out;
}

// Reason a technique has no result in a scenario on a backend, from its rows.
std::string whyMissing(const std::vector<Measurement>& rows, const std::string& backend, const std::string& technique,
                       const std::string& scenario) {
  for (const Measurement& m : rows)
    if (m.backend == backend && m.technique == technique && (m.scenario == scenario || m.scenario == "*") && m.status != "ok")
      return technique + " " + m.status + (m.note.empty() ? "" : ": " + m.note);
  return technique + " not measured";
}

// A ratio as the summary states it: the value with its interval, or why there is no number.
std::string ratioText(const RatioRow& r) {
  if (!r.available) return "not available";
  const std::string interval = r.intervalHigh > 0 ? fmt(r.intervalLow, "%.2f") + "-" + fmt(r.intervalHigh, "%.2f") : "";
  if (r.inconclusive) return "inconclusive" + (interval.empty() ? std::string() : " (" + interval + ")");
  return fmt(r.value, "%.2f") + "x" + (interval.empty() ? "" : " (" + interval + ")");
}

// The interval of a ratio's per-round values, one vector per process (RatioRow), their outliers
// left out and named (numbered through the processes in order).
void setInterval(RatioRow& r, const std::vector<std::vector<double>>& perProcess, bool valueIsTheirMedian) {
  const ProcessSpread spread = ratioSpread(perProcess, kRatioTolerance, valueIsTheirMedian ? 0 : r.value);
  std::vector<double> perRound;
  for (const auto& rounds : perProcess) perRound.insert(perRound.end(), rounds.begin(), rounds.end());
  r.rounds = spread.kept;
  r.outlierRounds = spread.outliers;
  r.processMedians = spread.processMedians;
  if (valueIsTheirMedian && spread.kept > 0) r.value = spread.median;
  if (!spread.outliers.empty()) {
    r.note += "; rounds";
    for (size_t i : spread.outliers) r.note += " " + std::to_string(i + 1) + " (" + fmt(perRound[i], "%.2f") + ")";
    r.note += " left out as outliers";
  }
  if (!spread.interval.valid) {
    r.inconclusive = true;
    r.note += "; " + std::to_string(spread.kept) + " rounds are too few for a 95% interval (6 at least)";
    return;
  }
  r.intervalLow = spread.interval.low;
  r.intervalHigh = spread.interval.high;
  r.inconclusive = r.value <= 0 || !spread.tight;
  r.note += "; " + std::to_string(spread.kept) + " rounds";
  if (!spread.processMedians.empty()) {
    r.note += " in " + std::to_string(spread.processMedians.size()) + " processes (medians";
    for (double m : spread.processMedians) r.note += " " + fmt(m, "%.3f");
    r.note += ")";
  }
  r.note += ", 95% interval " + fmt(spread.interval.low, "%.3f") + "-" + fmt(spread.interval.high, "%.3f") +
            (r.inconclusive ? " (wider than +-5%: inconclusive)" : "");
}

// A ratio over several points, each point weighing the same however many rounds it took to
// tighten: the geometric mean of the points' medians. Its interval, in logarithms: the points'
// rounds are independent from point to point, so the half-width is the root of the sum of the
// squares of the points' own half-widths (each the wider side of its rounds' 95% interval) over
// the number of points: n points as wide as one give an interval 1/sqrt(n) as wide. A process
// that ran slower as a whole would be so at every point, which that does not shrink: the interval
// is widened to reach each process's geometric mean of its medians at the points. A ratio whose
// every point is within +-5% (as the lockstep judges them) is within +-5%.
void setPointsInterval(RatioRow& r, const std::vector<std::vector<std::vector<double>>>& perPoint) {
  double logValue = 0, sumSquares = 0;
  size_t outliers = 0, tooFew = 0;
  const size_t processes = perPoint.front().size();
  std::vector<double> logProcess(processes, 0.0);
  bool everyProcess = processes > 1;
  r.rounds = 0;
  for (const auto& point : perPoint) {
    const ProcessSpread spread = ratioSpread(point, kRatioTolerance);
    r.rounds += spread.kept;
    outliers += spread.outliers.size();
    if (!spread.roundsInterval.valid || spread.median <= 0 || spread.roundsInterval.low <= 0) {
      ++tooFew;
      continue;
    }
    logValue += std::log(spread.median);
    const double halfWidth = std::max(std::log(spread.roundsInterval.high / spread.median),
                                      std::log(spread.median / spread.roundsInterval.low));
    sumSquares += halfWidth * halfWidth;
    everyProcess = everyProcess && spread.processMedians.size() == processes;
    for (size_t p = 0; everyProcess && p < processes; ++p) logProcess[p] += std::log(spread.processMedians[p]);
  }
  if (outliers) r.note += "; " + std::to_string(outliers) + " rounds left out as outliers";
  if (tooFew) {
    r.inconclusive = true;
    r.note += "; " + std::to_string(tooFew) + " points have too few rounds for a 95% interval (6 at least)";
    return;
  }
  const double n = static_cast<double>(perPoint.size());
  r.value = std::exp(logValue / n);
  const double halfWidth = std::sqrt(sumSquares) / n;
  r.intervalLow = r.value * std::exp(-halfWidth);
  r.intervalHigh = r.value * std::exp(halfWidth);
  r.note += "; " + std::to_string(r.rounds) + " rounds, the points' 95% intervals combined " + fmt(r.intervalLow, "%.3f") +
            "-" + fmt(r.intervalHigh, "%.3f");
  if (everyProcess) {
    r.note += "; in " + std::to_string(processes) + " processes (geometric means of their medians";
    for (double l : logProcess) {
      r.processMedians.push_back(std::exp(l / n));
      r.intervalLow = std::min(r.intervalLow, r.processMedians.back());
      r.intervalHigh = std::max(r.intervalHigh, r.processMedians.back());
      r.note += " " + fmt(r.processMedians.back(), "%.3f");
    }
    r.note += ")";
  }
  r.inconclusive = !withinTolerance(r.intervalLow, r.intervalHigh, r.value, kRatioTolerance);
  r.note += ", interval " + fmt(r.intervalLow, "%.3f") + "-" + fmt(r.intervalHigh, "%.3f") +
            (r.inconclusive ? " (wider than +-5%: inconclusive)" : "");
}

// Round by round, num's frame time over den's, one vector per process: round j of a process with
// round j of the same process (rows of different point groups may have different numbers of
// added rounds).
std::vector<std::vector<double>> pairedRatios(const Measurement& num, const Measurement& den) {
  const std::vector<std::vector<double>> a = framesByProcess(num), b = framesByProcess(den);
  if (a.size() != b.size()) return {};
  std::vector<std::vector<double>> out;
  for (size_t p = 0; p < a.size(); ++p) out.push_back(roundRatios(a[p], b[p]));
  return out;
}

// Per-light cost of `technique` fitted to one round's frame times alone, for every round, one
// vector per process (a round of a process is measured at every point).
std::vector<std::vector<double>> perRoundSlopes(const std::vector<Measurement>& rows, const std::string& backend,
                                                const std::string& technique, const std::string& scenario) {
  std::vector<double> x;
  std::vector<std::vector<std::vector<double>>> frames;  // per point, per process
  for (const Measurement& m : rows)
    if (m.status == "ok" && m.backend == backend && m.technique == technique && m.scenario == scenario) {
      x.push_back(m.x);
      frames.push_back(framesByProcess(m));
    }
  std::vector<std::vector<double>> slopes;
  if (frames.empty()) return slopes;
  for (size_t p = 0; p < frames.front().size(); ++p) {
    slopes.emplace_back();
    for (size_t j = 0;; ++j) {
      std::vector<double> y;
      for (const auto& point : frames)
        if (p < point.size() && j < point[p].size()) y.push_back(point[p][j]);
      if (y.size() != x.size()) break;
      if (auto fit = fitLine(x, y)) slopes.back().push_back(fit->slope);
    }
  }
  return slopes;
}

void slopeRatio(Summary& s, const std::vector<Measurement>& rows, const std::string& backend, const std::string& scenario,
                const std::string& a, const std::string& b, const std::string& seed) {
  RatioRow r;
  r.name = a + " / " + b + " per-light cost, " + scenario + " lights";
  r.backend = backend;
  r.seed = seed;
  const SlopeRow* sa = findSlope(s, scenario, backend, a);
  const SlopeRow* sb = findSlope(s, scenario, backend, b);
  if (!sa || !sb) {
    r.note = !sa ? whyMissing(rows, backend, a, scenario) : whyMissing(rows, backend, b, scenario);
  } else if (sb->wallSlope <= 0) {
    r.note = b + "'s slope is not positive (" + fmt(sb->wallSlope) + " ms/light): the ratio is meaningless";
  } else {
    r.available = true;
    r.value = sa->wallSlope / sb->wallSlope;
    r.note = "least-squares slopes of median frame time: " + fmt(sa->wallSlope) + " / " + fmt(sb->wallSlope) + " ms per light";
    // The same ratio round by round (each round's frames fitted alone): its run-to-run spread.
    const std::vector<std::vector<double>> slopesA = perRoundSlopes(rows, backend, a, scenario),
                                           slopesB = perRoundSlopes(rows, backend, b, scenario);
    std::vector<std::vector<double>> perProcess;
    for (size_t p = 0; p < std::min(slopesA.size(), slopesB.size()); ++p) perProcess.push_back(roundRatios(slopesA[p], slopesB[p]));
    setInterval(r, perProcess, false);
  }
  s.ratios.push_back(r);
}

void pointRatio(Summary& s, const std::vector<Measurement>& rows, const std::string& name, const std::string& backend,
                const std::string& a, const std::string& sa, double xa, const std::string& b, const std::string& sb, double xb,
                const std::string& seed) {
  RatioRow r;
  r.name = name;
  r.backend = backend;
  r.seed = seed;
  const Measurement* ma = find(rows, backend, a, sa, xa);
  const Measurement* mb = find(rows, backend, b, sb, xb);
  if (!ma || !mb) {
    r.note = !ma ? whyMissing(rows, backend, a, sa) : whyMissing(rows, backend, b, sb);
  } else {
    r.available = mb->wall.median > 0;
    r.value = r.available ? ma->wall.median / mb->wall.median : 0;
    r.note = "median frame times " + fmt(ma->wall.median) + " / " + fmt(mb->wall.median) + " ms";
    // Round by round (the techniques of one round are measured next to each other): the median
    // of those ratios is the value, their interval the spread.
    const std::vector<std::vector<double>> perProcess = pairedRatios(*ma, *mb);
    std::vector<double> perRound;
    for (const auto& rounds : perProcess) perRound.insert(perRound.end(), rounds.begin(), rounds.end());
    if (!perRound.empty()) r.value = summarise(perRound).median;
    setInterval(r, perProcess, true);
  }
  s.ratios.push_back(r);
}

int stopRank(const std::string& reason) {
  return reason == "round limit" ? 3 : reason == "budget" ? 2 : reason == "tight" ? 1 : 0;
}

// `other`'s frame time over `reference`'s for technique t (summariseStudy's last ratios).
void crossRatio(Summary& s, const StudyPlan& plan, const std::vector<Measurement>& rows, const std::string& reference,
                const std::string& other, const std::string& t) {
  double logSum = 0;
  size_t n = 0;
  std::vector<std::vector<std::vector<double>>> perPoint;  // each point's per-round ratios, per process
  size_t added = 0;
  std::string stop;
  const size_t planned = static_cast<size_t>(framesPerProcess(plan)) * plan.processes;
  for (const Measurement& m : rows) {
    if (m.backend != other || m.technique != t || m.status != "ok") continue;
    const Measurement* g = nullptr;
    for (const Measurement& o : rows)
      if (o.backend == reference && o.technique == t && o.status == "ok" && o.scenario == m.scenario && o.x == m.x && o.params == m.params)
        g = &o;
    if (g && g->wall.median > 0 && m.wall.median > 0) {
      logSum += std::log(m.wall.median / g->wall.median);
      ++n;
    }
    if (g && g->frames.size() == m.frames.size()) {
      perPoint.push_back(pairedRatios(m, *g));
      if (m.frames.size() > planned) added += m.frames.size() - planned;
      // The worst reason over the points: a round limit, then a spent budget, outweigh "tight".
      for (const std::string& reason : {m.roundsStop, g->roundsStop})
        if (stopRank(reason) > stopRank(stop)) stop = reason;
    }
  }
  const std::string name = other == "vk" && reference == "gl" ? "vk / gl" : other + " / " + reference;
  RatioRow r{name + " frame time, " + t, other + "/" + reference, n > 0, n ? std::exp(logSum / n) : 0, "-", ""};
  r.note = n ? "geometric mean over " + std::to_string(n) + " points" : whyMissing(rows, reference, t, "*");
  if (n && plan.lockstep && !perPoint.empty()) {
    r.addedRounds = added;
    r.roundsStop = stop;
    r.note = perPoint.size() == 1 ? "lockstep: median of the per-round ratios"
                                  : "lockstep: geometric mean of " + std::to_string(perPoint.size()) +
                                        " points' medians of their per-round ratios";
    if (!stop.empty())
      r.note += "; " + std::to_string(added) + " rounds added, " +
                (stop == "tight" ? std::string("until the interval was within +-5%") : stop == "budget" ? "then the budget was spent" : "then the round limit was reached");
    if (perPoint.size() == 1)
      setInterval(r, perPoint.front(), true);
    else
      setPointsInterval(r, perPoint);
  }
  s.ratios.push_back(r);
}

}  // namespace

std::string slug(const std::string& text) {
  std::string s;
  for (char c : text) {
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '.') s += c;
    else if (c == ':') s += 'x';
    else if (!s.empty() && s.back() != '-') s += '-';
  }
  while (!s.empty() && s.back() == '-') s.pop_back();
  return s.empty() ? "all" : s;
}

CsvTable measurementsCsv(const StudyPlan& plan, const std::vector<Measurement>& rows) {
  CsvTable t;
  t.header = {"study", "scenario", "backend", "platform", "technique", "params", "x", "lights", "big_lights", "small_lights",
              "width", "height", "warmup", "frames", "wall_median_ms", "wall_p25_ms", "wall_p75_ms", "wall_min_ms",
              "wall_max_ms", "gpu_median_ms", "gpu_p25_ms", "gpu_p75_ms", "passes_gpu_median_ms", "status", "note"};
  for (const Measurement& m : rows) {
    const bool ok = m.status == "ok";
    const bool gpu = ok && m.gpu.count > 0;
    auto v = [&](bool have, double d) { return have ? fmt(d, "%.4f") : std::string(); };
    t.rows.push_back({plan.study, m.scenario, m.backend, plan.platform, m.technique, m.params, m.scenario == "*" ? "" : fmt(m.x, "%g"),
                      m.scenario == "*" ? "" : std::to_string(m.bigLights + m.smallLights), std::to_string(m.bigLights),
                      std::to_string(m.smallLights), std::to_string(plan.width), std::to_string(plan.height),
                      std::to_string(plan.warmup), ok ? std::to_string(m.wall.count) : "0", v(ok, m.wall.median),
                      v(ok, m.wall.p25), v(ok, m.wall.p75), v(ok, m.wall.min), v(ok, m.wall.max), v(gpu, m.gpu.median),
                      v(gpu, m.gpu.p25), v(gpu, m.gpu.p75), passesText(m.passes), m.status, m.note});
  }
  return t;
}

Summary summariseStudy(const StudyPlan& plan, const std::vector<Measurement>& rows) {
  Summary s;
  const std::vector<std::string> backends = backendsOf(rows);
  if (lightAxis(plan)) {
    for (const std::string& scenario : scenariosOf(plan))
      for (const std::string& backend : backends)
        for (const std::string& technique : plan.techniques) {
          std::vector<double> x, wall, gx, gpu;
          for (const Measurement& m : rows) {
            if (m.status != "ok" || m.scenario != scenario || m.backend != backend || m.technique != technique) continue;
            x.push_back(m.x);
            wall.push_back(m.wall.median);
            if (m.gpu.count) {
              gx.push_back(m.x);
              gpu.push_back(m.gpu.median);
            }
          }
          auto fit = fitLine(x, wall);
          if (!fit) continue;
          SlopeRow r{scenario, backend, technique, fit->slope, 0, false, fit->r2, fit->points};
          if (auto g = fitLine(gx, gpu); g && gx.size() == x.size()) {
            r.gpuSlope = g->slope;
            r.gpu = true;
          }
          s.slopes.push_back(r);
        }
  }
  for (const std::string& backend : backends) {
    if (plan.study == "lights") {
      slopeRatio(s, rows, backend, "small", "forward-multipass", "deferred", "4.9x (thesis 4.2: 0.84 / 0.17 ms)");
      slopeRatio(s, rows, backend, "big", "forward-multipass", "deferred", "2.0x (thesis 4.1: 4.6 / 2.3 ms)");
      slopeRatio(s, rows, backend, "big+shadows", "forward-shadows", "deferred-shadows", "1.4x (thesis 4.1: 10 / 7 ms)");
      for (const char* scenario : {"mixed 1:10", "mixed 1:5"})
        slopeRatio(s, rows, backend, scenario, "forward-shadows", "deferred-shadows", "- (thesis 4.3)");
      for (const char* scenario : {"small", "big"}) slopeRatio(s, rows, backend, scenario, "forward", "deferred", "-");
    } else if (plan.study == "inferred-scale") {
      pointRatio(s, rows, "inferred: full-res L-buffer without DSF / 0.625 L-buffer with DSF, 122 lights", backend, "inferred",
                 "dsf off", 1.0, "inferred", "dsf on", 0.625, "1.28x (inferred paper 6: 32 / 25 ms)");
      pointRatio(s, rows, "inferred: 0.625 L-buffer without DSF / with DSF (cost of the filter)", backend, "inferred", "dsf off", 0.625,
                 "inferred", "dsf on", 0.625, "-");
    } else if (plan.study == "lidr-overlap") {
      // lidr-bits-1x255 is the paper's "1 overlap LIDR"; the other packings for comparison.
      for (const std::string& t : plan.techniques) {
        if (t.rfind("lidr", 0) != 0) continue;
        pointRatio(s, rows, "forward-multipass / " + t + " at 255 lights", backend, "forward-multipass", "small", 255, t, "small", 255,
                   t == "lidr-bits-1x255" ? "6.8x (LIDR paper, illustration 1: 82 / 12 fps)"
                   : t == "lidr-bits-2x255" ? "5.2x (62 / 12 fps)"
                   : t == "lidr-bits"       ? "3.1x (4 overlaps: 37 / 12 fps)"
                                            : "-");
      }
    } else if (plan.study == "tiled") {
      pointRatio(s, rows, "deferred / tiled-deferred at 1024 lights", backend, "deferred", "small", 1024, "tiled-deferred", "small",
                 1024, "- (beyond the seeds)");
      pointRatio(s, rows, "deferred / tiled-forward at 1024 lights", backend, "deferred", "small", 1024, "tiled-forward", "small",
                 1024, "- (beyond the seeds)");
    }
  }
  // Each device's frame time over the first one's, per technique: Vulkan / GL by default, or
  // `--devices`' order. In lockstep (rounds alternated, Measurement::frames paired round by round)
  // the median of the per-round ratios over every point, with their interval; otherwise the
  // geometric mean of the per-point ratios of median frame time (the devices measured one after
  // the other: drift lands on one of them).
  std::vector<std::string> sides = plan.devices;
  if (sides.size() < 2 && std::count(backends.begin(), backends.end(), "gl") && std::count(backends.begin(), backends.end(), "vk"))
    sides = {"gl", "vk"};
  for (size_t k = 1; k < sides.size(); ++k)
    for (const std::string& t : plan.techniques) crossRatio(s, plan, rows, sides[0], sides[k], t);
  return s;
}

bool readBaseline(const std::string& dir, const std::string& study, StudyPlan* plan, std::vector<Measurement>* rows,
                  std::string* error) {
  const std::string path = (fs::path(dir) / (study + ".json")).string();
  std::string text;
  if (!harness::readTextFile(path, &text, error)) return false;
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.contains("plan") || !j.contains("rows")) {
    *error = path + ": not the study file of a parity bench run with its rows";
    return false;
  }
  try {
    *plan = planFromJson(j.at("plan"));
    rows->clear();
    for (const auto& r : j.at("rows")) rows->push_back(measurementFromJson(r));
  } catch (const std::exception& e) {
    *error = path + ": " + e.what();
    return false;
  }
  return true;
}

std::vector<RatioChange> compareRatios(const Summary& before, const Summary& now) {
  std::vector<RatioChange> out;
  for (const RatioRow& n : now.ratios) {
    if (!n.available) continue;
    for (const RatioRow& b : before.ratios) {
      if (b.name != n.name || b.backend != n.backend || !b.available) continue;
      RatioChange c{n.name, n.backend, b, n};
      c.judged = b.intervalHigh > 0 && n.intervalHigh > 0;
      c.moved = c.judged && (n.intervalLow > b.intervalHigh || n.intervalHigh < b.intervalLow);
      out.push_back(c);
    }
  }
  return out;
}

std::string baselineMarkdown(const std::string& dir, const std::vector<RatioChange>& changes) {
  std::string s = "\n## Against the baseline " + dir + "\n\n";
  s += "A ratio moved when its 95% interval in this run and in the baseline do not overlap.\n\n";
  s += "| ratio | backend | baseline | now | |\n|---|---|---|---|---|\n";
  auto cell = [](const RatioRow& r) { return ratioText(r); };
  for (const RatioChange& c : changes)
    s += "| " + c.name + " | " + c.backend + " | " + cell(c.before) + " | " + cell(c.now) + " | " +
         (!c.judged ? "no interval" : c.moved ? "**MOVED**" : "intervals overlap") + " |\n";
  return s;
}

std::string summaryMarkdown(const StudyPlan& plan, const Summary& summary, const std::vector<BackendRun>& backends) {
  std::string s = "# parity bench " + plan.study + "\n\n";
  s += "Scene `" + plan.scene + "`, platform `" + plan.platform + "`, " + std::to_string(plan.width) + "x" +
       std::to_string(plan.height) + ", " +
       (plan.processes > 1 ? std::to_string(plan.processes) + " processes a device, each with " : std::string()) +
       std::to_string(plan.warmup) + " warm-up, " + std::to_string(timestampRoundsPerProcess(plan)) +
       " timestamped (GPU and per-pass times) and " + std::to_string(framesPerProcess(plan)) +
       " measured frames (wall times) per point and technique (techniques interleaved frame by frame" +
       (plan.lockstep ? "; devices in lockstep, round by round" : "; devices one after the other") + "), seed " +
       std::to_string(plan.seed) + ", " +
       "software rasteriser threads " +
       (plan.rasterThreads ? std::to_string(plan.rasterThreads) + " (LP_NUM_THREADS)"
                           : std::string("none, the rasteriser runs on the API's thread (LP_NUM_THREADS=0)")) + ".\n" +
       (plan.lockstep ? "Rounds added past them while a cross ratio's interval was wider than +-5%, within " +
                            fmt(plan.budgetSeconds, "%g") + " s for the run and " + std::to_string(plan.maxRounds) +
                            " rounds a point.\n"
                      : "") +
       "\n";
  for (const BackendRun& b : backends)
    s += "- `" + b.backend + "`: " + (b.ran ? b.device + " (" + fmt(b.seconds, "%.1f") + " s)" : "not run: " + b.device) + "\n";
  for (const auto& [t, why] : plan.skipped) s += "- skipped `" + t + "`: " + why + "\n";
  if (!summary.slopes.empty()) {
    s += "\n## Per-light cost (least squares over the sweep)\n\n| scenario | backend | technique | frame ms/light | GPU ms/light | r² | points |\n|---|---|---|---|---|---|---|\n";
    for (const SlopeRow& r : summary.slopes)
      s += "| " + r.scenario + " | " + r.backend + " | " + r.technique + " | " + fmt(r.wallSlope) + " | " +
           (r.gpu ? fmt(r.gpuSlope) : "-") + " | " + fmt(r.r2, "%.3f") + " | " + std::to_string(r.points) + " |\n";
  }
  if (!summary.ratios.empty()) {
    s += "\n## Ratios\n\n| ratio | backend | measured | seed | how / why not |\n|---|---|---|---|---|\n";
    for (const RatioRow& r : summary.ratios)
      s += "| " + r.name + " | " + r.backend + " | " + ratioText(r) + " | " + r.seed +
           " | " + r.note + " |\n";
  }
  return s;
}

nlohmann::json ratiosJson(const Summary& summary) {
  nlohmann::json out = nlohmann::json::array();
  for (const RatioRow& r : summary.ratios) {
    std::vector<size_t> outliers;
    for (size_t i : r.outlierRounds) outliers.push_back(i + 1);
    const bool stated = r.available && !r.inconclusive;
    out.push_back({{"name", r.name}, {"backend", r.backend}, {"available", r.available}, {"inconclusive", r.inconclusive},
                   {"value", stated ? nlohmann::json(r.value) : nlohmann::json()}, {"median", r.value},
                   {"interval", r.intervalHigh > 0 ? nlohmann::json{r.intervalLow, r.intervalHigh} : nlohmann::json()},
                   {"rounds_kept", r.rounds}, {"outlier_rounds", outliers}, {"process_medians", r.processMedians},
                   {"added_rounds", r.addedRounds},
                   {"rounds_stop", r.roundsStop}, {"seed", r.seed}, {"note", r.note}});
  }
  return out;
}

bool writeStudyOutputs(const std::string& outDir, const StudyPlan& plan, const std::vector<Measurement>& rows,
                       const std::vector<BackendRun>& backends, std::vector<std::string>* written, std::string* error) {
  const fs::path dir(outDir);
  harness::removeStaleTemporaries(outDir, false);  // left by an earlier bench killed mid-write
  auto put = [&](const std::string& name, const std::string& text) {
    if (!harness::writeFileAtomic((dir / name).string(), text, error)) return false;
    written->push_back((dir / name).string());
    return true;
  };
  if (!put(plan.study + ".csv", formatCsv(measurementsCsv(plan, rows)))) return false;
  const Summary summary = summariseStudy(plan, rows);
  const std::string md = summaryMarkdown(plan, summary, backends);
  if (!put(plan.study + "-summary.md", md)) return false;
  CsvTable st;
  st.header = {"kind", "name", "scenario", "backend", "technique", "value", "gpu_value", "r2", "points", "seed", "note"};
  for (const SlopeRow& r : summary.slopes)
    st.rows.push_back({"slope_ms_per_light", "", r.scenario, r.backend, r.technique, fmt(r.wallSlope, "%.6f"),
                       r.gpu ? fmt(r.gpuSlope, "%.6f") : "", fmt(r.r2, "%.4f"), std::to_string(r.points), "", ""});
  for (const RatioRow& r : summary.ratios)
    st.rows.push_back({"ratio", r.name, "", r.backend, "", !r.available ? "not available" : r.inconclusive ? "inconclusive" : fmt(r.value, "%.4f"),
                       "", "", "", r.seed, r.note});
  if (!put(plan.study + "-summary.csv", formatCsv(st))) return false;

  // One plot per scenario and backend: median frame time with the p25-p75 spread.
  nlohmann::json plots = nlohmann::json::array();
  for (const std::string& scenario : scenariosOf(plan)) {
    for (const std::string& backend : backendsOf(rows)) {
      Plot plot;
      plot.title = plan.study + ": " + scenario + " (" + backend + ", " + std::to_string(plan.width) + "x" + std::to_string(plan.height) + ")";
      plot.xLabel = plan.xLabel;
      plot.yLabel = "frame time (ms)";
      for (const std::string& t : plan.techniques) {
        PlotSeries series{t, {}};
        for (const Measurement& m : rows)
          if (m.status == "ok" && m.backend == backend && m.technique == t && m.scenario == scenario)
            series.points.push_back({m.x, m.wall.median, m.wall.p25, m.wall.p75});
        std::sort(series.points.begin(), series.points.end(), [](const PlotPoint& a, const PlotPoint& b) { return a.x < b.x; });
        if (!series.points.empty()) plot.series.push_back(series);
      }
      if (plot.series.empty()) continue;
      const std::string base = plan.study + "-" + slug(scenario) + "-" + backend;
      if (!put(base + ".svg", renderSvg(plot))) return false;
      if (!writePlotPng(plot, (dir / (base + ".png")).string(), error)) return false;
      written->push_back((dir / (base + ".png")).string());
      nlohmann::json curves = nlohmann::json::array();
      for (const PlotSeries& ps : plot.series) curves.push_back(ps.name);
      plots.push_back({{"scenario", scenario}, {"backend", backend}, {"svg", base + ".svg"}, {"png", base + ".png"}, {"curves", curves}});
    }
  }
  nlohmann::json measured = nlohmann::json::array();
  for (const Measurement& m : rows) measured.push_back(toJson(m));
  nlohmann::json meta{{"ratios", ratiosJson(summary)}, {"study", plan.study},       {"csv", plan.study + ".csv"}, {"summary_md", plan.study + "-summary.md"},
                      {"summary_csv", plan.study + "-summary.csv"}, {"plots", plots}, {"summary_text", md},
                      {"lockstep", plan.lockstep}, {"plan", toJson(plan)}, {"rows", measured}};
  if (!put(plan.study + ".json", meta.dump(2))) return false;

  // index.html over every study present in the folder, in the order of studyNames().
  std::string html =
      "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>parity bench</title><style>body{font-family:sans-serif;max-width:1100px;"
      "margin:auto}pre{background:#f4f4f4;padding:8px;overflow-x:auto}img{max-width:100%}</style></head><body>\n<h1>parity bench</h1>\n"
      "<p>Frame time per technique (median, whiskers p25&ndash;p75) against the swept parameter; see docs/BENCH.md. The run report of "
      "<code>parity run</code> lives in its own folder.</p>\n";
  for (const std::string& study : studyNames()) {
    std::string text, err;
    if (!harness::readTextFile((dir / (study + ".json")).string(), &text, &err)) continue;
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded()) continue;
    auto esc = [](const std::string& in) {
      std::string o;
      for (char c : in) o += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
      return o;
    };
    html += "<h2 id=\"" + study + "\">" + study + "</h2>\n<p><a href=\"" + j.value("csv", "") + "\">CSV</a> &middot; <a href=\"" +
            j.value("summary_md", "") + "\">summary (Markdown)</a> &middot; <a href=\"" + j.value("summary_csv", "") +
            "\">summary (CSV)</a></p>\n<pre>" + esc(j.value("summary_text", "")) + "</pre>\n";
    for (const auto& p : j.value("plots", nlohmann::json::array()))
      html += "<figure><a href=\"" + p.value("svg", "") + "\"><img src=\"" + p.value("svg", "") + "\" alt=\"" +
              esc(study + " " + p.value("scenario", "") + " " + p.value("backend", "")) + "\"></a><figcaption><a href=\"" +
              p.value("png", "") + "\">PNG</a></figcaption></figure>\n";
  }
  html += "</body></html>\n";
  return put("index.html", html);
}

}  // namespace parity::bench
