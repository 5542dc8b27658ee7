// The evidence behind a golden (golden/evidence.json): why an image is right, beyond GL and
// Vulkan agreeing (here both are llvmpipe running one SPIR-V, so their agreement shows
// determinism, not correctness). `parity bless` refuses a golden that no claim covers, checks
// every claim that covers it, and records each claim with what it measured in the manifest.
//
//   {"tests_root": "..",                                   // optional, see below
//    "evidence": [
//     {"case": "GLOB over technique/scene/platform", "except": ["GLOB", ...],  // optional
//      "reference": "{technique}/{scene}/reference",     // another golden of the same run or folder
//      "bound": {"max": 0.004, "mean": 0.0002, "percent": 1, "threshold": 0.004,
//                "residual_mean": 0.0002},               // any subset; at least one
//      "explained_by": "half-pixel shift",               // optional: the diagnosis must name it
//      "why": "what makes the reference a reason (required)"},
//     {"case": "GLOB", "tests": ["tests/x_test.cpp: Suite.Name"], "why": "..."}]}
//
// A reference claim compares the image with the reference's image (the run's deterministic
// render of that case, else its golden) channel by channel: "max" and "mean" bound the largest
// and the mean difference, "percent" the share of pixels over "threshold"; with "explained_by",
// the diagnosis (harness/compare/diagnosis.h) must name that cause and "residual_mean" bounds
// what is left once it is applied. A tests claim names tests (a file, then the gtest suite and
// name) that must exist as written; files are relative to "tests_root", itself relative to the
// folder holding evidence.json (default "..": the project root when the goldens are PROJECT/golden).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace parity::harness {

struct EvidenceBound {
  std::optional<double> max, mean, percent, threshold, residualMean;
};

struct EvidenceClaim {
  std::string casePattern;
  std::vector<std::string> except;  // globs of cases the claim does not cover
  std::string why;
  std::string reference;  // template: {technique}, {scene}, {platform} are replaced
  EvidenceBound bound;
  std::string explainedBy;
  std::vector<std::string> tests;  // "FILE: Suite.Name"
  std::string source;              // "FILE: evidence[N]", for messages
};

struct EvidenceFile {
  std::vector<EvidenceClaim> claims;
  std::string testsRoot;  // the folder test files are relative to
};

// False with "FILE: evidence[N]: reason" for a file that is not valid; an absent file reads as
// no claims (every bless is then refused).
bool loadEvidence(const std::string& file, EvidenceFile* out, std::string* error);

struct EvidenceContext {
  std::string testsRoot;                                         // test files are relative to it
  std::function<std::string(const std::string& key)> imageOf;    // reference key -> image path ("" if none)
};

// Checks the claims that cover `key` (technique/scene/platform) for the image at `image`. True
// when at least one covers it and every one that does holds; `records` gets one object per claim
// (the claim and what was measured or found). False with the reasons in `why` otherwise.
bool checkEvidence(const std::vector<EvidenceClaim>& claims, const std::string& key, const std::string& image,
                   const EvidenceContext& context, nlohmann::json* records, std::string* why);

}  // namespace parity::harness
