// This run against an earlier one, case by case (harness/run/baseline.h).
#include "harness/run/baseline.h"

#include <cstdio>
#include <filesystem>
#include <map>

#include "harness/run/expectations.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

constexpr const char* kPass = "Pass";

// Pointers into `results` itself (json::value would return a copy that dies at once).
std::map<std::string, const nlohmann::json*> casesById(const nlohmann::json& results) {
  std::map<std::string, const nlohmann::json*> byId;
  if (results.contains("cases") && results["cases"].is_array())
    for (const auto& c : results["cases"]) byId[c.value("id", "")] = &c;
  return byId;
}

std::string plural(size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

bool loadBaseline(const std::string& dir, nlohmann::json* baseline, std::string* error) {
  const std::string file = (fs::path(dir) / "results.json").string();
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) {
    *error = file + ": no such file (--baseline needs the output folder of an earlier `parity run`)";
    return false;
  }
  nlohmann::json j;
  if (!readJsonFile(file, &j, error)) return false;
  if (!j.is_object() || !j.contains("cases") || !j["cases"].is_array()) {
    *error = file + ": not a parity results file (no \"cases\" array)";
    return false;
  }
  for (size_t i = 0; i < j["cases"].size(); ++i) {
    const nlohmann::json& c = j["cases"][i];
    if (!c.is_object() || !c.contains("id") || !c["id"].is_string() || !c.contains("result") || !c["result"].is_string()) {
      *error = file + ": cases[" + std::to_string(i) + "] needs a string id and result";
      return false;
    }
  }
  *baseline = std::move(j);
  return true;
}

nlohmann::json compareWithBaseline(const std::string& dir, const nlohmann::json& baseline, const nlohmann::json& results) {
  nlohmann::json b{{"dir", dir},
                   {"run_id", baseline.value("run_id", "")},
                   {"regressions", nlohmann::json::array()},
                   {"fixes", nlohmann::json::array()},
                   {"new", nlohmann::json::array()},
                   {"vanished", nlohmann::json::array()}};
  const auto before = casesById(baseline);
  const auto now = casesById(results);
  for (const auto& [id, c] : now) {
    const std::string result = c->value("result", "");
    auto was = before.find(id);
    if (was == before.end()) {
      b["new"].push_back({{"id", id}, {"now", result}});
      continue;
    }
    const std::string previous = was->second->value("result", "");
    nlohmann::json change{{"id", id}, {"before", previous}, {"now", result}};
    if (previous == kPass && result != kPass) {
      change["reason"] = c->value("reason", "");
      b["regressions"].push_back(change);
    } else if (previous != kPass && result == kPass) {
      b["fixes"].push_back(change);
    }
  }
  for (const auto& [id, c] : before)
    if (!now.count(id)) b["vanished"].push_back({{"id", id}, {"before", c->value("result", "")}});
  return b;
}

std::string baselineSummary(const nlohmann::json& comparison) {
  auto count = [&](const char* key) { return comparison.value(key, nlohmann::json::array()).size(); };
  return "against baseline " + comparison.value("dir", "") + ": " + plural(count("regressions"), "regression", "regressions") +
         ", " + plural(count("fixes"), "fix", "fixes") + ", " + std::to_string(count("new")) + " new, " +
         std::to_string(count("vanished")) + " vanished";
}

void printBaselineChanges(const char* command, const nlohmann::json& comparison) {
  for (const auto& c : comparison.value("regressions", nlohmann::json::array())) {
    const std::string reason = c.value("reason", "");
    std::printf("%s: regression %s: %s before, %s now%s\n", command, c.value("id", "").c_str(), c.value("before", "").c_str(),
                c.value("now", "").c_str(), reason.empty() ? "" : (" (" + reason + ")").c_str());
  }
  for (const auto& c : comparison.value("fixes", nlohmann::json::array()))
    std::printf("%s: fix %s: %s before, %s now\n", command, c.value("id", "").c_str(), c.value("before", "").c_str(),
                c.value("now", "").c_str());
}

std::string baselineChange(const nlohmann::json& comparison, const std::string& caseId) {
  for (const char* kind : {"regressions", "fixes"})
    for (const auto& c : comparison.value(kind, nlohmann::json::array()))
      if (c.value("id", "") == caseId)
        return std::string(kind == std::string("fixes") ? "fix" : "regression") + ": " + c.value("before", "") + " before, " +
               c.value("now", "") + " now";
  for (const auto& c : comparison.value("new", nlohmann::json::array()))
    if (c.value("id", "") == caseId) return "new: not in the baseline";
  return "";
}

}  // namespace parity::harness
