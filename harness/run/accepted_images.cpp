#include "harness/run/accepted_images.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "harness/io/image_io.h"
#include "harness/run/expectations.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

std::string acceptedImagePath(const std::string& goldenDir, const std::string& groupKey, const std::string& name) {
  return (fs::path(goldenDir) / (groupKey + "." + name + ".png")).string();
}

bool isAcceptedName(const std::string& name) {
  if (name.empty() || name.front() == '.' || name.back() == '.' || name.find("..") != std::string::npos) return false;
  return std::all_of(name.begin(), name.end(), [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.';
  });
}

bool checkAccepted(const nlohmann::json& accepted, const std::string& manifestPath, std::string* error) {
  const std::string where = manifestPath + ": accepted";
  if (!accepted.is_object()) {
    *error = where + ": must be an object mapping technique/scene/platform to accepted images";
    return false;
  }
  for (const auto& [key, byName] : accepted.items()) {
    if (!byName.is_object()) {
      *error = where + ": " + key + ": must be an object mapping names to accepted images";
      return false;
    }
    for (const auto& [name, entry] : byName.items()) {
      const std::string at = where + ": " + key + ": " + name;
      // The name is part of a file name: no folder, nothing hidden.
      if (!isAcceptedName(name)) {
        *error = at + ": a name is letters, digits, '-', '_' and inner dots";
        return false;
      }
      if (!entry.is_object() || !entry.contains("devices") || !entry["devices"].is_array() || entry["devices"].empty()) {
        *error = at + ": needs \"devices\", a non-empty array of device globs";
        return false;
      }
      for (const auto& d : entry["devices"])
        if (!d.is_string() || d.get<std::string>().empty()) {
          *error = at + ": devices: " + d.dump() + " is not a device glob";
          return false;
        }
    }
  }
  return true;
}

std::vector<std::pair<std::string, nlohmann::json>> acceptedFor(const nlohmann::json& manifest, const std::string& groupKey,
                                                                 const std::string& device) {
  std::vector<std::pair<std::string, nlohmann::json>> found;
  if (!manifest.contains("accepted") || !manifest["accepted"].contains(groupKey)) return found;
  for (const auto& [name, entry] : manifest["accepted"][groupKey].items())
    for (const auto& glob : entry["devices"])
      if (globMatch(glob.get<std::string>(), device)) {
        found.emplace_back(name, entry);
        break;
      }
  return found;
}

double flipPercentile(const FlipResult& flip, double p) {
  if (flip.errorMap.empty()) return 0;
  std::vector<float> v = flip.errorMap;
  const size_t rank = static_cast<size_t>(std::ceil(p / 100.0 * static_cast<double>(v.size())));
  const size_t at = std::min(v.size() - 1, rank == 0 ? 0 : rank - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(at), v.end());
  return v[at];
}

ImageJudgement judgeImage(const std::string& image, const std::string& accepted, const Tolerance& t) {
  ImageJudgement r;
  r.diff = diffFiles(image, accepted, t.golden);
  OIIO::ImageBuf a, b;
  std::string err;
  r.images = r.diff.verdict != DiffVerdict::SizeMismatch && r.diff.verdict != DiffVerdict::FileError &&
             readImage(image, &a, &err) && readImage(accepted, &b, &err);
  if (!r.images) {
    r.summary = summaryLine(r.diff);
    return r;
  }
  if (r.diff.maxError > 0) {
    r.flip = computeLdrFlip(b, a);
  } else {  // identical: FLIP is zero by definition, no need to filter
    r.flip.ok = true;
    r.flip.pixelsPerDegree = flipDefaultPixelsPerDegree();
  }
  std::vector<std::string> over;
  if (!t.budget) {
    if (r.diff.verdict == DiffVerdict::Fail) over.push_back(summaryLine(r.diff));
    if (r.flip.ok && r.flip.mean > t.flipMean)
      over.push_back("FLIP mean " + fmt(r.flip.mean) + " (tolerance " + fmt(t.flipMean) + ")");
  } else {
    const Budget& budget = *t.budget;
    nlohmann::json measured = nlohmann::json::object();
    if (budget.fuzzy) {
      // The reftest rule counts every pixel with a channel off by a step, and the largest step.
      DiffThresholds step;
      step.fail = step.warn = 0.5 / 255.0;
      const DiffResult f = diffImages(b, a, step);
      const long maxDifference = std::lround(f.maxError * 255.0);
      const long long pixels = static_cast<long long>(f.failPixels);
      measured["fuzzy"] = {{"max_difference", maxDifference}, {"pixels", pixels}};
      if (maxDifference > budget.fuzzy->maxDifference)
        over.push_back("max difference " + std::to_string(maxDifference) + " > " + std::to_string(budget.fuzzy->maxDifference));
      if (pixels > budget.fuzzy->pixels)
        over.push_back(std::to_string(pixels) + " differing pixels > " + std::to_string(budget.fuzzy->pixels));
    }
    if (budget.flipPercentile) {
      const double p = budget.flipPercentile->p;
      if (!r.flip.ok) {
        over.push_back("no FLIP: " + r.flip.error);
      } else {
        const double value = flipPercentile(r.flip, p);
        measured["flip_percentile"] = {{"p", p}, {"value", value}};
        if (value > budget.flipPercentile->max)
          over.push_back("FLIP p" + fmt(p) + " " + fmt(value) + " > " + fmt(budget.flipPercentile->max));
      }
    }
    r.budget = toJson(budget);
    r.budget["measured"] = measured;
    r.budget["pass"] = over.empty();
    if (!over.empty()) over.front() = "budget " + budget.name + ": " + over.front();
  }
  r.pass = over.empty();
  for (const std::string& o : over) r.summary += (r.summary.empty() ? "" : ", ") + o;
  return r;
}

}  // namespace parity::harness
