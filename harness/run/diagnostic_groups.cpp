#include "harness/run/diagnostic_groups.h"

#include <algorithm>

namespace parity::harness {

namespace {
void addOnce(std::vector<std::string>& list, const std::string& s) {
  if (!s.empty() && std::find(list.begin(), list.end(), s) == list.end()) list.push_back(s);
}

std::string joined(const std::vector<std::string>& list) {
  std::string out;
  for (const std::string& s : list) out += (out.empty() ? "" : ", ") + s;
  return out;
}

std::string text(const nlohmann::json& d, const char* key) {
  return d.contains(key) && d[key].is_string() ? d[key].get<std::string>() : std::string();
}
}  // namespace

std::string DiagnosticGroup::line() const {
  std::string out = severity + " " + code;
  if (!section.empty()) out += " [" + section + "]";
  out += ": " + message;
  if (occurrences > 1) out += " (" + std::to_string(occurrences) + " like it";
  if (occurrences > 1 && count > 0) out += ", " + std::to_string(count) + " in all";
  if (occurrences > 1) out += ")";
  std::string where;
  if (!passes.empty()) where += (passes.size() > 1 ? "passes " : "pass ") + joined(passes);
  if (!pipelines.empty()) where += std::string(where.empty() ? "" : ", ") + (pipelines.size() > 1 ? "pipelines " : "pipeline ") + joined(pipelines);
  if (!targets.empty()) where += std::string(where.empty() ? "" : "; ") + (targets.size() > 1 ? "targets " : "target ") + joined(targets);
  if (!where.empty()) out += "; " + where;
  if (!expected.empty()) out += " (expected: " + expected + ")";
  return out;
}

std::vector<DiagnosticGroup> groupDiagnostics(const nlohmann::json& diagnostics) {
  std::vector<DiagnosticGroup> groups;
  if (!diagnostics.is_array()) return groups;
  for (const nlohmann::json& d : diagnostics) {
    if (!d.is_object()) continue;
    const std::string code = text(d, "code");
    auto g = std::find_if(groups.begin(), groups.end(), [&](const DiagnosticGroup& x) { return x.code == code; });
    if (g == groups.end()) {
      DiagnosticGroup fresh;
      fresh.code = code;
      fresh.severity = text(d, "severity");
      fresh.section = text(d, "section");
      fresh.message = text(d, "message");
      groups.push_back(std::move(fresh));
      g = groups.end() - 1;
    }
    ++g->occurrences;
    if (d.contains("count") && d["count"].is_number_unsigned()) g->count += d["count"].get<uint64_t>();
    if (d.contains("targets") && d["targets"].is_array())
      for (const nlohmann::json& t : d["targets"])
        if (t.is_string()) addOnce(g->targets, t.get<std::string>());
    addOnce(g->passes, text(d, "pass"));
    addOnce(g->pipelines, text(d, "pipeline"));
    if (g->expected.empty()) g->expected = text(d, "expected");
  }
  return groups;
}

}  // namespace parity::harness
