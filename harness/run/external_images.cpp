#include "harness/run/external_images.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "harness/compare/diff.h"
#include "harness/io/image_io.h"

namespace parity::harness {

namespace fs = std::filesystem;

namespace {

constexpr const char* kRepeatSuffix = ".repeat";

bool readDevices(const std::string& dir, nlohmann::json* devices, std::string* error) {
  const fs::path file = fs::path(dir) / "devices.json";
  std::error_code ec;
  *devices = nlohmann::json::object();
  if (!fs::exists(file, ec)) return true;
  std::ifstream in(file);
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    *error = file.string() + ": not a JSON object of backends";
    return false;
  }
  for (const auto& [backend, d] : j.items())
    if (!d.is_object() || (d.contains("renderer") && !d["renderer"].is_string()) ||
        (d.contains("driver") && !d["driver"].is_string()) || (d.contains("api") && !d["api"].is_string())) {
      *error = file.string() + ": backend '" + backend + "' must be an object of strings renderer, driver, api";
      return false;
    }
  *devices = j;
  return true;
}

}  // namespace

std::vector<CaseKey> enumerateImageCases(const std::string& dir, const RunFilters& f, const Shard& shard,
                                         std::string* error) {
  error->clear();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    *error = dir + ": --images needs a folder of <technique>/<scene>/<platform>/<backend>.png";
    return {};
  }
  nlohmann::json devices;
  if (!readDevices(dir, &devices, error)) return {};
  std::map<std::string, std::set<std::string>> groups;  // technique/scene/platform -> backends
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (!it->is_regular_file() || it->path().extension() != ".png") continue;
    const fs::path rel = fs::relative(it->path(), dir);
    const std::string stem = it->path().stem().string();
    if (stem.size() > 7 && stem.substr(stem.size() - 7) == kRepeatSuffix) continue;
    if (std::distance(rel.begin(), rel.end()) != 4) {
      *error = it->path().string() + ": not at <technique>/<scene>/<platform>/<backend>.png";
      return {};
    }
    groups[rel.parent_path().generic_string()].insert(stem);
  }
  if (ec) {
    *error = dir + ": " + ec.message();
    return {};
  }
  if (groups.empty()) {
    *error = dir + ": no image at <technique>/<scene>/<platform>/<backend>.png";
    return {};
  }
  const std::set<std::string> wanted(f.cases.begin(), f.cases.end());
  std::vector<CaseKey> cases;
  size_t groupIndex = 0;
  for (const auto& [group, backends] : groups) {
    CaseKey k;
    if (!CaseKey::parse(group + "/gl", &k, error)) return {};
    if (!inFilter(f.techniques, k.technique) || !inFilter(f.scenes, k.scene) || !inFilter(f.platforms, k.platform))
      continue;
    const bool mine = static_cast<int>(groupIndex++ % static_cast<size_t>(shard.count)) == shard.index;
    for (const std::string& b : backends) {
      k.backend = b;
      if (!inFilter(f.backends, b) || (!wanted.empty() && !wanted.count(k.id()))) continue;
      if (mine) cases.push_back(k);
    }
  }
  return cases;
}

bool loadExternalCase(const std::string& dir, const CaseKey& key, const std::string& imageOut, nlohmann::json* worker,
                      std::string* error) {
  const fs::path folder = fs::path(dir) / key.technique / key.scene / key.platform;
  const fs::path image = folder / (key.backend + ".png");
  OIIO::ImageBuf img;
  if (!readImage(image.string(), &img, error)) return false;
  std::error_code ec;
  fs::copy_file(image, imageOut, fs::copy_options::overwrite_existing, ec);
  if (ec) {
    *error = imageOut + ": cannot write: " + ec.message();
    return false;
  }
  nlohmann::json devices;
  if (!readDevices(dir, &devices, error)) return false;
  nlohmann::json w = nlohmann::json::object();
  const nlohmann::json device = devices.value(key.backend, nlohmann::json::object());
  w["renderer"] = device.value("renderer", "external (" + key.backend + ")");
  w["driver"] = device.value("driver", "");
  w["api"] = device.value("api", "");
  w["external"] = image.string();
  // Determinism is known only when the other program rendered the case twice.
  const fs::path repeat = folder / (key.backend + kRepeatSuffix + ".png");
  w["renders"] = 1;
  w["deterministic"] = true;
  if (fs::exists(repeat, ec)) {
    DiffThresholds exact;
    exact.fail = exact.warn = 0.0;
    DiffResult d = diffFiles(image.string(), repeat.string(), exact);
    w["renders"] = 2;
    w["deterministic"] = d.verdict == DiffVerdict::Pass && d.maxError == 0.0;
    if (!w["deterministic"].get<bool>()) w["differing_pixels"] = d.failPixels;
  }
  *worker = w;
  return true;
}

}  // namespace parity::harness
