#include "harness/run/budgets.h"

#include <cmath>
#include <set>
#include <sstream>

#include "harness/run/expectations.h"

namespace parity::harness {

namespace {

std::string shown(const nlohmann::json& v) {
  if (!v.is_number()) return v.dump();
  std::ostringstream s;
  s << v.get<double>();
  return s.str();
}

// An object holding exactly `keys`, each a finite number in [lo, hi] (an integer when `whole`).
struct NumberKey {
  const char* name;
  double lo, hi;
  bool whole, openLow;
};
bool checkMeasure(const nlohmann::json& m, const std::string& where, const std::vector<NumberKey>& keys, std::string* error) {
  std::string names;
  for (const NumberKey& k : keys) names += (names.empty() ? "" : ", ") + std::string(k.name);
  if (!m.is_object()) {
    *error = where + ": must be an object of " + names;
    return false;
  }
  for (const auto& [name, value] : m.items()) {
    bool known = false;
    for (const NumberKey& k : keys) known = known || name == k.name;
    if (!known) {
      *error = where + ": unknown key '" + name + "' (known: " + names + ")";
      return false;
    }
  }
  for (const NumberKey& k : keys) {
    if (!m.contains(k.name)) {
      *error = where + ": " + k.name + " is required";
      return false;
    }
    const nlohmann::json& v = m[k.name];
    const bool number = v.is_number() && std::isfinite(v.get<double>());
    const double x = number ? v.get<double>() : 0;
    if (!number || (k.whole && !v.is_number_integer()) || x > k.hi || (k.openLow ? x <= k.lo : x < k.lo)) {
      std::ostringstream range;
      range << (k.openLow ? "(" : "[") << k.lo << ", " << k.hi << "]";
      *error = where + ": " + k.name + " is " + shown(v) + "; it must be " + (k.whole ? "an integer" : "a number") +
               " in " + range.str();
      return false;
    }
  }
  return true;
}

}  // namespace

bool checkBudgets(const nlohmann::json& budgets, const std::string& file, std::string* error) {
  if (!budgets.is_array()) {
    *error = file + ": budgets must be an array of named budgets, not " + std::string(budgets.type_name());
    return false;
  }
  static const std::set<std::string> known = {"name", "devices", "cases", "flip_percentile", "fuzzy", "reason"};
  std::set<std::string> names;
  for (size_t i = 0; i < budgets.size(); ++i) {
    const nlohmann::json& b = budgets[i];
    std::string where = file + ": budgets[" + std::to_string(i) + "]";
    if (!b.is_object()) {
      *error = where + ": must be an object, not " + std::string(b.type_name());
      return false;
    }
    if (b.contains("name") && b["name"].is_string()) where += " (" + b["name"].get<std::string>() + ")";
    for (const auto& [key, value] : b.items())
      if (!known.count(key)) {
        *error = where + ": unknown key '" + key + "' (known: name, devices, cases, flip_percentile, fuzzy, reason)";
        return false;
      }
    for (const char* key : {"name", "devices", "reason", "cases"}) {
      const bool required = std::string(key) != "cases";
      if (!b.contains(key) && !required) continue;
      if (!b.contains(key) || !b[key].is_string() || b[key].get<std::string>().empty()) {
        *error = where + ": " + key + " must be a non-empty string" +
                 (std::string(key) == "reason" ? " (why this device may differ)" : "");
        return false;
      }
    }
    if (!names.insert(b["name"].get<std::string>()).second) {
      *error = where + ": name is used by an earlier budget";
      return false;
    }
    if (!b.contains("flip_percentile") && !b.contains("fuzzy")) {
      *error = where + ": needs flip_percentile or fuzzy (or both)";
      return false;
    }
    if (b.contains("flip_percentile") &&
        !checkMeasure(b["flip_percentile"], where + ": flip_percentile",
                      {{"p", 0, 100, false, true}, {"max", 0, 1, false, false}}, error))
      return false;
    if (b.contains("fuzzy") &&
        !checkMeasure(b["fuzzy"], where + ": fuzzy", {{"max_difference", 0, 255, true, false}, {"pixels", 0, 1e12, true, false}},
                      error))
      return false;
  }
  return true;
}

std::optional<Budget> findBudget(const nlohmann::json& budgets, const std::string& file, const std::string& device,
                                 const std::string& caseId) {
  std::optional<Budget> found;
  for (size_t i = 0; i < budgets.size(); ++i) {
    const nlohmann::json& j = budgets[i];
    if (!globMatch(j["devices"].get<std::string>(), device) || !globMatch(j.value("cases", std::string()), caseId)) continue;
    Budget b;
    b.name = j["name"];
    b.devices = j["devices"];
    b.cases = j.value("cases", std::string("*"));
    b.reason = j["reason"];
    b.source = file + ": budgets[" + std::to_string(i) + "] (" + b.name + ")";
    if (j.contains("flip_percentile"))
      b.flipPercentile = FlipPercentileBudget{j["flip_percentile"]["p"].get<double>(), j["flip_percentile"]["max"].get<double>()};
    if (j.contains("fuzzy"))
      b.fuzzy = FuzzyBudget{j["fuzzy"]["max_difference"].get<int>(), j["fuzzy"]["pixels"].get<long long>()};
    found = b;
  }
  return found;
}

nlohmann::json toJson(const Budget& b) {
  nlohmann::json j = {{"name", b.name}, {"devices", b.devices}, {"cases", b.cases}, {"reason", b.reason}, {"source", b.source}};
  if (b.flipPercentile) j["flip_percentile"] = {{"p", b.flipPercentile->p}, {"max", b.flipPercentile->max}};
  if (b.fuzzy) j["fuzzy"] = {{"max_difference", b.fuzzy->maxDifference}, {"pixels", b.fuzzy->pixels}};
  return j;
}

}  // namespace parity::harness
