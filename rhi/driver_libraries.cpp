#include "rhi/driver_libraries.h"

#include <dlfcn.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace parity::rhi {

std::vector<std::string> envPathList(const char* name) {
  std::vector<std::string> out;
  const char* value = std::getenv(name);
  if (!value) return out;
  std::istringstream s(value);
  for (std::string item; std::getline(s, item, ':');)
    if (!item.empty()) out.push_back(item);
  return out;
}

std::vector<std::string> jsonManifestsIn(const std::vector<std::string>& foldersOrFiles) {
  std::vector<std::string> out;
  for (const std::string& path : foldersOrFiles) {
    std::error_code ec;
    if (fs::is_regular_file(path, ec)) {
      out.push_back(path);
      continue;
    }
    std::vector<std::string> files;
    for (fs::directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec))
      if (it->path().extension() == ".json") files.push_back(it->path().string());
    std::sort(files.begin(), files.end());
    out.insert(out.end(), files.begin(), files.end());
  }
  return out;
}

std::vector<std::string> manifestLibraries(const std::string& manifest, const std::string& layerName) {
  std::ifstream in(manifest);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (!j.is_object()) return {};
  std::vector<nlohmann::json> entries;
  if (j.contains("ICD")) entries.push_back(j["ICD"]);
  if (j.contains("layer")) entries.push_back(j["layer"]);
  if (j.contains("layers") && j["layers"].is_array())
    for (const auto& l : j["layers"]) entries.push_back(l);
  std::vector<std::string> out;
  for (const nlohmann::json& e : entries) {
    if (!e.is_object() || !e.contains("library_path") || !e["library_path"].is_string()) continue;
    if (!layerName.empty() && e.value("name", "") != layerName) continue;
    const std::string path = e["library_path"];
    if (path.find('/') == std::string::npos || fs::path(path).is_absolute()) out.push_back(path);
    else out.push_back((fs::path(manifest).parent_path() / path).lexically_normal().string());
  }
  return out;
}

std::vector<std::string> loadLibraries(const std::vector<std::string>& libraries) {
  std::vector<std::string> loaded;
  std::set<std::string> seen;
  for (const std::string& lib : libraries) {
    if (!seen.insert(lib).second) continue;
    // Never closed: the point is that the library stays mapped for whoever loads it next.
    if (::dlopen(lib.c_str(), RTLD_NOW | RTLD_LOCAL)) loaded.push_back(lib);
  }
  return loaded;
}

}  // namespace parity::rhi
