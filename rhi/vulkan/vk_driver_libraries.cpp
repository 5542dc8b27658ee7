// The libraries the Vulkan loader loads when an instance is created, found the way the loader
// finds them on Linux (its manifest search: VK_DRIVER_FILES / VK_ICD_FILENAMES replace the
// driver folders, VK_ADD_DRIVER_FILES adds to them, then the XDG configuration and data folders),
// for rhi::preloadDriverLibraries. The loader loads every driver it finds to enumerate their
// devices, and every implicit layer; the one explicit layer this backend enables is validation.
#include <cstdlib>
#include <string>
#include <vector>

#include "rhi/backends.h"
#include "rhi/driver_libraries.h"

namespace parity::rhi {

namespace {

// The loader's search folders for one kind of manifest ("icd.d", "implicit_layer.d", ...).
std::vector<std::string> loaderFolders(const std::string& kind) {
  auto orDefault = [](const char* name, const std::string& fallback) {
    std::vector<std::string> v = envPathList(name);
    if (v.empty() && !fallback.empty()) v.push_back(fallback);
    return v;
  };
  const char* home = std::getenv("HOME");
  const std::string homeDir = home ? home : "";
  std::vector<std::string> roots = orDefault("XDG_CONFIG_HOME", homeDir.empty() ? "" : homeDir + "/.config");
  for (const std::string& r : orDefault("XDG_CONFIG_DIRS", "/etc/xdg")) roots.push_back(r);
  roots.push_back("/etc");
  for (const std::string& r : orDefault("XDG_DATA_HOME", homeDir.empty() ? "" : homeDir + "/.local/share")) roots.push_back(r);
  std::vector<std::string> data = envPathList("XDG_DATA_DIRS");
  if (data.empty()) data = {"/usr/local/share", "/usr/share"};
  roots.insert(roots.end(), data.begin(), data.end());
  std::vector<std::string> folders;
  for (const std::string& r : roots) folders.push_back(r + "/vulkan/" + kind);
  return folders;
}

}  // namespace

std::vector<std::string> preloadVkDriverLibraries() {
  std::vector<std::string> libs = {"libvulkan.so.1"};
  std::vector<std::string> drivers = envPathList("VK_ADD_DRIVER_FILES");
  std::vector<std::string> replaced = envPathList("VK_DRIVER_FILES");
  if (replaced.empty()) replaced = envPathList("VK_ICD_FILENAMES");
  for (const std::string& d : replaced.empty() ? loaderFolders("icd.d") : replaced) drivers.push_back(d);
  for (const std::string& m : jsonManifestsIn(drivers))
    for (const std::string& l : manifestLibraries(m)) libs.push_back(l);
  for (const std::string& m : jsonManifestsIn(loaderFolders("implicit_layer.d")))
    for (const std::string& l : manifestLibraries(m)) libs.push_back(l);
  std::vector<std::string> explicitLayers = envPathList("VK_LAYER_PATH");
  for (const std::string& f : loaderFolders("explicit_layer.d")) explicitLayers.push_back(f);
  for (const std::string& m : jsonManifestsIn(explicitLayers))
    for (const std::string& l : manifestLibraries(m, "VK_LAYER_KHRONOS_validation")) libs.push_back(l);
  return loadLibraries(libs);
}

}  // namespace parity::rhi
