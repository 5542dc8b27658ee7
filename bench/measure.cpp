// Measurement of a plan on one device (runs in the `bench-child` process).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <thread>

#include "bench/bench.h"
#include "bench/pass_groups.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "platforms/platform_device.h"
#include "rhi/rhi.h"
#include "scene/scene.h"
#include "scene/scene_gpu.h"
#include "techniques/technique.h"

namespace parity::bench {

namespace {

bool paramConcerns(const Param& param, const std::string& technique) {
  return technique == param.technique || technique.rfind(param.technique + "-", 0) == 0;
}

std::string joinParams(const std::vector<Param>& params) {
  std::string s;
  for (const Param& p : params) s += (s.empty() ? "" : ";") + p.define + "=" + p.value;
  return s;
}

// A scale parameter must show up as a target of the reduced size (floor(size * scale), at least
// 1, inferred.h's rule); a technique that ignores it would otherwise be measured at its default
// under the wrong label.
std::string checkScaleApplied(rhi::Device& device, const techniques::Technique& t, const std::vector<Param>& params,
                              uint32_t width) {
  for (const Param& p : params) {
    if (p.define.find("SCALE") == std::string::npos) continue;
    const double scale = std::atof(p.value.c_str());
    const uint32_t expected = std::max<uint32_t>(1, static_cast<uint32_t>(std::floor(width * scale)));
    for (const techniques::NamedTarget& nt : t.targets())
      if (const rhi::TextureDesc* d = device.describe(nt.texture); d && d->width == expected) return "";
    return p.define + "=" + p.value + " not honoured by the technique (no " + std::to_string(expected) + "-wide target)";
  }
  return "";
}

Measurement baseRow(const StudyPlan& plan, const BenchPoint& p, const std::string& backend, const std::string& technique) {
  Measurement m;
  m.backend = backend;
  m.technique = technique;
  m.scenario = p.scenario;
  m.x = p.x;
  m.bigLights = p.bigLights;
  m.smallLights = p.smallLights;
  std::vector<Param> own;
  for (const Param& q : p.params)
    if (paramConcerns(q, technique)) own.push_back(q);
  m.params = joinParams(own);
  m.note = p.note;
  return m;
}

// The point's scene: big lights placed from the seed, small ones from the next seed (so a mixed
// scene's two classes are not placed at correlated positions), one ambient and one directional
// light always present (scene::Scene).
bool buildScene(const StudyPlan& plan, const BenchPoint& p, scene::Scene* out, std::string* error) {
  scene::SceneParams params;
  params.seed = plan.seed;
  params.lightCount = p.bigLights > 0 ? p.bigLights : p.smallLights;
  params.lightSize = p.bigLights > 0 ? scene::LightSize::Big : scene::LightSize::Small;
  if (!scene::makeScene(plan.scene, params, out, error)) return false;
  if (p.bigLights > 0 && p.smallLights > 0) {
    scene::Scene smalls;
    params.seed = plan.seed + 1;
    params.lightCount = p.smallLights;
    params.lightSize = scene::LightSize::Small;
    if (!scene::makeScene(plan.scene, params, &smalls, error)) return false;
    out->lights.insert(out->lights.end(), smalls.lights.begin(), smalls.lights.end());
  }
  // The big lights come first; with the directional light (on by default) they cast shadows.
  for (uint32_t i = 0; i < p.bigLights && i < out->lights.size(); ++i) out->lights[i].castsShadows = p.shadows;
  out->directionalCastsShadows = true;
  return true;
}

struct Active {
  const BenchPoint* point = nullptr;
  std::string name;
  std::vector<Param> params;
  std::unique_ptr<techniques::Technique> technique;
  std::vector<double> wall, gpu, starts;
  std::vector<std::vector<std::pair<std::string, double>>> passes;
  std::string failure;
};

double elapsedMs(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

std::vector<std::pair<size_t, size_t>> pointGroups(const StudyPlan& plan) {
  std::vector<std::pair<size_t, size_t>> groups;
  for (size_t first = 0; first < plan.points.size();) {
    size_t last = first + 1;
    while (last < plan.points.size() && !plan.points[first].group.empty() && plan.points[last].group == plan.points[first].group)
      ++last;
    groups.emplace_back(first, last);
    first = last;
  }
  return groups;
}

bool parsePlantedSleep(const std::string& spec, PlantedSleep* out, std::string* error) {
  const size_t a = spec.find(':'), b = a == std::string::npos ? a : spec.find(':', a + 1);
  char* end = nullptr;
  PlantedSleep s;
  if (b != std::string::npos) {
    s.device = spec.substr(0, a);
    s.random = spec[a + 1] == '~';
    s.ms = std::strtod(spec.c_str() + a + 1 + (s.random ? 1 : 0), &end);
    const bool msOk = end == spec.c_str() + b && s.ms > 0 && s.ms <= 60000;
    const bool every = spec.size() > b + 1 && spec[b + 1] == '%';
    const unsigned long n = std::strtoul(spec.c_str() + b + 1 + (every ? 1 : 0), &end, 10);
    bool deviceOk = !s.device.empty();
    if (const size_t hash = s.device.find('#'); hash != std::string::npos) {
      char* pend = nullptr;
      const unsigned long process = std::strtoul(s.device.c_str() + hash + 1, &pend, 10);
      deviceOk = hash > 0 && *pend == 0 && pend != s.device.c_str() + hash + 1 && process > 0 && process < 1000;
      s.process = static_cast<uint32_t>(process);
      s.device.resize(hash);
    }
    if (msOk && deviceOk && *end == 0 && n > 0 && n < 1000000) {
      (every ? s.every : s.round) = static_cast<uint32_t>(n);
      *out = s;
      return true;
    }
  }
  *error = "PARITY_BENCH_PLANT_SLEEP '" + spec +
           "' is not DEVICE:MS:ROUND or DEVICE:MS:%K (DEVICE#P for process P only; MS in 0..60000, ~MS for a random "
           "time up to it; ROUND and K from 1)";
  return false;
}

double PlantedSleep::msIn(const std::string& label, uint32_t inProcess, uint32_t measuredRound) const {
  if (ms <= 0 || label != device || (process && inProcess != process) ||
      !(measuredRound == round || (every > 0 && measuredRound % every == 0)))
    return 0;
  if (!random) return ms;
  std::mt19937 draw(measuredRound * 1000 + inProcess);  // the same noise in every run
  return std::uniform_real_distribution<double>(0, ms)(draw);
}

std::vector<Measurement> measurePlan(const StudyPlan& plan, rhi::Device& device, const std::string& backend,
                                     const MeasureHooks& hooks) {
  std::vector<Measurement> rows;
  rhi::TimingDevice timing(device);
  const auto platform = platforms::platformFromName(plan.platform);
  // Techniques draw through the platform's conventions (x360: D3D9 pixel centres), as in `parity run`.
  platforms::PlatformDevice onPlatform(timing, platform.value_or(platforms::PlatformId::Reference), {}, false);
  RoundTurns* turns = hooks.turns;
  const std::vector<std::pair<size_t, size_t>> groups = pointGroups(plan);

  for (size_t gi = 0; gi < groups.size(); ++gi) {
    // Points of one interleave group (consecutive, same scene) are measured together.
    const size_t groupBegin = groups[gi].first, last = groups[gi].second;
    const BenchPoint& p = plan.points[groupBegin];
    if (turns) turns->beforePoint(gi);  // the preparation (shader compilation) of one backend never overlaps a round of the other
    if (!p.unavailable.empty()) {
      for (const std::string& t : techniquesAt(plan, p)) {
        Measurement m = baseRow(plan, p, backend, t);
        m.status = "not available";
        m.note = p.unavailable;
        rows.push_back(m);
      }
      continue;
    }
    scene::Scene scene;
    std::string error;
    if (!buildScene(plan, p, &scene, &error)) {
      for (const std::string& t : techniquesAt(plan, p)) {
        Measurement m = baseRow(plan, p, backend, t);
        m.status = "failed";
        m.note = error;
        rows.push_back(m);
      }
      continue;
    }
    const scene::Camera* camera = scene.camera(plan.camera);
    if (!camera) camera = &scene.cameras.front();
    auto gpu = std::make_unique<scene::SceneGpu>(timing, scene);

    std::vector<Active> active;
    std::vector<Measurement> pointRows;
    for (size_t pi = groupBegin; pi < last; ++pi)
    for (const std::string& t : techniquesAt(plan, plan.points[pi])) {
      const BenchPoint& point = plan.points[pi];
      techniques::RenderSettings settings;
      settings.width = plan.width;
      settings.height = plan.height;
      settings.platform = platform.value_or(platforms::PlatformId::Reference);
      settings.diagnostics = false;  // the techniques' own passes only (LIDR's overlap count is the harness's)
      std::vector<Param> own;
      for (const Param& q : point.params)
        if (paramConcerns(q, t)) {
          settings.shaderOptions.defines.push_back({q.define, q.value});
          own.push_back(q);
        }
      Active a;
      a.point = &point;
      a.params = own;
      a.name = t;
      a.technique = techniques::createTechnique(t);
      try {
        if (!a.technique) throw techniques::TechniqueError("not registered");
        a.technique->prepare(onPlatform, settings);
      } catch (const std::exception& e) {
        Measurement m = baseRow(plan, point, backend, t);
        m.status = "failed";
        m.note = std::string("prepare: ") + e.what();
        pointRows.push_back(m);
        continue;
      }
      active.push_back(std::move(a));
    }

    // Techniques interleaved frame by frame, the first one rotating, so that slow drift of the
    // machine (thermal state, other load) lands on every technique alike.
    // In lockstep the parent may add rounds past the planned ones, until it says stop.
    // Rounds before `measured` are not sent to the parent: it counts and pairs measured rounds only.
    const uint32_t timestamped = plan.warmup, measured = plan.warmup + timestampRoundsPerProcess(plan);
    const uint32_t total = measured + framesPerProcess(plan);
    RoundTimes previous;
    RoundTurns::Stop stop = RoundTurns::Stop::None;
    for (uint32_t f = 0; turns || f < total; ++f) {
      if (turns) {
        stop = turns->beforeRound(gi, f >= total, previous);
        if (stop != RoundTurns::Stop::None) break;
      }
      previous.clear();
      const uint32_t measuredRound = f + 1 - measured;  // 1-based, when f >= measured
      for (size_t i = 0; i < active.size(); ++i) {
        Active& a = active[(f + i) % active.size()];
        if (!a.failure.empty()) continue;
        try {
          const bool timestamps = f >= timestamped && f < measured;
          if (timestamps)
            timing.beginFrame();
          else
            timing.beginUntimedFrame();
          auto t0 = std::chrono::steady_clock::now();
          a.technique->render(onPlatform, *gpu, *camera);
          if (const double sleep = f >= measured ? hooks.sleep.msIn(backend, hooks.process, measuredRound) : 0; sleep > 0)
            std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(sleep));
          timing.submit();
          auto t1 = std::chrono::steady_clock::now();
          if (f == 0) {
            a.failure = checkScaleApplied(timing, *a.technique, a.params, plan.width);
            if (!a.failure.empty()) continue;
          }
          if (timestamps) {
            if (const double g = timing.frameGpuMs(); g >= 0) a.gpu.push_back(g);
            a.passes.push_back(groupPassTimes(timing.passTimings()));
          }
          if (f < measured) continue;
          a.wall.push_back(elapsedMs(t0, t1));
          a.starts.push_back(std::chrono::duration<double, std::milli>(t0.time_since_epoch()).count());
          previous.emplace_back(a.name + "|" + a.point->scenario, a.wall.back());
        } catch (const std::exception& e) {
          a.failure = std::string("render: ") + e.what();
        }
      }
    }
    const char* stopText = stop == RoundTurns::Stop::Tight ? "tight" : stop == RoundTurns::Stop::Budget ? "budget"
                         : stop == RoundTurns::Stop::RoundLimit ? "round limit" : "";

    std::string line = backend + " " + plan.study + " " + (p.group.empty() ? p.scenario : p.group) + " x=" +
                       std::to_string(p.x).substr(0, 6) + ":";
    for (Active& a : active) {
      Measurement m = baseRow(plan, *a.point, backend, a.name);
      m.roundsStop = stopText;
      if (a.failure.find("not honoured") != std::string::npos) {
        m.status = "not available";
        m.note = a.failure;
      } else if (!a.failure.empty()) {
        m.status = "failed";
        m.note = a.failure;
      } else {
        m.status = "ok";
        m.wall = summarise(a.wall);
        m.frames = a.wall;
        m.frameStarts = a.starts;
        m.gpu = summarise(a.gpu);
        // Median per pass group over the frames, in the order the passes first appear.
        std::vector<std::string> order;
        std::map<std::string, std::vector<double>> byName;
        for (const auto& frame : a.passes)
          for (const auto& [name, ms] : frame) {
            if (!byName.count(name)) order.push_back(name);
            byName[name].push_back(ms);
          }
        for (const std::string& name : order) m.passes.emplace_back(name, summarise(byName[name]).median);
        char buf[64];
        std::snprintf(buf, sizeof(buf), " %s%s %.2f ms", a.name.c_str(), last - groupBegin > 1 ? (" (" + a.point->scenario + ")").c_str() : "",
                      m.wall.median);
        line += buf;
      }
      pointRows.push_back(m);
      a.technique->release(onPlatform);
    }
    timing.submit();
    gpu.reset();
    // Keep the plan's order: point, then technique.
    for (size_t pi = groupBegin; pi < last; ++pi)
      for (const std::string& t : techniquesAt(plan, plan.points[pi]))
        for (const Measurement& m : pointRows)
          if (m.technique == t && m.scenario == plan.points[pi].scenario && m.x == plan.points[pi].x) rows.push_back(m);
    if (hooks.progress) hooks.progress(line);
  }
  return rows;
}

std::vector<Measurement> unmeasuredRows(const StudyPlan& plan, const std::string& backend) {
  std::vector<Measurement> rows;
  for (const auto& [name, reason] : plan.skipped) {
    Measurement m;
    m.backend = backend;
    m.technique = name;
    m.scenario = "*";
    m.status = "skipped";
    m.note = reason;
    rows.push_back(m);
  }
  return rows;
}

// --- JSON (plan to the child, measurements back) ---

nlohmann::json toJson(const StudyPlan& p) {
  nlohmann::json j{{"study", p.study}, {"x_label", p.xLabel}, {"scene", p.scene}, {"camera", p.camera},
                   {"platform", p.platform}, {"width", p.width}, {"height", p.height}, {"frames", p.frames},
                   {"warmup", p.warmup}, {"seed", p.seed}, {"techniques", p.techniques}, {"lockstep", p.lockstep},
                   {"budget_seconds", p.budgetSeconds}, {"max_rounds", p.maxRounds}, {"devices", p.devices},
                   {"raster_threads", p.rasterThreads}, {"processes", p.processes}};
  j["skipped"] = nlohmann::json::array();
  for (const auto& [t, r] : p.skipped) j["skipped"].push_back({t, r});
  j["points"] = nlohmann::json::array();
  for (const BenchPoint& b : p.points) {
    nlohmann::json params = nlohmann::json::array();
    for (const Param& q : b.params) params.push_back({q.technique, q.define, q.value});
    j["points"].push_back({{"scenario", b.scenario}, {"x", b.x}, {"big", b.bigLights}, {"small", b.smallLights},
                           {"params", params}, {"shadows", b.shadows}, {"unavailable", b.unavailable}, {"note", b.note},
                           {"group", b.group}});
  }
  return j;
}

StudyPlan planFromJson(const nlohmann::json& j) {
  StudyPlan p;
  p.study = j.at("study");
  p.xLabel = j.at("x_label");
  p.scene = j.at("scene");
  p.camera = j.at("camera");
  p.platform = j.at("platform");
  p.width = j.at("width");
  p.height = j.at("height");
  p.frames = j.at("frames");
  p.warmup = j.at("warmup");
  p.seed = j.at("seed");
  p.techniques = j.at("techniques").get<std::vector<std::string>>();
  p.lockstep = j.value("lockstep", false);
  p.budgetSeconds = j.value("budget_seconds", 0.0);
  p.maxRounds = j.value("max_rounds", 0u);
  p.devices = j.value("devices", std::vector<std::string>{});
  p.rasterThreads = j.value("raster_threads", 0u);
  p.processes = j.value("processes", 1u);
  for (const auto& s : j.at("skipped")) p.skipped.push_back({s.at(0), s.at(1)});
  for (const auto& b : j.at("points")) {
    BenchPoint q;
    q.scenario = b.at("scenario");
    q.x = b.at("x");
    q.bigLights = b.at("big");
    q.smallLights = b.at("small");
    for (const auto& kv : b.at("params")) q.params.push_back({kv.at(0), kv.at(1), kv.at(2)});
    q.shadows = b.at("shadows");
    q.unavailable = b.at("unavailable");
    q.note = b.at("note");
    q.group = b.value("group", "");
    p.points.push_back(q);
  }
  return p;
}

namespace {
nlohmann::json statsJson(const Stats& s) {
  return {{"n", s.count}, {"median", s.median}, {"p25", s.p25}, {"p75", s.p75}, {"min", s.min}, {"max", s.max}};
}
Stats statsFrom(const nlohmann::json& j) {
  Stats s;
  s.count = j.at("n");
  s.median = j.at("median");
  s.p25 = j.at("p25");
  s.p75 = j.at("p75");
  s.min = j.at("min");
  s.max = j.at("max");
  return s;
}
}  // namespace

nlohmann::json toJson(const Measurement& m) {
  nlohmann::json passes = nlohmann::json::array();
  for (const auto& [n, v] : m.passes) passes.push_back({n, v});
  return {{"backend", m.backend}, {"technique", m.technique}, {"scenario", m.scenario}, {"status", m.status},
          {"x", m.x},         {"big", m.bigLights},         {"small", m.smallLights},   {"params", m.params},
          {"wall", statsJson(m.wall)}, {"gpu", statsJson(m.gpu)}, {"passes", passes}, {"frames", m.frames}, {"frame_starts", m.frameStarts},
          {"process_rounds", m.processRounds},
          {"rounds_stop", m.roundsStop}, {"note", m.note}};
}

Measurement measurementFromJson(const nlohmann::json& j) {
  Measurement m;
  m.backend = j.at("backend");
  m.technique = j.at("technique");
  m.scenario = j.at("scenario");
  m.status = j.at("status");
  m.x = j.at("x");
  m.bigLights = j.at("big");
  m.smallLights = j.at("small");
  m.params = j.at("params");
  m.wall = statsFrom(j.at("wall"));
  m.gpu = statsFrom(j.at("gpu"));
  for (const auto& p : j.at("passes")) m.passes.emplace_back(p.at(0), p.at(1));
  if (j.contains("frames")) m.frames = j.at("frames").get<std::vector<double>>();
  if (j.contains("frame_starts")) m.frameStarts = j.at("frame_starts").get<std::vector<double>>();
  m.processRounds = j.value("process_rounds", std::vector<size_t>{});
  m.roundsStop = j.value("rounds_stop", "");
  m.note = j.at("note");
  return m;
}

}  // namespace parity::bench
