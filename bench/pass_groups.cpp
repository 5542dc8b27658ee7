#include "bench/pass_groups.h"

#include <cctype>

namespace parity::bench {

std::string passGroupName(const std::string& label) {
  std::string s = label;
  while (!s.empty() && (std::isdigit(static_cast<unsigned char>(s.back())) || s.back() == ' ' || s.back() == '/' ||
                        s.back() == '#' || s.back() == '-' || s.back() == '_' || s.back() == '.'))
    s.pop_back();
  return s.empty() ? "(unnamed)" : s;
}

std::vector<std::pair<std::string, double>> groupPassTimes(const std::vector<rhi::PassTiming>& timings) {
  std::vector<std::pair<std::string, double>> out;
  for (const rhi::PassTiming& t : timings) {
    std::string name = passGroupName(t.label);
    bool merged = false;
    for (auto& [n, ms] : out)
      if (n == name) {
        ms += t.ms;
        merged = true;
      }
    if (!merged) out.emplace_back(name, t.ms);
  }
  return out;
}

}  // namespace parity::bench
