// Lockstep of `parity bench`'s children: one child measures at a time, round by round in turn,
// through two FIFOs per child. A child ends each turn with one JSON line (what it measured, what it
// wants next); the parent answers with one byte: 'g' (go on), or for a round past the planned ones
// a stop with its reason: 't' (every ratio within +-5%), 'b' (budget spent), 'l' (round limit).
#pragma once

#include <atomic>
#include <chrono>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench.h"

namespace parity::harness {

// The child's side: opens the FIFOs; every call hands the turn back and waits for the next one.
class ChildTurns : public bench::RoundTurns {
 public:
  ChildTurns(const std::string& go, const std::string& done);
  ~ChildTurns() override;  // says the child has finished
  bool active() const { return go_ >= 0 && done_ >= 0; }
  void beforePoint(size_t group) override;
  Stop beforeRound(size_t group, bool extra, const bench::RoundTimes& previous) override;

 private:
  char exchange(const nlohmann::json& message);
  int go_ = -1, done_ = -1;
};

// The parent's side: hands the turn round until every child has finished or exited (a child that
// died drops out, the others go on alone), and decides whether a point gets another round: while
// some device's frame time over the first device's, per technique, is wider than +-5% round by
// round (bench::ratioSpread over every process's rounds), the point's share of the budget is not
// spent and no technique has the round limit (over all processes).
// Children are ordered by process, then device (plan.devices): child p * devices + d is process p
// of device d; a device's ratio in process p pairs its rounds with the first device's in process p.
class Lockstep {
 public:
  struct Child {
    std::string go, done;
    int goFd = -1, doneFd = -1;
    std::atomic<bool> exited{false};
    bool ended = false;
    std::string pending;      // bytes read past the last line
    nlohmann::json request;   // its last message
    std::map<size_t, size_t> rounds;  // measured rounds per point group
  };
  Lockstep(const std::vector<std::string>& fifoPrefixes, const bench::StudyPlan& plan);
  ~Lockstep();
  bool ok() const;
  Child& child(size_t i) { return children_[i]; }
  void run();

 private:
  bool readMessage(Child& c);
  char decide(size_t group, size_t rounds);

  std::vector<Child> children_;
  double budgetPerGroup_ = 0;
  uint32_t maxRounds_ = 0;
  size_t devices_ = 1;
  // Per point group, per child: "technique|scenario" -> frame time of each round.
  std::map<size_t, std::vector<std::map<std::string, std::vector<double>>>> times_;
  std::map<std::pair<size_t, size_t>, char> decisions_;  // (group, rounds measured) -> answer
  std::map<size_t, std::chrono::steady_clock::time_point> firstExtra_;
};

}  // namespace parity::harness
