// The studies' plans: which techniques, scenes and parameters each one measures.
#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "bench/bench.h"
#include "platforms/common/platform.h"
#include "techniques/technique.h"

namespace parity::bench {

namespace {

// Thesis §3.3: "increments of one light for [1-10] range, in increments of two for (10-20]
// range and increments of ten for (20-100] range".
std::vector<uint32_t> thesisLightCounts() {
  std::vector<uint32_t> n;
  for (uint32_t i = 1; i <= 10; ++i) n.push_back(i);
  for (uint32_t i = 12; i <= 20; i += 2) n.push_back(i);
  for (uint32_t i = 30; i <= 100; i += 10) n.push_back(i);
  return n;
}

bool registered(const std::string& name) {
  for (const auto& e : techniques::techniqueRegistry())
    if (e.name == name) return true;
  return false;
}

// Expands "prefix-*" to the registered techniques that start with "prefix-", keeps the order.
void resolveTechniques(const std::vector<std::string>& wanted, StudyPlan* plan) {
  for (const std::string& w : wanted) {
    if (w.size() > 1 && w.back() == '*') {
      const std::string prefix = w.substr(0, w.size() - 1);
      bool any = false;
      for (const auto& e : techniques::techniqueRegistry())
        if (e.name.rfind(prefix, 0) == 0 && std::find(plan->techniques.begin(), plan->techniques.end(), e.name) == plan->techniques.end()) {
          plan->techniques.push_back(e.name);
          any = true;
        }
      if (!any) plan->skipped.push_back({w, "no technique named " + w + " is registered in this build"});
    } else if (registered(w)) {
      if (std::find(plan->techniques.begin(), plan->techniques.end(), w) == plan->techniques.end()) plan->techniques.push_back(w);
    } else {
      plan->skipped.push_back({w, "not registered in this build (see `parity list`)"});
    }
  }
}

BenchPoint lightPoint(const std::string& scenario, uint32_t big, uint32_t small) {
  BenchPoint p;
  p.scenario = scenario;
  p.bigLights = big;
  p.smallLights = small;
  p.x = big + small;
  return p;
}

void planLights(const StudyOptions& o, StudyPlan* plan) {
  const std::vector<uint32_t> counts =
      !o.lightCounts.empty() ? o.lightCounts : o.quick ? std::vector<uint32_t>{1, 5, 10, 20, 40, 70, 100} : thesisLightCounts();
  std::vector<uint32_t> mixedSteps;
  if (!o.lightCounts.empty()) {
    for (uint32_t k : o.lightCounts)
      if (k <= 10) mixedSteps.push_back(k);
  } else if (o.quick) {
    mixedSteps = {1, 4, 10};
  } else {
    for (uint32_t k = 1; k <= 10; ++k) mixedSteps.push_back(k);
  }
  for (uint32_t n : counts) plan->points.push_back(lightPoint("small", 0, n));
  for (uint32_t n : counts) plan->points.push_back(lightPoint("big", n, 0));
  for (uint32_t n : counts) {
    BenchPoint p = lightPoint("big+shadows", n, 0);
    p.shadows = true;
    plan->points.push_back(p);
  }
  // Thesis §4.3: k big shadow-casting lights with 10k (or 5k) small ones, k = 1..10.
  for (uint32_t ratio : {10u, 5u}) {
    for (uint32_t k : mixedSteps) {
      BenchPoint p = lightPoint("mixed 1:" + std::to_string(ratio), k, k * ratio);
      p.shadows = true;
      plan->points.push_back(p);
    }
  }
}

// Inferred paper §6, figure 9: 122 lights, 800x450 L-buffer with DSF against 1280x720 without.
void planInferredScale(const StudyOptions& o, StudyPlan* plan) {
  plan->xLabel = "L-buffer scale";
  const std::vector<double> scales =
      o.quick ? std::vector<double>{0.25, 0.625, 1.0} : std::vector<double>{0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0};
  const uint32_t lights = o.lightCounts.empty() ? 122 : o.lightCounts.front();
  for (double s : scales) {
    for (const char* dsf : {"on", "off"}) {
      BenchPoint p = lightPoint(std::string("dsf ") + dsf, 0, lights);
      p.x = s;
      char value[32];
      std::snprintf(value, sizeof(value), "%g", s);
      // techniques/inferred/inferred.h: the scale and the plain-bilinear switch are defines.
      p.params = {{"inferred", "INFERRED_LBUFFER_SCALE", value}};
      if (std::string(dsf) == "off") p.params.push_back({"inferred", "INFERRED_PLAIN_BILINEAR", "1"});
      p.group = std::string("scale ") + value;
      plan->points.push_back(p);
    }
  }
}

// LIDR paper, illustration 1: 255 lights, 1 / 2 / 4 overlaps against multi-pass forward. The
// overlap count of the bit-shifting packing is part of the technique's name (lidr-bits-1x255,
// -2x255, lidr-bits = 4x255, -8x255), so every lidr-* technique is one curve.
void planLidrOverlap(const StudyOptions& o, StudyPlan* plan) {
  const std::vector<uint32_t> counts =
      !o.lightCounts.empty() ? o.lightCounts : o.quick ? std::vector<uint32_t>{255} : std::vector<uint32_t>{15, 64, 128, 255};
  for (uint32_t n : counts) plan->points.push_back(lightPoint("small", 0, n));
}

void planTiled(const StudyOptions& o, StudyPlan* plan) {
  const std::vector<uint32_t> counts =
      !o.lightCounts.empty() ? o.lightCounts : o.quick ? std::vector<uint32_t>{64, 256, 1024} : std::vector<uint32_t>{64, 128, 256, 512, 1024, 2048, 4096};
  for (uint32_t n : counts) plan->points.push_back(lightPoint("small", 0, n));
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= s.size()) {
    size_t end = s.find(sep, start);
    if (end == std::string::npos) end = s.size();
    std::string item = s.substr(start, end - start);
    if (!item.empty()) out.push_back(item);
    start = end + 1;
  }
  return out;
}

bool parseSizeText(const std::string& text, uint32_t* w, uint32_t* h) {
  unsigned a = 0, b = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%u%c%u%c", &a, &x, &b, &extra) != 3 || (x != 'x' && x != 'X')) return false;
  if (a == 0 || b == 0 || a > 16384 || b > 16384) return false;
  *w = a;
  *h = b;
  return true;
}

}  // namespace

const std::vector<std::string>& studyNames() {
  static const std::vector<std::string> names = {"lights", "inferred-scale", "lidr-overlap", "tiled"};
  return names;
}

bool makeStudyPlan(const StudyOptions& o, StudyPlan* plan, std::string* error) {
  *plan = StudyPlan{};
  plan->study = o.study;
  plan->scene = o.scene;
  plan->platform = o.platform;
  plan->seed = o.seed;
  if (!platforms::platformFromName(o.platform)) {
    *error = "unknown platform '" + o.platform + "' (known: reference, dx10, ps3, x360)";
    return false;
  }
  std::vector<std::string> defaults;
  if (o.study == "lights") {
    // Thesis: multi-pass forward against deferred (with shadows: forward-shadows against
    // deferred-shadows, the shadowed scenarios' only techniques); the others for comparison.
    defaults = o.quick ? std::vector<std::string>{"forward-multipass", "forward", "deferred", "light-prepass",
                                                  "forward-shadows", "deferred-shadows"}
                       : std::vector<std::string>{"forward-multipass", "forward", "deferred", "light-prepass",
                                                  "light-prepass-4ch", "inferred", "forward-shadows", "deferred-shadows"};
    planLights(o, plan);
  } else if (o.study == "inferred-scale") {
    defaults = {"inferred"};
    planInferredScale(o, plan);
  } else if (o.study == "lidr-overlap") {
    defaults = {"forward-multipass", "lidr-*"};
    planLidrOverlap(o, plan);
  } else if (o.study == "tiled") {
    defaults = {"deferred", "tiled-deferred", "tiled-forward"};
    planTiled(o, plan);
  } else {
    *error = "unknown study '" + o.study + "' (known: lights, inferred-scale, lidr-overlap, tiled)";
    return false;
  }
  resolveTechniques(o.techniques.empty() ? defaults : o.techniques, plan);
  // The software rasterisers are slow: the quick sweep renders a quarter of the pixels.
  const std::string size = !o.size.empty() ? o.size : o.quick ? "160x90" : "320x180";
  if (!parseSizeText(size, &plan->width, &plan->height)) {
    *error = "--size '" + size + "' is not WIDTHxHEIGHT with sides 1..16384";
    return false;
  }
  if (o.frames == 0) {
    *error = "--frames must be at least 1";
    return false;
  }
  // 12 rounds: the fewest whose 95% interval of the median leaves out the two extremes of each end
  // (the 3rd to the 10th; bench/stats.h), so that a ratio can be stated at all.
  plan->frames = o.frames > 0 ? static_cast<uint32_t>(o.frames) : 12;
  plan->warmup = o.warmup >= 0 ? static_cast<uint32_t>(o.warmup) : 1;
  // Added rounds (lockstep): a run's budget shared by its points.
  plan->budgetSeconds = o.budgetSeconds >= 0 ? o.budgetSeconds : 60;
  if (o.rasterThreads >= 0) {
    plan->rasterThreads = static_cast<uint32_t>(o.rasterThreads);
  } else if (const char* set = std::getenv("LP_NUM_THREADS"); set && *set) {
    plan->rasterThreads = static_cast<uint32_t>(std::max(0, std::atoi(set)));
  } else {
    plan->rasterThreads = 0;
  }
  // 4 processes a device: their medians' range covers the median process with probability 87.5%
  // (stats.h, ProcessSpread); each measures at least one round.
  if (o.processes == 0 || (o.processes > 0 && static_cast<uint32_t>(o.processes) > plan->frames)) {
    *error = "--processes " + std::to_string(o.processes) + " must be 1.." + std::to_string(plan->frames) +
             " (each process measures at least one of the --frames rounds)";
    return false;
  }
  plan->processes = o.processes > 0 ? static_cast<uint32_t>(o.processes) : std::min<uint32_t>(4, plan->frames);
  plan->maxRounds = o.maxRounds >= 0 ? static_cast<uint32_t>(o.maxRounds) : std::max<uint32_t>(200, plan->frames);
  if (plan->maxRounds < plan->frames) {
    *error = "--max-rounds " + std::to_string(plan->maxRounds) + " is fewer than the " + std::to_string(plan->frames) +
             " planned rounds (--frames)";
    return false;
  }
  return true;
}

std::vector<std::string> splitList(const std::string& s) { return split(s, ','); }

std::vector<std::string> techniquesAt(const StudyPlan& plan, const BenchPoint& p) {
  std::vector<std::string> out;
  for (const std::string& t : plan.techniques)
    for (const techniques::TechniqueEntry& e : techniques::techniqueRegistry())
      if (e.name == t && e.rendersShadows == p.shadows) out.push_back(t);
  return out;
}

}  // namespace parity::bench
