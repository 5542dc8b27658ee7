// A case's platform diagnostics as a person reads them (harness/run/diagnostic_groups.h): one line
// per code, its targets, passes and pipelines once each, counts summed, the expectation's reason
// once, however many times the rule fired.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "harness/run/diagnostic_groups.h"

using namespace parity::harness;

namespace {

TEST(DiagnosticGroups, OneLinePerCodeWithItsTargetsPassesAndCountsOnce) {
  const nlohmann::json diagnostics = nlohmann::json::parse(R"([
    {"code": "E_EDRAM_NOT_READABLE", "severity": "error", "section": "X1", "message": "light samples albedo",
     "targets": ["albedo"], "pass": "light", "pipeline": "light", "count": 0, "expected": "a known port problem"},
    {"code": "W_FIXED16_RANGE_CLAMP", "severity": "warning", "section": "X2", "message": "30 samples of a",
     "targets": ["a"], "pass": "p1", "pipeline": "", "count": 30},
    {"code": "E_EDRAM_NOT_READABLE", "severity": "error", "section": "X1", "message": "compose samples albedo",
     "targets": ["albedo"], "pass": "compose", "pipeline": "compose", "count": 0, "expected": "a known port problem"},
    {"code": "W_FIXED16_RANGE_CLAMP", "severity": "warning", "section": "X2", "message": "12 samples of b",
     "targets": ["b"], "pass": "p1", "pipeline": "", "count": 12}
  ])");
  const std::vector<DiagnosticGroup> groups = groupDiagnostics(diagnostics);
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0].code, "E_EDRAM_NOT_READABLE");
  EXPECT_EQ(groups[0].occurrences, 2u);
  EXPECT_EQ(groups[0].targets, (std::vector<std::string>{"albedo"}));
  EXPECT_EQ(groups[0].passes, (std::vector<std::string>{"light", "compose"}));
  EXPECT_EQ(groups[0].line(),
            "error E_EDRAM_NOT_READABLE [X1]: light samples albedo (2 like it); passes light, compose, pipelines light, "
            "compose; target albedo (expected: a known port problem)");
  EXPECT_EQ(groups[1].count, 42u);
  EXPECT_EQ(groups[1].line(),
            "warning W_FIXED16_RANGE_CLAMP [X2]: 30 samples of a (2 like it, 42 in all); pass p1; targets a, b");
  EXPECT_TRUE(groupDiagnostics(nlohmann::json::array()).empty());
  EXPECT_TRUE(groupDiagnostics(nlohmann::json::object()).empty()) << "not a list: nothing, no throw";
}

}  // namespace
