// A case's platform diagnostics as a person reads them: one group per code, the targets, passes
// and pipelines it fired in listed once, the counts of rules about values summed, the first
// message and the expectation's reason once. `parity render`, the report's case pages and JUnit
// print the same lines; a run's results.json keeps every diagnostic (golden.diagnostics).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace parity::harness {

struct DiagnosticGroup {
  std::string code, severity, section;
  std::vector<std::string> targets, passes, pipelines;  // each once, in the order first seen
  uint64_t count = 0;       // the sum of their counts (samples, texels), 0 for other rules
  size_t occurrences = 0;   // diagnostics in the group
  std::string message;      // the first one's
  std::string expected;     // the reason of the expectation that matched it, if any
  // "error E_MRT_FORMAT_MISMATCH [P1]: <message>; pass store, pipeline abuffer store; targets
  // a, b (expected: ...)", with "(2 like it)" when several fired.
  std::string line() const;
  bool operator==(const DiagnosticGroup&) const = default;
};

// `diagnostics`: a JSON array as results.json holds them (code, severity, section, message,
// targets, pass, pipeline, count, expected). Groups in the order their codes first appear.
std::vector<DiagnosticGroup> groupDiagnostics(const nlohmann::json& diagnostics);

}  // namespace parity::harness
