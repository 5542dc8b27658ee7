// The names and keys of `parity run` (harness/run/run.h): results, platforms, case ids. Kept apart
// from the runner so that the expectation and tolerance parsers (harness/run/expectations.cpp) and
// their fuzz targets link without the rest of the harness.
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "harness/run/run.h"
#include "platforms/common/platform.h"

namespace parity::harness {

namespace {
struct ResultNameEntry {
  CaseResult result;
  const char* name;
};
constexpr ResultNameEntry kResultNames[] = {
    {CaseResult::Pass, "Pass"},
    {CaseResult::Fail, "Fail"},
    {CaseResult::ParityWarning, "ParityWarning"},
    {CaseResult::Crash, "Crash"},
    {CaseResult::Timeout, "Timeout"},
    {CaseResult::Skip, "Skip"},
    {CaseResult::ExpectedFail, "ExpectedFail"},
    {CaseResult::UnexpectedPass, "UnexpectedPass"},
    {CaseResult::Flake, "Flake"},
    {CaseResult::Nondeterministic, "Nondeterministic"},
};
}  // namespace

const char* resultName(CaseResult r) {
  for (const auto& e : kResultNames)
    if (e.result == r) return e.name;
  return "?";
}

bool parseResultName(const std::string& name, CaseResult* out) {
  for (const auto& e : kResultNames)
    if (name == e.name) {
      *out = e.result;
      return true;
    }
  return false;
}

bool isBadResult(CaseResult r, bool strict) {
  if (strict && (r == CaseResult::ParityWarning || r == CaseResult::Flake)) return true;
  return r == CaseResult::Fail || r == CaseResult::Crash || r == CaseResult::Timeout ||
         r == CaseResult::Nondeterministic || r == CaseResult::UnexpectedPass;
}

const std::vector<std::string>& platformNames() {
  static const std::vector<std::string> names = {"reference", "dx10", "ps3", "x360"};
  return names;
}

// Every platform renders: techniques::FrameRequest carries the platform and its parameters, and
// the platform layer maps the technique's logical targets to that platform's formats.
bool inFilter(const std::vector<std::string>& filter, const std::string& value) {
  return filter.empty() || std::find(filter.begin(), filter.end(), value) != filter.end();
}

bool platformHasRenderPath(const std::string& platform) { return platforms::platformFromName(platform).has_value(); }

std::string CaseKey::id() const { return technique + "/" + scene + "/" + platform + "/" + backend; }
std::string CaseKey::group() const { return technique + "/" + scene + "/" + platform; }

bool CaseKey::parse(const std::string& id, CaseKey* out, std::string* error) {
  std::vector<std::string> parts;
  std::stringstream s(id);
  std::string part;
  while (std::getline(s, part, '/')) parts.push_back(part);
  if (parts.size() != 4 || std::any_of(parts.begin(), parts.end(), [](const std::string& p) { return p.empty(); })) {
    *error = "case '" + id + "' is not technique/scene/platform/backend (e.g. forward/default/reference/gl)";
    return false;
  }
  *out = CaseKey{parts[0], parts[1], parts[2], parts[3]};
  return true;
}

}  // namespace parity::harness
