#include "harness/run/evidence.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "harness/compare/diagnosis.h"
#include "harness/compare/diff.h"
#include "harness/io/image_io.h"
#include "harness/run/expectations.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

bool readBound(const nlohmann::json& j, const std::string& where, EvidenceBound* b, std::string* error) {
  if (!j.is_object()) {
    *error = where + ": \"bound\" must be an object";
    return false;
  }
  static const std::vector<std::pair<std::string, std::optional<double> EvidenceBound::*>> fields = {
      {"max", &EvidenceBound::max},
      {"mean", &EvidenceBound::mean},
      {"percent", &EvidenceBound::percent},
      {"threshold", &EvidenceBound::threshold},
      {"residual_mean", &EvidenceBound::residualMean}};
  for (const auto& [name, value] : j.items()) {
    auto f = std::find_if(fields.begin(), fields.end(), [&](const auto& p) { return p.first == name; });
    if (f == fields.end()) {
      *error = where + ": unknown bound \"" + name + "\" (max, mean, percent, threshold, residual_mean)";
      return false;
    }
    if (!value.is_number() || value.get<double>() < 0) {
      *error = where + ": bound \"" + name + "\" must be a number >= 0";
      return false;
    }
    b->*(f->second) = value.get<double>();
  }
  if (b->percent.has_value() != b->threshold.has_value()) {
    *error = where + ": bound \"percent\" and \"threshold\" go together";
    return false;
  }
  if (!b->max && !b->mean && !b->percent && !b->residualMean) {
    *error = where + ": \"bound\" must set at least one of max, mean, percent, residual_mean";
    return false;
  }
  return true;
}

std::string expand(std::string text, const std::string& key) {
  const size_t a = key.find('/'), b = key.find('/', a + 1);
  const std::pair<std::string, std::string> fields[] = {
      {"{technique}", key.substr(0, a)}, {"{scene}", key.substr(a + 1, b - a - 1)}, {"{platform}", key.substr(b + 1)}};
  for (const auto& [name, value] : fields)
    for (size_t at; (at = text.find(name)) != std::string::npos;) text.replace(at, name.size(), value);
  return text;
}

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// A reference claim: the image within the bound of the reference's image.
bool checkReference(const EvidenceClaim& c, const std::string& key, const std::string& image,
                    const EvidenceContext& context, nlohmann::json* record, std::string* why) {
  const std::string refKey = expand(c.reference, key);
  (*record)["reference"] = refKey;
  if (refKey == key) {
    *why = c.source + ": the reference is the golden itself";
    return false;
  }
  const std::string refImage = context.imageOf(refKey);
  OIIO::ImageBuf a, b;
  std::string error;
  if (refImage.empty() || !readImage(refImage, &a, &error)) {
    *why = c.source + ": no image of the reference " + refKey + " (neither in the run nor golden)";
    return false;
  }
  if (!readImage(image, &b, &error)) {
    *why = error;
    return false;
  }
  DiffThresholds t;
  t.fail = t.warn = c.bound.threshold.value_or(0.0);
  const DiffResult d = diffImages(a, b, t);
  if (d.verdict == DiffVerdict::SizeMismatch || d.verdict == DiffVerdict::FileError) {
    *why = c.source + ": against " + refKey + ": " + d.message;
    return false;
  }
  nlohmann::json measured = {{"max", d.maxError}, {"mean", d.meanError}};
  if (c.bound.percent) measured["percent"] = 100.0 * d.failShare();
  std::vector<std::string> over;
  if (c.bound.max && d.maxError > *c.bound.max) over.push_back("max " + fmt(d.maxError) + " > " + fmt(*c.bound.max));
  if (c.bound.mean && d.meanError > *c.bound.mean) over.push_back("mean " + fmt(d.meanError) + " > " + fmt(*c.bound.mean));
  if (c.bound.percent && 100.0 * d.failShare() > *c.bound.percent)
    over.push_back(fmt(100.0 * d.failShare()) + "% of pixels over " + fmt(*c.bound.threshold) + " > " +
                   fmt(*c.bound.percent) + "%");
  if (!c.explainedBy.empty()) {
    std::optional<Diagnosis> diagnosis = diagnose(a, b);
    if (!diagnosis || diagnosis->cause.rfind(c.explainedBy, 0) != 0) {
      over.push_back("the diagnosis names " + (diagnosis ? "\"" + diagnosis->cause + "\"" : std::string("no cause")) +
                     ", not \"" + c.explainedBy + "\"");
    } else {
      measured["diagnosis"] = diagnosis->cause;
      measured["residual_mean"] = diagnosis->residual;
      if (c.bound.residualMean && diagnosis->residual > *c.bound.residualMean)
        over.push_back("residual mean " + fmt(diagnosis->residual) + " > " + fmt(*c.bound.residualMean));
    }
  } else if (c.bound.residualMean) {
    over.push_back("\"residual_mean\" needs \"explained_by\"");
  }
  (*record)["measured"] = measured;
  if (over.empty()) return true;
  std::string text;
  for (const auto& o : over) text += (text.empty() ? "" : ", ") + o;
  *why = c.source + ": against " + refKey + ": " + text;
  return false;
}

// A tests claim: each named test exists in its file as TEST, TEST_F or TEST_P(Suite, Name).
bool checkTests(const EvidenceClaim& c, const EvidenceContext& context, nlohmann::json* record, std::string* why) {
  for (const std::string& test : c.tests) {
    const size_t colon = test.rfind(": ");
    const size_t dot = colon == std::string::npos ? std::string::npos : test.find('.', colon);
    if (dot == std::string::npos) {
      *why = c.source + ": \"" + test + "\" is not \"FILE: Suite.Name\"";
      return false;
    }
    const fs::path file = fs::path(context.testsRoot) / test.substr(0, colon);
    const std::string suite = test.substr(colon + 2, dot - colon - 2), name = test.substr(dot + 1);
    std::ifstream in(file, std::ios::binary);
    if (!in) {
      *why = c.source + ": test file " + test.substr(0, colon) + " not found";
      return false;
    }
    std::stringstream text;
    text << in.rdbuf();
    const std::regex declaration("TEST(_F|_P)?\\(\\s*" + suite + "\\s*,\\s*" + name + "\\s*\\)");
    if (!std::regex_search(text.str(), declaration)) {
      *why = c.source + ": " + test.substr(0, colon) + " has no test " + suite + "." + name;
      return false;
    }
  }
  (*record)["tests"] = c.tests;
  (*record)["found"] = true;
  return true;
}

}  // namespace

bool loadEvidence(const std::string& file, EvidenceFile* out, std::string* error) {
  *out = {};
  const fs::path folder = fs::absolute(file).parent_path();
  out->testsRoot = (folder / "..").lexically_normal().string();
  std::error_code ec;
  if (!fs::exists(file, ec)) return true;
  nlohmann::json j;
  if (!readJsonFile(file, &j, error)) return false;
  if (!j.is_object() || !j.contains("evidence") || !j["evidence"].is_array()) {
    *error = file + ": not an evidence file (an object with an \"evidence\" array expected)";
    return false;
  }
  for (const auto& [name, value] : j.items())
    if (name != "evidence" && name != "tests_root" && name != "about") {
      *error = file + ": unknown key \"" + name + "\" (evidence, tests_root, about)";
      return false;
    }
  if (j.contains("tests_root")) {
    if (!j["tests_root"].is_string() || j["tests_root"].get<std::string>().empty()) {
      *error = file + ": \"tests_root\" must be a folder";
      return false;
    }
    out->testsRoot = (folder / j["tests_root"].get<std::string>()).lexically_normal().string();
  }
  static const std::regex testForm(R"(^[^:]+: [A-Za-z_][A-Za-z0-9_]*\.[A-Za-z_][A-Za-z0-9_]*$)");
  for (size_t i = 0; i < j["evidence"].size(); ++i) {
    const nlohmann::json& e = j["evidence"][i];
    EvidenceClaim c;
    c.source = file + ": evidence[" + std::to_string(i) + "]";
    if (!e.is_object()) {
      *error = c.source + ": must be an object";
      return false;
    }
    for (const auto& [name, value] : e.items())
      if (name != "case" && name != "except" && name != "why" && name != "reference" && name != "bound" && name != "explained_by" &&
          name != "tests") {
        *error = c.source + ": unknown key \"" + name + "\"";
        return false;
      }
    auto text = [&](const char* name, std::string* to, bool required) {
      if (!e.contains(name)) {
        if (required) *error = c.source + ": \"" + name + "\" is required";
        return !required;
      }
      if (!e[name].is_string() || e[name].get<std::string>().empty()) {
        *error = c.source + ": \"" + name + "\" must be a non-empty string";
        return false;
      }
      *to = e[name].get<std::string>();
      return true;
    };
    if (!text("case", &c.casePattern, true) || !text("why", &c.why, true) || !text("reference", &c.reference, false) ||
        !text("explained_by", &c.explainedBy, false))
      return false;
    if (e.contains("except")) {
      if (!e["except"].is_array() || e["except"].empty()) {
        *error = c.source + ": \"except\" must be a non-empty array of globs";
        return false;
      }
      for (const auto& g : e["except"]) {
        if (!g.is_string() || g.get<std::string>().empty()) {
          *error = c.source + ": \"except\": " + g.dump() + " is not a glob";
          return false;
        }
        c.except.push_back(g.get<std::string>());
      }
    }
    if (e.contains("tests")) {
      if (!e["tests"].is_array() || e["tests"].empty()) {
        *error = c.source + ": \"tests\" must be a non-empty array of \"FILE: Suite.Name\"";
        return false;
      }
      for (const auto& t : e["tests"]) {
        if (!t.is_string() || !std::regex_match(t.get<std::string>(), testForm)) {
          *error = c.source + ": \"tests\": " + t.dump() + " is not \"FILE: Suite.Name\"";
          return false;
        }
        c.tests.push_back(t.get<std::string>());
      }
    }
    if (c.reference.empty() == c.tests.empty()) {
      *error = c.source + ": give either \"reference\" (with \"bound\") or \"tests\"";
      return false;
    }
    if (!c.reference.empty()) {
      if (!e.contains("bound")) {
        *error = c.source + ": a reference claim needs a \"bound\"";
        return false;
      }
      if (!readBound(e["bound"], c.source, &c.bound, error)) return false;
    } else if (e.contains("bound") || !c.explainedBy.empty()) {
      *error = c.source + ": \"bound\" and \"explained_by\" belong to a reference claim";
      return false;
    }
    out->claims.push_back(std::move(c));
  }
  return true;
}

bool checkEvidence(const std::vector<EvidenceClaim>& claims, const std::string& key, const std::string& image,
                   const EvidenceContext& context, nlohmann::json* records, std::string* why) {
  *records = nlohmann::json::array();
  std::vector<std::string> failed;
  for (const EvidenceClaim& c : claims) {
    if (!globMatch(c.casePattern, key) ||
        std::any_of(c.except.begin(), c.except.end(), [&](const std::string& g) { return globMatch(g, key); }))
      continue;
    nlohmann::json record = {{"why", c.why}};
    std::string reason;
    bool holds;
    if (!c.reference.empty()) {
      record["kind"] = "reference";
      nlohmann::json bound;
      if (c.bound.max) bound["max"] = *c.bound.max;
      if (c.bound.mean) bound["mean"] = *c.bound.mean;
      if (c.bound.percent) bound["percent"] = *c.bound.percent, bound["threshold"] = *c.bound.threshold;
      if (c.bound.residualMean) bound["residual_mean"] = *c.bound.residualMean;
      record["bound"] = bound;
      if (!c.explainedBy.empty()) record["explained_by"] = c.explainedBy;
      holds = checkReference(c, key, image, context, &record, &reason);
    } else {
      record["kind"] = "tests";
      holds = checkTests(c, context, &record, &reason);
    }
    if (!holds) failed.push_back(reason);
    records->push_back(record);
  }
  if (records->empty()) {
    *why = "no evidence covers it (GL and Vulkan agreeing is not evidence: add a claim to evidence.json)";
    return false;
  }
  if (failed.empty()) return true;
  *why = failed.front();
  for (size_t i = 1; i < failed.size(); ++i) *why += "; " + failed[i];
  return false;
}

}  // namespace parity::harness
