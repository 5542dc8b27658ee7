// Diagnostics raised by the platform layers (console render-target quirks).
//
// Every diagnostic has a stable code taken verbatim from the reference pack's diagnostic
// catalogue (console-quirks.md: the consolidated table plus the codes each section X1-X5,
// P1-P4, D1 names; W_FLOAT7E3_RANGE_CLAMP, for the 7e3 format X2 describes without a code, is
// parity's own), a severity, and a message that names the targets involved, and where it fired
// (the pass and pipeline, a count for rules about values). Tests and the `parity explain`
// command match on the code, never on the message text.
//
// Severity follows the code's prefix, as the pack proposes: E_ = error, W_ = warning,
// I_ = information.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace parity::platforms {

enum class Severity : uint8_t { Error, Warning, Info };

std::string_view severityName(Severity severity);  // "error", "warning", "info"

// One row of the catalogue.
struct CatalogueEntry {
  std::string_view code;         // e.g. "E_EDRAM_OVERLAP"
  Severity severity;
  std::string_view platform;     // "x360", "ps3", "ps3/d3d9", "dx10"
  std::string_view description;  // one line: the exact trigger
  std::string_view section;      // section of the reference pack that defines it: "X1", "P2", ...
  // True when the code is a row of the pack's consolidated catalogue table; false when only the
  // section's own diagnostic list names it.
  bool consolidated;
};

// Every code of the reference pack, in the pack's order (sections X1..X5, P1..P4, D1).
std::span<const CatalogueEntry> diagnosticCatalogue();
// Null for a code that is not in the catalogue.
const CatalogueEntry* findCatalogueEntry(std::string_view code);

// Where in a frame's command stream a rule fired: the technique's pass (its PassDesc label),
// the pipeline of the draw or dispatch (its label), and for rules about values the number of
// texels or samples that broke it. Empty / 0 where the rule is about the plan alone.
struct DiagnosticSite {
  std::string pass;
  std::string pipeline;
  uint64_t count = 0;
};

struct Diagnostic {
  std::string code;
  Severity severity = Severity::Error;
  std::string message;               // names the targets involved
  std::vector<std::string> targets;  // the targets (surfaces, textures) involved
  std::string section;               // pack section, copied from the catalogue
  std::string pass;                  // DiagnosticSite
  std::string pipeline;
  uint64_t count = 0;

  // "error E_EDRAM_OVERLAP [X1]: <message>"
  std::string format() const;
};

// An ordered list of diagnostics. report() only accepts catalogue codes (it throws
// std::logic_error for anything else), so a typo in a layer cannot invent a code.
class DiagnosticList {
 public:
  void report(std::string_view code, std::vector<std::string> targets, std::string message,
              const DiagnosticSite& site = {});

  const std::vector<Diagnostic>& all() const { return items_; }
  bool empty() const { return items_.empty(); }
  std::size_t size() const { return items_.size(); }
  bool has(std::string_view code) const;
  std::size_t count(std::string_view code) const;
  const Diagnostic* first(std::string_view code) const;  // null when absent
  bool hasErrors() const;
  void append(const DiagnosticList& other);
  // Stamps `site`'s pass and pipeline on the diagnostics from index `from` on that have none.
  void locate(std::size_t from, const DiagnosticSite& site);
  void clear() { items_.clear(); }
  // One formatted diagnostic per line.
  std::string format() const;

 private:
  std::vector<Diagnostic> items_;
};

}  // namespace parity::platforms
