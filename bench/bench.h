// `parity bench`: the seeds' performance studies (thesis chapter 4 light sweeps, the inferred
// paper's L-buffer scale trade-off, LIDR overlap counts, tiled shading at many lights) as plans
// of measured points, measured per backend in a child process, and reported as CSV, plots, a
// summary of per-light cost slopes and ratios, and an HTML page (docs/BENCH.md).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/stats.h"

namespace parity::rhi {
class Device;
}

namespace parity::bench {

// A technique parameter, passed the way the technique documents it: a shader define of
// RenderSettings::shaderOptions (e.g. inferred's INFERRED_LBUFFER_SCALE=<float>). `technique`
// names the techniques it concerns: that name and every "name-*".
struct Param {
  std::string technique, define, value;
};

// One measured configuration of the scene and the technique parameters; the plan's techniques
// that fit the point (techniquesAt) are measured at it.
struct BenchPoint {
  std::string scenario;        // "small", "big", "big+shadows", "mixed 1:10", "dsf on", ...
  double x = 0;                // abscissa of the plot: light count, L-buffer scale, overlaps
  uint32_t bigLights = 0, smallLights = 0;
  std::vector<Param> params;   // technique parameters of this point
  // The big lights and the directional light cast shadows: only the techniques that render
  // shadows (TechniqueEntry::rendersShadows) are measured here, and only here.
  bool shadows = false;
  std::string unavailable;     // not measured, with this reason
  std::string note;            // recorded next to the result (e.g. "big lights unshadowed")
  // Consecutive points with the same non-empty group share a scene and are measured
  // interleaved with each other, like techniques (variants compared directly: DSF on and off).
  std::string group;
};

struct StudyPlan {
  std::string study;
  std::string xLabel = "lights";
  std::string scene = "default", camera = "default", platform = "reference";
  uint32_t width = 320, height = 180, frames = 10, warmup = 2, seed = 1;
  std::vector<std::string> techniques;                       // registered: measured
  std::vector<std::pair<std::string, std::string>> skipped;  // technique, reason
  std::vector<BenchPoint> points;
  bool lockstep = false;  // the backends' children alternated round by round (parity bench's default)
  // In lockstep, rounds are added to a point until every ratio between the children is within
  // +-5% (kRatioTolerance), its share of this many seconds (budget / point groups) is spent, or a
  // technique has maxRounds measured rounds.
  double budgetSeconds = 0;
  uint32_t maxRounds = 0;
  // Threads of the software rasterisers (llvmpipe, lavapipe; LP_NUM_THREADS) in every child; 0: the
  // rasteriser runs on the API's thread. Handing a frame to rasteriser threads and waiting for
  // them made per-round ratios spread two to three times as wide on a 2-core machine, and how much a
  // frame overlaps with them depends on the machine's cores (docs/BENCH.md, "The rasteriser on the
  // API's thread"). Other drivers ignore it.
  uint32_t rasterThreads = 0;
  // Processes each device is measured in, side by side (in lockstep, round by round with the
  // others'): each one renders the warm-up, its share of the timestamped and measured rounds
  // (roundsPerProcess), and added rounds. A process can run slower or faster as a whole, so a
  // ratio's interval reaches every process's own median (stats.h, ProcessSpread).
  uint32_t processes = 1;
  // The children's labels in order (backends "gl", "vk" or device names "gl-zink", ...): rows are
  // labelled by them, and the cross ratios are each one's frame time over the first one's.
  std::vector<std::string> devices;
};

// What the user asked for (`parity bench STUDY ...`).
struct StudyOptions {
  std::string study;
  std::vector<std::string> techniques;  // empty: the study's defaults
  std::string size;                     // empty: the study's default (quick or full)
  int frames = -1, warmup = -1;         // negative: the study's default
  uint32_t seed = 1;
  std::string scene = "default";
  std::string platform = "reference";
  bool quick = false;
  // Overrides the swept light counts (lights, tiled), the mixed scenarios' multipliers k <= 10
  // (lights), or the fixed light count (first value: inferred-scale, lidr-overlap).
  std::vector<uint32_t> lightCounts;
  double budgetSeconds = -1;  // negative: 60
  // Negative: LP_NUM_THREADS when it is set, else 0.
  int rasterThreads = -1;
  int maxRounds = -1;         // negative: 200
  int processes = -1;         // negative: 4, or fewer when there are fewer measured frames
};

const std::vector<std::string>& studyNames();
// The plan's techniques measured at point p: those that render shadows at a shadowed point, the
// others elsewhere (forward-shadows and deferred-shadows are the thesis's shadowed renderers).
std::vector<std::string> techniquesAt(const StudyPlan& plan, const BenchPoint& p);
// "a,b,,c" -> {a, b, c}.
std::vector<std::string> splitList(const std::string& s);
// False with a one-line reason for an unknown study, technique list or size.
bool makeStudyPlan(const StudyOptions& options, StudyPlan* plan, std::string* error);

// One (point, technique, backend) result.
struct Measurement {
  std::string backend, technique, scenario, status;  // status: "ok", "skipped", "not available", "failed"
  double x = 0;
  uint32_t bigLights = 0, smallLights = 0;
  std::string params;  // "name=value;..." of the point's parameters that concern this technique
  Stats wall, gpu;     // milliseconds per frame; gpu.count 0 without timestamps
  std::vector<std::pair<std::string, double>> passes;  // median GPU ms per pass group
  std::vector<double> frames;  // wall ms of each measured round, in order (lockstep ratios pair them)
  // The rounds of `frames` each process measured, in order (StudyPlan::processes): frames holds
  // the first process's rounds, then the second's. Empty: one process.
  std::vector<size_t> processRounds;
  // When each of those frames started, ms of the system's monotonic clock (comparable across
  // processes: it shows which backend's round ran when).
  std::vector<double> frameStarts;
  // Why its point's rounds ended after the planned ones (lockstep only, RoundTurns::Stop): "tight",
  // "budget" or "round limit"; empty when no round could be added.
  std::string roundsStop;
  std::string note;
};

// Consecutive points measured together ([first, last) of plan.points): one interleave group, or
// a single point (BenchPoint::group).
std::vector<std::pair<size_t, size_t>> pointGroups(const StudyPlan& plan);

// Frame times of one round of a point: "technique|scenario" -> ms.
using RoundTimes = std::vector<std::pair<std::string, double>>;

// The lockstep's side of a child (parity bench's FIFOs): every call hands the previous turn back
// with what it measured and waits for the next turn.
class RoundTurns {
 public:
  enum class Stop { None, Tight, Budget, RoundLimit };
  virtual ~RoundTurns() = default;
  // Before the preparation of point group `group`.
  virtual void beforePoint(size_t group) = 0;
  // Before a round of the group; `previous` is the last round's times (empty after a warm-up
  // round or the preparation). Past the planned rounds (`extra`) the answer may be a stop: the
  // point's rounds end, and the reason is recorded (Measurement::roundsStop).
  virtual Stop beforeRound(size_t group, bool extra, const RoundTimes& previous) = 0;
};

// A hook for tests of the statistics: sleep inside the timed frame of every technique in the
// given measured rounds (1-based) of the child labelled `device`: a planted pause, or noise.
struct PlantedSleep {
  std::string device;
  uint32_t process = 0;  // that process of the device only (1-based, "DEVICE#P"); 0: every one
  double ms = 0;
  bool random = false;  // a duration drawn from 0..ms for each round (noise) instead of ms
  uint32_t round = 0;   // that round only
  uint32_t every = 0;   // or every k-th round
  // The sleep in that round of that child, ms (0: none).
  double msIn(const std::string& label, uint32_t process, uint32_t measuredRound) const;
};
// "DEVICE:MS:ROUND" or "DEVICE:MS:%K", MS optionally "~MS" (random up to MS), DEVICE optionally
// "DEVICE#P" (process P only): the PARITY_BENCH_PLANT_SLEEP variable. Rounds count within each
// process. False with a one-line reason.
bool parsePlantedSleep(const std::string& spec, PlantedSleep* out, std::string* error);

// Rounds per point, after the warm-up and before the measured ones, whose frames write the
// timestamps of GPU and per-pass times. Measured rounds write none: on llvmpipe and lavapipe each
// timestamp finishes the queued work, which made LIDR's frames at 160x90 about a third longer
// and their ratios noisier (docs/BENCH.md, "Wall times without timestamps").
constexpr uint32_t kTimestampRounds = 3;
// One process's share of the plan's timestamped and measured rounds (rounded up; a process
// measures at least one of each).
uint32_t timestampRoundsPerProcess(const StudyPlan& plan);
uint32_t framesPerProcess(const StudyPlan& plan);
// The rows of every process of one device (in process order) as one row per point and
// technique: frames concatenated with processRounds; GPU and per-pass times the median of the
// processes' medians. A technique that did not measure in every process keeps the first failure.
std::vector<Measurement> mergeProcessRows(const std::vector<std::vector<Measurement>>& perProcess);
// A merged row's frames split again by process (processRounds); one vector when it has none.
std::vector<std::vector<double>> framesByProcess(const Measurement& m);

// Measures the plan on one device in this process (the `bench-child` command), its rows labelled
// `label`: for every point, builds the scene, prepares every technique, then renders warm-up,
// timestamped (kTimestampRounds) and measured frames with the techniques interleaved frame by
// frame (the first technique rotating), so drift of the machine affects every technique alike.
// `progress` gets one line per point.
// `turns`, when set, is asked before each point's preparation and before each round (and for
// rounds past the planned ones): the parent alternates the children round by round with it, so
// that each round of one device sits next to the same round of the others (lockstep).
struct MeasureHooks {
  std::function<void(const std::string&)> progress;
  RoundTurns* turns = nullptr;
  PlantedSleep sleep;
  uint32_t process = 1;  // which of the device's processes this is (1-based; PlantedSleep::process)
};
std::vector<Measurement> measurePlan(const StudyPlan& plan, rhi::Device& device, const std::string& label,
                                     const MeasureHooks& hooks);

nlohmann::json toJson(const StudyPlan& plan);
StudyPlan planFromJson(const nlohmann::json& j);
nlohmann::json toJson(const Measurement& m);
Measurement measurementFromJson(const nlohmann::json& j);

// Rows for the skipped techniques and unavailable points of the plan (no child needed).
std::vector<Measurement> unmeasuredRows(const StudyPlan& plan, const std::string& backend);

}  // namespace parity::bench
