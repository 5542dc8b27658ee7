// Named budgets per device class and case glob (golden/tolerances.json, "budgets"): how far a
// device's image may lie from an accepted image of its case, in the two measures peers use:
// a FLIP percentile (the p-th percentile of the per-pixel LDR-FLIP error at most `max`) and
// Mozilla's reftest rule fuzzy(maxDifference, pixelCount) (no channel more than max_difference
// 8-bit steps apart, and at most `pixels` pixels differing at all).
//
//   {"budgets": [{"name": "zink-aa", "devices": "gl-zink*", "cases": "lidr-msaa/*",
//                 "flip_percentile": {"p": 99, "max": 0.1},
//                 "fuzzy": {"max_difference": 2, "pixels": 40},
//                 "reason": "why this device may differ (required)"}]}
//
// `devices` is a glob over the case's device name (`gl-zink`, or another engine's backend name
// under `parity run --images`), `cases` (default every case) a glob over case ids. The last
// budget matching a case judges it, in place of the golden_* thresholds and golden_flip_mean:
// against the primary golden and against the accepted images of its device
// (harness/run/accepted_images.h). Parsed here with JSON only, so the tolerance fuzz target
// links it; measured in accepted_images.cpp.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace parity::harness {

struct FlipPercentileBudget {
  double p = 99;    // percentile in (0, 100]
  double max = 0;   // LDR-FLIP error in [0, 1]
};

struct FuzzyBudget {
  int maxDifference = 0;  // 8-bit steps, 0..255
  long long pixels = 0;   // pixels with any channel differing
};

struct Budget {
  std::string name, devices, cases, reason;
  std::optional<FlipPercentileBudget> flipPercentile;
  std::optional<FuzzyBudget> fuzzy;
  std::string source;  // "FILE: budgets[N] (NAME)"
};

// The "budgets" value of FILE: an array of entries with known keys only, a unique name, a
// reason, a device glob and at least one measure with numbers in range. False with
// "FILE: budgets[N] (NAME): reason" otherwise.
bool checkBudgets(const nlohmann::json& budgets, const std::string& file, std::string* error);

// The last entry of a checked "budgets" array whose `devices` glob matches `device` and whose
// `cases` glob matches `caseId`; none when no entry does.
std::optional<Budget> findBudget(const nlohmann::json& budgets, const std::string& file, const std::string& device,
                                 const std::string& caseId);

// The budget as results.json shows it: name, devices, cases, its measures, reason, source.
nlohmann::json toJson(const Budget& b);

}  // namespace parity::harness
