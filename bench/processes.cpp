// Several processes per device (StudyPlan::processes): each one's share of the rounds, and their
// rows merged into one per point and technique.
#include <algorithm>

#include "bench/bench.h"

namespace parity::bench {

namespace {

uint32_t share(uint32_t rounds, uint32_t processes) {
  const uint32_t k = std::max(processes, 1u);
  return std::max((rounds + k - 1) / k, 1u);
}

}  // namespace

uint32_t timestampRoundsPerProcess(const StudyPlan& plan) { return share(kTimestampRounds, plan.processes); }
uint32_t framesPerProcess(const StudyPlan& plan) { return share(plan.frames, plan.processes); }

std::vector<Measurement> mergeProcessRows(const std::vector<std::vector<Measurement>>& perProcess) {
  if (perProcess.size() < 2) return perProcess.empty() ? std::vector<Measurement>{} : perProcess.front();
  std::vector<Measurement> merged;
  for (size_t i = 0; i < perProcess.front().size(); ++i) {
    Measurement m = perProcess.front()[i];
    auto same = [&](const Measurement& o) {
      return o.backend == m.backend && o.technique == m.technique && o.scenario == m.scenario && o.x == m.x &&
             o.params == m.params;
    };
    std::vector<const Measurement*> parts;
    for (const auto& rows : perProcess) {
      auto it = std::find_if(rows.begin(), rows.end(), same);
      if (it != rows.end()) parts.push_back(&*it);
    }
    if (m.status != "ok" || parts.size() != perProcess.size() ||
        std::any_of(parts.begin(), parts.end(), [](const Measurement* p) { return p->status != "ok"; })) {
      for (const Measurement* p : parts)
        if (p->status != "ok") {
          m = *p;
          break;
        }
      if (m.status == "ok") {
        m.status = "failed";
        m.note = "not measured in every process";
      }
      m.frames.clear();
      m.frameStarts.clear();
      merged.push_back(m);
      continue;
    }
    m.frames.clear();
    m.frameStarts.clear();
    std::vector<double> gpu;
    for (const Measurement* p : parts) {
      m.frames.insert(m.frames.end(), p->frames.begin(), p->frames.end());
      m.frameStarts.insert(m.frameStarts.end(), p->frameStarts.begin(), p->frameStarts.end());
      m.processRounds.push_back(p->frames.size());
      if (p->gpu.count) gpu.push_back(p->gpu.median);
      // The worst reason any process's rounds ended with (the parent answers every process alike).
      if (p->roundsStop == "round limit" || (p->roundsStop == "budget" && m.roundsStop != "round limit"))
        m.roundsStop = p->roundsStop;
    }
    m.wall = summarise(m.frames);
    m.gpu = gpu.size() == parts.size() ? summarise(gpu) : Stats{};
    for (auto& [name, ms] : m.passes) {
      std::vector<double> each;
      for (const Measurement* p : parts)
        for (const auto& [n, v] : p->passes)
          if (n == name) each.push_back(v);
      ms = summarise(each).median;
    }
    merged.push_back(m);
  }
  return merged;
}

std::vector<std::vector<double>> framesByProcess(const Measurement& m) {
  if (m.processRounds.empty()) return {m.frames};
  std::vector<std::vector<double>> out;
  size_t at = 0;
  for (size_t n : m.processRounds) {
    const size_t end = std::min(at + n, m.frames.size());
    out.emplace_back(m.frames.begin() + static_cast<std::ptrdiff_t>(at), m.frames.begin() + static_cast<std::ptrdiff_t>(end));
    at = end;
  }
  return out;
}

}  // namespace parity::bench
