// Sections of the report that stand apart from its grid and its groups' images: the pairs of a
// group's backends, expired expectations, the run against its baseline.
#include "harness/run/report_sections.h"

#include <sstream>

#include "harness/run/baseline.h"

namespace parity::harness::report {

std::string xmlEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        // XML 1.0 forbids most control characters.
        if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t' && c != '\r') out += ' ';
        else out += c;
    }
  }
  return out;
}

std::string str(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : "";
}

std::string num(const nlohmann::json& j, const char* key) {
  if (!j.contains(key)) return "";
  const nlohmann::json& v = j[key];
  if (v.is_string()) return v.get<std::string>();
  std::ostringstream s;
  s.precision(6);
  s << v.get<double>();
  return s.str();
}

// "a vs b" of a pair of results.json's groups[].pairs.
std::string pairLabel(const nlohmann::json& pair) {
  const nlohmann::json b = pair.value("backends", nlohmann::json::array());
  return b.size() == 2 && b[0].is_string() && b[1].is_string() ? b[0].get<std::string>() + " vs " + b[1].get<std::string>()
                                                               : "?";
}

// Every pair of the group's backends, agreeing or not, and the odd one out with its diagnosis.
std::string pairsHtml(const nlohmann::json& info) {
  if (!info.contains("pairs") || !info["pairs"].is_array()) return "";
  // A group of gl and vk alone: its one pair is the metrics table's "gl vs vk" row already.
  if (info["pairs"].size() == 1 && info.contains("parity")) return "";
  std::ostringstream h;
  h << "<table class=\"pairs\"><tr><th>pair</th><th>images</th><th>rule</th><th>max</th><th>mean</th><th>pixels over</th></tr>\n";
  for (const auto& p : info["pairs"]) {
    const nlohmann::json m = p.value("metrics", nlohmann::json::object());
    h << "<tr><td>" << xmlEscape(pairLabel(p)) << "</td><td>" << (p.value("agree", false) ? "agree" : "<b>differ</b>")
      << "</td><td>" << xmlEscape(str(p, "rule")) << "</td><td>" << num(m, "max_error") << "</td><td>" << num(m, "mean_error")
      << "</td><td>" << num(m, "pixels_over_fail") << "</td></tr>\n";
  }
  h << "</table>\n";
  if (info.contains("odd_one_out") && info["odd_one_out"].is_object()) {
    const nlohmann::json& o = info["odd_one_out"];
    h << "<p class=\"odd-one-out\">odd one out: <b>" << xmlEscape(str(o, "backend")) << "</b>";
    if (o.contains("diagnosis") && o["diagnosis"].is_object())
      h << ", likely cause <b>" << xmlEscape(str(o["diagnosis"], "cause")) << "</b> ("
        << xmlEscape(str(o["diagnosis"], "detail")) << ", against " << xmlEscape(str(o, "compared_with")) << ")";
    else
      h << ", no porting bug explains its difference";
    h << "</p>\n";
  }
  return h.str();
}

// The expectations that have passed their `expires` date (results.json "expired_expectations").
std::string expiredExpectationsHtml(const nlohmann::json& results) {
  const nlohmann::json expired = results.value("expired_expectations", nlohmann::json::array());
  if (!expired.is_array() || expired.empty()) return "";
  std::ostringstream h;
  h << "<h2>Expired expectations</h2><table class=\"expired\"><tr><th>case</th><th>expected</th><th>reason</th>"
       "<th>bug</th><th>expired after</th></tr>\n";
  for (const auto& e : expired) {
    if (!e.is_object()) continue;
    h << "<tr><td>" << xmlEscape(str(e, "case")) << "</td><td>" << xmlEscape(str(e, "result") + str(e, "diagnostic"))
      << "</td><td>" << xmlEscape(str(e, "reason")) << "</td><td>" << xmlEscape(str(e, "bug")) << "</td><td>"
      << xmlEscape(str(e, "expires")) << "</td></tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

// This run against an earlier one (results.json "baseline"): what changed, case by case.
std::string baselineHtml(const nlohmann::json& results) {
  if (!results.contains("baseline") || !results["baseline"].is_object()) return "";
  const nlohmann::json& b = results["baseline"];
  std::ostringstream h;
  h << "<h2>Against baseline</h2><p class=\"baseline\">" << xmlEscape(baselineSummary(b)) << " (run "
    << xmlEscape(str(b, "run_id")) << ")</p>\n";
  const std::pair<const char*, const char*> kinds[] = {
      {"regressions", "regression"}, {"fixes", "fix"}, {"new", "new"}, {"vanished", "vanished"}};
  h << "<table class=\"baseline\"><tr><th>change</th><th>case</th><th>before</th><th>now</th><th>reason</th></tr>\n";
  for (const auto& [key, label] : kinds)
    for (const auto& c : b.value(key, nlohmann::json::array()))
      if (c.is_object())
        h << "<tr><td>" << label << "</td><td>" << xmlEscape(str(c, "id")) << "</td><td>" << xmlEscape(str(c, "before"))
          << "</td><td>" << xmlEscape(str(c, "now")) << "</td><td>" << xmlEscape(str(c, "reason")) << "</td></tr>\n";
  h << "</table>\n";
  return h.str();
}

}  // namespace parity::harness::report
