// `parity run --baseline DIR` and `parity merge --baseline DIR`: this run against an earlier one
// (DIR/results.json), case by case: regressions (Pass before, not Pass now), fixes (the reverse),
// new cases and vanished ones. The comparison is results.json's "baseline"; the summary line,
// junit.xml and the report show it from there.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace parity::harness {

// DIR/results.json, checked for what the comparison reads (cases with string ids and results).
// False with one line naming the file: missing, not JSON, or the wrong shape.
bool loadBaseline(const std::string& dir, nlohmann::json* baseline, std::string* error);

// {"dir", "run_id", "regressions": [{"id", "before", "now", "reason"}], "fixes": [...],
//  "new": [{"id", "now"}], "vanished": [{"id", "before"}]} of `results` against `baseline`.
nlohmann::json compareWithBaseline(const std::string& dir, const nlohmann::json& baseline, const nlohmann::json& results);

// "against baseline DIR: 1 regression, 1 fix, 0 new, 0 vanished" for a "baseline" object.
std::string baselineSummary(const nlohmann::json& comparison);

// One line per regression and fix on stdout, "<command>: regression ID: Pass before, Fail now
// (reason)".
void printBaselineChanges(const char* command, const nlohmann::json& comparison);

// How a case changed against the baseline ("regression: Pass before, Fail now"); empty when it
// did not (or there is no baseline).
std::string baselineChange(const nlohmann::json& comparison, const std::string& caseId);

}  // namespace parity::harness
