// golden/tolerances.json and golden/expectations.json (harness/run/golden.h): parsed and checked
// here, apart from blessing and the runner, so that their fuzz targets (fuzz/) link this file,
// harness/run/case_key.cpp and the platform names only.
#include "harness/run/expectations.h"

#include <fnmatch.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "harness/run/golden.h"

namespace fs = std::filesystem;

namespace parity::harness {

bool readTextFile(const std::string& path, std::string* text, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *error = path + ": cannot read";
    return false;
  }
  std::ostringstream s;
  s << in.rdbuf();
  *text = s.str();
  return true;
}

bool readJsonFile(const std::string& path, nlohmann::json* j, std::string* error) {
  std::string text;
  if (!readTextFile(path, &text, error)) return false;
  try {
    *j = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    *error = path + ": not valid JSON: " + e.what();
    return false;
  }
  return true;
}

bool globMatch(const std::string& pattern, const std::string& text) {
  return pattern.empty() || ::fnmatch(pattern.c_str(), text.c_str(), 0) == 0;
}


namespace {

// Every key a tolerance entry may set, where it goes and the values it accepts. A key outside
// this table is refused: a misspelt threshold would otherwise leave the default in force unseen.
enum class Range { NonNegative, Percent };
struct ToleranceField {
  const char* name;
  Range range;
  double Tolerance::*top = nullptr;  // a field of Tolerance itself
  double DiffThresholds::*diff = nullptr;
  bool parity = false;  // `diff` of Tolerance::parity rather than Tolerance::golden
  double AttachmentTolerance::*attachment = nullptr;
};
const std::vector<ToleranceField>& toleranceFields() {
  static const std::vector<ToleranceField> fields = {
      {"golden_fail", Range::NonNegative, nullptr, &DiffThresholds::fail},
      {"golden_fail_percent", Range::Percent, nullptr, &DiffThresholds::failPercent},
      {"golden_hard_fail", Range::NonNegative, nullptr, &DiffThresholds::hardFail},
      {"parity_fail", Range::NonNegative, nullptr, &DiffThresholds::fail, true},
      {"parity_fail_percent", Range::Percent, nullptr, &DiffThresholds::failPercent, true},
      {"golden_flip_mean", Range::NonNegative, &Tolerance::flipMean},
      {"attachment_normal_degrees", Range::NonNegative, nullptr, nullptr, false, &AttachmentTolerance::normalDegrees},
      {"attachment_depth_absolute", Range::NonNegative, nullptr, nullptr, false, &AttachmentTolerance::depthAbsolute},
      {"attachment_float_relative", Range::NonNegative, nullptr, nullptr, false, &AttachmentTolerance::floatRelative},
      {"attachment_quantised_steps", Range::NonNegative, nullptr, nullptr, false, &AttachmentTolerance::quantisedSteps},
      {"attachment_fail_percent", Range::Percent, nullptr, nullptr, false, &AttachmentTolerance::failPercent},
  };
  return fields;
}

const ToleranceField* findToleranceField(const std::string& name) {
  for (const ToleranceField& f : toleranceFields())
    if (name == f.name) return &f;
  return nullptr;
}

std::string jsonTypeName(const nlohmann::json& j) { return j.type_name(); }

// One entry ("default" or a case pattern's): an object of known keys with numbers in range.
bool checkToleranceEntry(const nlohmann::json& e, const std::string& where, std::string* error) {
  if (!e.is_object()) {
    *error = where + ": must be an object of thresholds, not " + jsonTypeName(e);
    return false;
  }
  for (const auto& [name, value] : e.items()) {
    const ToleranceField* f = findToleranceField(name);
    if (!f) {
      std::string known;
      for (const ToleranceField& k : toleranceFields()) known += (known.empty() ? "" : ", ") + std::string(k.name);
      *error = where + ": unknown key '" + name + "' (known: " + known + ")";
      return false;
    }
    if (!value.is_number()) {
      *error = where + ": " + name + " must be a number, not " + jsonTypeName(value);
      return false;
    }
    double v = value.get<double>();
    std::ostringstream shown;
    shown << v;
    if (!std::isfinite(v) || v < 0) {
      *error = where + ": " + name + " is " + shown.str() + "; it must be a finite number >= 0";
      return false;
    }
    if (f->range == Range::Percent && v > 100) {
      *error = where + ": " + name + " is " + shown.str() + "; a percentage must lie in [0, 100]";
      return false;
    }
  }
  return true;
}

void applyToleranceEntry(const nlohmann::json& e, Tolerance* t) {
  for (const auto& [name, value] : e.items()) {
    const ToleranceField* f = findToleranceField(name);
    double v = value.get<double>();
    if (f->top) t->*(f->top) = v;
    if (f->diff) (f->parity ? t->parity : t->golden).*(f->diff) = v;
    if (f->attachment) t->attachments.*(f->attachment) = v;
  }
}

// A calendar date written YYYY-MM-DD (the form ISO 8601 and `date -I` write), as days since the
// epoch; false for any other text or a day the month does not have.
bool parseDate(const std::string& text, std::chrono::sys_days* out) {
  if (text.size() != 10 || text[4] != '-' || text[7] != '-') return false;
  for (size_t i : {0, 1, 2, 3, 5, 6, 8, 9})
    if (text[i] < '0' || text[i] > '9') return false;
  const std::chrono::year_month_day date{std::chrono::year{std::stoi(text.substr(0, 4))},
                                         std::chrono::month{static_cast<unsigned>(std::stoi(text.substr(5, 2)))},
                                         std::chrono::day{static_cast<unsigned>(std::stoi(text.substr(8, 2)))}};
  if (!date.ok()) return false;
  *out = std::chrono::sys_days{date};
  return true;
}

}  // namespace

bool checkTolerances(const nlohmann::json& j, const std::string& file, std::string* error) {
  if (!j.is_object()) {
    *error = file + ": must be an object with \"default\" and \"cases\", not " + jsonTypeName(j);
    return false;
  }
  for (const auto& [key, value] : j.items()) {
    if (key == "about") continue;
    if (key == "default") {
      if (!checkToleranceEntry(value, file + ": default", error)) return false;
    } else if (key == "cases") {
      if (!value.is_object()) {
        *error = file + ": cases must be an object mapping case globs to thresholds, not " + jsonTypeName(value);
        return false;
      }
      for (const auto& [pattern, entry] : value.items())
        if (!checkToleranceEntry(entry, file + ": cases: " + pattern, error)) return false;
    } else if (key == "targets") {
      if (!value.is_object()) {
        *error = file + ": targets must be an object mapping case globs to target globs, not " + jsonTypeName(value);
        return false;
      }
      for (const auto& [pattern, byTarget] : value.items()) {
        const std::string where = file + ": targets: " + pattern;
        if (!byTarget.is_object()) {
          *error = where + ": must map target globs to thresholds, not " + jsonTypeName(byTarget);
          return false;
        }
        for (const auto& [target, entry] : byTarget.items()) {
          const std::string at = where + ": " + target;
          if (!entry.is_object() || !entry.contains("reason") || !entry["reason"].is_string() ||
              entry["reason"].get<std::string>().empty()) {
            *error = at + ": needs a \"reason\" (why this target may differ more)";
            return false;
          }
          nlohmann::json thresholds = entry;
          thresholds.erase("reason");
          for (const auto& [name, v] : thresholds.items())
            if (name.rfind("attachment_", 0) != 0) {
              *error = at + ": only attachment_* thresholds apply to a target, not '" + name + "'";
              return false;
            }
          if (!checkToleranceEntry(thresholds, at, error)) return false;
        }
      }
    } else if (key == "budgets") {
      if (!checkBudgets(value, file, error)) return false;
    } else {
      *error = file + ": unknown key '" + key + "' (known: about, default, cases, targets, budgets)";
      return false;
    }
  }
  return true;
}

bool checkTolerancesFile(const std::string& file, std::string* error) {
  std::error_code ec;
  if (file.empty() || !fs::exists(file, ec)) return true;
  nlohmann::json j;
  return readJsonFile(file, &j, error) && checkTolerances(j, file, error);
}

bool loadTolerance(const std::string& file, const CaseKey& key, Tolerance* out, std::string* error) {
  Tolerance t;
  // Goldens come from the same Mesa build here, where every image is reproducible bit for bit;
  // the default leaves room for one rounding step on a few edge pixels of another build.
  t.golden.fail = 1.5 / 255.0;
  t.golden.failPercent = 0.05;
  t.golden.hardFail = 24.0 / 255.0;
  t.golden.warn = 0.5 / 255.0;
  t.golden.warnPercent = 0.0;
  // GL and Vulkan are bit-identical on Mesa (docs/ARCHITECTURE.md), so the parity budget is zero.
  t.parity.fail = 0.5 / 255.0;
  t.parity.failPercent = 0.0;
  t.parity.warn = 0.5 / 255.0;
  std::error_code ec;
  if (!file.empty() && fs::exists(file, ec)) {
    nlohmann::json j;
    if (!readJsonFile(file, &j, error) || !checkTolerances(j, file, error)) return false;
    auto apply = [&](const nlohmann::json& e, const std::string& source) {
      applyToleranceEntry(e, &t);
      t.parity.warn = std::min(t.parity.warn, t.parity.fail);
      t.golden.warn = std::min(t.golden.warn, t.golden.fail);
      t.source = source;
    };
    if (j.contains("default")) apply(j["default"], file + ": default");
    if (j.contains("cases"))
      for (auto& [pattern, e] : j["cases"].items())
        if (globMatch(pattern, key.id())) apply(e, file + ": " + pattern);
    if (j.contains("targets"))
      for (auto& [pattern, byTarget] : j["targets"].items()) {
        if (!globMatch(pattern, key.id())) continue;
        for (auto& [target, entry] : byTarget.items()) {
          Tolerance relaxed = t;
          nlohmann::json thresholds = entry;
          thresholds.erase("reason");
          applyToleranceEntry(thresholds, &relaxed);
          t.targets.push_back({target, relaxed.attachments, entry["reason"].get<std::string>(),
                               file + ": targets: " + pattern + ": " + target});
        }
      }
    // The case's backend axis is its device ("gl-zink", or another engine's backend name).
    if (j.contains("budgets")) t.budget = findBudget(j["budgets"], file, key.backend, key.id());
  }
  *out = t;
  return true;
}

const TargetTolerance* Tolerance::forTarget(const std::string& name) const {
  const TargetTolerance* found = nullptr;
  for (const TargetTolerance& t : targets)
    if (globMatch(t.target, name)) found = &t;
  return found;
}

bool loadExpectations(const std::string& file, std::vector<Expectation>* out, std::string* error) {
  out->clear();
  std::error_code ec;
  if (file.empty() || !fs::exists(file, ec)) return true;
  nlohmann::json j;
  if (!readJsonFile(file, &j, error)) return false;
  if (!j.is_object()) {
    *error = file + ": must be an object with \"expectations\", not " + jsonTypeName(j);
    return false;
  }
  for (const auto& [key, value] : j.items())
    if (key != "about" && key != "expectations") {
      *error = file + ": unknown key '" + key + "' (known: about, expectations)";
      return false;
    }
  if (!j.contains("expectations")) return true;
  const nlohmann::json& list = j["expectations"];
  if (!list.is_array()) {
    *error = file + ": expectations must be an array, not " + jsonTypeName(list);
    return false;
  }
  for (size_t i = 0; i < list.size(); ++i) {
    const nlohmann::json& e = list[i];
    std::string where = file + ": expectations[" + std::to_string(i) + "]";
    if (!e.is_object()) {
      *error = where + ": must be an object, not " + jsonTypeName(e);
      return false;
    }
    for (const auto& [key, value] : e.items()) {
      if (key != "case" && key != "driver" && key != "result" && key != "reason" && key != "diagnostic" &&
          key != "target" && key != "pass" && key != "bug" && key != "expires") {
        *error = where + ": unknown key '" + key + "' (known: case, driver, result, diagnostic, target, pass, reason, bug, expires)";
        return false;
      }
      if (!value.is_string()) {
        *error = where + ": " + key + " must be a string, not " + jsonTypeName(value);
        return false;
      }
    }
    if (!e.contains("case")) {
      *error = where + ": has no case";
      return false;
    }
    Expectation x;
    x.casePattern = e["case"].get<std::string>();
    x.driverPattern = e.value("driver", "");
    x.reason = e.value("reason", "");
    x.diagnosticPattern = e.value("diagnostic", "");
    x.targetPattern = e.value("target", "");
    x.passPattern = e.value("pass", "");
    x.bug = e.value("bug", "");
    x.expires = e.value("expires", "");
    if (e.contains("expires")) {
      std::chrono::sys_days last;
      if (!parseDate(x.expires, &last)) {
        *error = where + ": expires '" + x.expires + "' is not a date YYYY-MM-DD";
        return false;
      }
      // The entry holds through its last day, in UTC (the day CI machines agree on).
      x.expired = std::chrono::floor<std::chrono::days>(std::chrono::system_clock::now()) > last;
    }
    if (e.contains("diagnostic") && (x.diagnosticPattern.empty() || e.contains("result"))) {
      *error = where + ": diagnostic must be a non-empty code glob, and an entry expects a diagnostic or a result, not both";
      return false;
    }
    if ((e.contains("target") || e.contains("pass")) && !e.contains("diagnostic")) {
      *error = where + ": target and pass narrow a diagnostic expectation; this entry has no diagnostic";
      return false;
    }
    std::string result = e.value("result", "Fail");
    if (!parseResultName(result, &x.result)) {
      *error = file + ": unknown result '" + result + "' for " + x.casePattern;
      return false;
    }
    if (x.reason.empty()) {
      *error = file + ": expectation for " + x.casePattern + " has no reason";
      return false;
    }
    out->push_back(x);
  }
  return true;
}

const Expectation* findExpectation(const std::vector<Expectation>& list, const std::string& caseId,
                                   const std::string& deviceText) {
  for (const Expectation& e : list)
    if (e.diagnosticPattern.empty() && globMatch(e.casePattern, caseId) && globMatch(e.driverPattern, deviceText)) return &e;
  return nullptr;
}

nlohmann::json toJson(const Expectation& e) {
  nlohmann::json j{{"case", e.casePattern}, {"reason", e.reason}};
  if (!e.driverPattern.empty()) j["driver"] = e.driverPattern;
  if (e.diagnosticPattern.empty()) j["result"] = resultName(e.result);
  else j["diagnostic"] = e.diagnosticPattern;
  if (!e.bug.empty()) j["bug"] = e.bug;
  if (!e.expires.empty()) {
    j["expires"] = e.expires;
    j["expired"] = e.expired;
  }
  return j;
}

bool Expectation::matchesDiagnostic(const std::string& code, const std::vector<std::string>& targets,
                                    const std::string& pass) const {
  if (diagnosticPattern.empty() || !globMatch(diagnosticPattern, code)) return false;
  if (!passPattern.empty() && !globMatch(passPattern, pass)) return false;
  if (targetPattern.empty()) return true;
  return std::any_of(targets.begin(), targets.end(), [&](const std::string& t) { return globMatch(targetPattern, t); });
}

std::vector<const Expectation*> findDiagnosticExpectations(const std::vector<Expectation>& list, const std::string& caseId,
                                                           const std::string& deviceText) {
  std::vector<const Expectation*> found;
  for (const Expectation& e : list)
    if (!e.diagnosticPattern.empty() && globMatch(e.casePattern, caseId) && globMatch(e.driverPattern, deviceText))
      found.push_back(&e);
  return found;
}

// Bless rule: a golden is written only when the run shows GL and Vulkan rendering bit-identical
// images of the group, each deterministic, in that same run (re-checked on the files); or with
// an explicit backend and a written reason. The reason goes into the manifest.

}  // namespace parity::harness
