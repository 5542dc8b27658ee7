#include "harness/cli/bench_lockstep.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>

#include "bench/report.h"

namespace parity::harness {

namespace {

void writeAll(int fd, const std::string& text) {
  for (size_t at = 0; at < text.size();) {
    const ssize_t n = ::write(fd, text.data() + at, text.size() - at);
    if (n <= 0) return;
    at += static_cast<size_t>(n);
  }
}

}  // namespace

ChildTurns::ChildTurns(const std::string& go, const std::string& done) {
  if (go.empty()) return;
  go_ = ::open(go.c_str(), O_RDONLY | O_CLOEXEC);
  done_ = ::open(done.c_str(), O_WRONLY | O_CLOEXEC);
}

ChildTurns::~ChildTurns() {
  if (done_ >= 0) writeAll(done_, nlohmann::json{{"next", "end"}}.dump() + "\n");
  if (go_ >= 0) ::close(go_);
  if (done_ >= 0) ::close(done_);
}

char ChildTurns::exchange(const nlohmann::json& message) {
  if (!active()) return 'g';
  writeAll(done_, message.dump() + "\n");
  char c = 'g';
  (void)!::read(go_, &c, 1);
  return c;
}

void ChildTurns::beforePoint(size_t group) { exchange({{"next", "prepare"}, {"group", group}}); }

bench::RoundTurns::Stop ChildTurns::beforeRound(size_t group, bool extra, const bench::RoundTimes& previous) {
  nlohmann::json m{{"next", extra ? "extra" : "round"}, {"group", group}};
  if (!previous.empty()) m["times"] = previous;
  switch (exchange(m)) {
    case 't': return Stop::Tight;
    case 'b': return Stop::Budget;
    case 'l': return Stop::RoundLimit;
    default: return Stop::None;
  }
}

Lockstep::Lockstep(const std::vector<std::string>& fifoPrefixes, const bench::StudyPlan& plan)
    : children_(fifoPrefixes.size()), maxRounds_(plan.maxRounds), devices_(std::max<size_t>(plan.devices.size(), 1)) {
  const size_t groups = bench::pointGroups(plan).size();
  budgetPerGroup_ = groups ? plan.budgetSeconds / static_cast<double>(groups) : 0;
  for (size_t i = 0; i < fifoPrefixes.size(); ++i) {
    Child& c = children_[i];
    c.go = fifoPrefixes[i] + "-go";
    c.done = fifoPrefixes[i] + "-done";
    ::unlink(c.go.c_str());
    ::unlink(c.done.c_str());
    // Read-write opens of a FIFO do not wait for the other end (Linux), and keep it open.
    if (::mkfifo(c.go.c_str(), 0600) == 0 && ::mkfifo(c.done.c_str(), 0600) == 0) {
      c.goFd = ::open(c.go.c_str(), O_RDWR | O_CLOEXEC);
      c.doneFd = ::open(c.done.c_str(), O_RDWR | O_CLOEXEC);
    }
  }
}

Lockstep::~Lockstep() {
  for (Child& c : children_) {
    if (c.goFd >= 0) ::close(c.goFd);
    if (c.doneFd >= 0) ::close(c.doneFd);
    ::unlink(c.go.c_str());
    ::unlink(c.done.c_str());
  }
}

bool Lockstep::ok() const {
  for (const Child& c : children_)
    if (c.goFd < 0 || c.doneFd < 0) return false;
  return true;
}

// The child's next line into c.request; false when it has finished or exited without one.
bool Lockstep::readMessage(Child& c) {
  for (;;) {
    const size_t eol = c.pending.find('\n');
    if (eol != std::string::npos) {
      c.request = nlohmann::json::parse(c.pending.substr(0, eol), nullptr, false);
      c.pending.erase(0, eol + 1);
      return c.request.is_object() && c.request.value("next", "") != "end";
    }
    // Whether it exited is read before polling, so that a line written just before is still read.
    const bool exited = c.exited;
    pollfd p{c.doneFd, POLLIN, 0};
    if (::poll(&p, 1, exited ? 0 : 200) > 0) {
      char buf[4096];
      const ssize_t n = ::read(c.doneFd, buf, sizeof(buf));
      if (n > 0) c.pending.append(buf, static_cast<size_t>(n));
      continue;
    }
    if (exited) return false;
  }
}

char Lockstep::decide(size_t group, size_t rounds) {
  if (auto it = decisions_.find({group, rounds}); it != decisions_.end()) return it->second;
  char answer = 'g';
  const auto now = std::chrono::steady_clock::now();
  const auto first = firstExtra_.emplace(group, now).first->second;
  const auto& perChild = times_[group];
  const size_t processes = children_.size() / devices_;
  bool wide = false;
  for (size_t d = 1; d < devices_ && !perChild.empty(); ++d)
    for (const auto& [key, unused] : perChild[0]) {
      std::vector<std::vector<double>> perProcess;
      for (size_t p = 0; p < processes && (p + 1) * devices_ <= perChild.size(); ++p) {
        const auto& firstDevice = perChild[p * devices_];
        const auto& thisDevice = perChild[p * devices_ + d];
        const auto reference = firstDevice.find(key);
        const auto other = thisDevice.find(key);
        if (reference == firstDevice.end() || other == thisDevice.end()) continue;
        perProcess.push_back(bench::roundRatios(other->second, reference->second));
      }
      if (!bench::ratioSpread(perProcess, bench::kRatioTolerance).tight) wide = true;
    }
  if (!wide) answer = 't';
  else if (rounds * processes >= maxRounds_) answer = 'l';
  else if (std::chrono::duration<double>(now - first).count() >= budgetPerGroup_) answer = 'b';
  decisions_[{group, rounds}] = answer;
  return answer;
}

void Lockstep::run() {
  for (Child& c : children_) c.ended = !readMessage(c);
  for (bool any = true; any;) {
    any = false;
    for (size_t i = 0; i < children_.size(); ++i) {
      Child& c = children_[i];
      if (c.ended) continue;
      any = true;
      const size_t group = c.request.value("group", size_t{0});
      const char answer = c.request.value("next", "") == "extra" ? decide(group, c.rounds[group]) : 'g';
      (void)!::write(c.goFd, &answer, 1);
      if (!readMessage(c)) {
        c.ended = true;
        continue;
      }
      if (c.request.contains("times")) {
        const size_t g = c.request.value("group", size_t{0});
        auto& perChild = times_[g];
        perChild.resize(children_.size());
        for (const auto& entry : c.request["times"]) perChild[i][entry.at(0).get<std::string>()].push_back(entry.at(1).get<double>());
        ++c.rounds[g];
      }
    }
  }
}

}  // namespace parity::harness
