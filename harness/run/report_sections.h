// Parts of the HTML report (harness/run/report.h) kept apart from its grid and group pages, and
// the helpers they share with them.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace parity::harness::report {

// Text escaped for XML and HTML (control characters XML 1.0 forbids become spaces).
std::string xmlEscape(const std::string& s);
// j[key] when it is a string, "" otherwise.
std::string str(const nlohmann::json& j, const char* key);
// j[key] as a number (6 significant digits) or the string it holds; "" when absent.
std::string num(const nlohmann::json& j, const char* key);

// "a vs b" of one of results.json's groups[].pairs.
std::string pairLabel(const nlohmann::json& pair);
// A group's pairs of backends (agree or differ, by which rule) and its odd one out with the
// diagnosis of its difference; "" for a group without pairs.
std::string pairsHtml(const nlohmann::json& group);
// results.json's "expired_expectations" as a table; "" when there are none.
std::string expiredExpectationsHtml(const nlohmann::json& results);
// results.json's "baseline": the summary and every regression, fix, new and vanished case.
std::string baselineHtml(const nlohmann::json& results);

}  // namespace parity::harness::report
