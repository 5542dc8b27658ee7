// Driver libraries loaded ahead of device creation (rhi::preloadDriverLibraries in rhi.h): what
// the backends share. Each backend names its own manifests (rhi/gl/gl_driver_libraries.cpp,
// rhi/vulkan/vk_driver_libraries.cpp), in the form its loader reads them.
#pragma once

#include <string>
#include <vector>

namespace parity::rhi {

// The value of an environment variable split at ':' (empty entries dropped); empty when unset.
std::vector<std::string> envPathList(const char* name);

// Every `*.json` in each folder, folders in the order given and files by name within one (a
// folder that does not exist is skipped); a path that is a file is taken as it is.
std::vector<std::string> jsonManifestsIn(const std::vector<std::string>& foldersOrFiles);

// The `library_path` of a loader manifest: {"ICD": {...}}, {"layer": {...}} or {"layers": [...]}
// (Vulkan's drivers and layers, glvnd's EGL vendors), resolved the way the loaders resolve it:
// a bare file name is left to the dynamic linker's search, a relative path is relative to the
// manifest's folder. `layerName`, when given, keeps only the layers of that name. A manifest
// that cannot be read gives nothing: the loader will say what is wrong with it when it reads it.
std::vector<std::string> manifestLibraries(const std::string& manifest, const std::string& layerName = "");

// dlopen()s each library (RTLD_NOW | RTLD_LOCAL: relocated now, its symbols kept out of the
// global scope) and keeps it loaded; returns those that loaded, once each.
std::vector<std::string> loadLibraries(const std::vector<std::string>& libraries);

}  // namespace parity::rhi
