// The libraries an EGL display loads when it is initialised, for rhi::preloadDriverLibraries:
// glvnd's EGL and its vendors, found the way glvnd finds them (__EGL_VENDOR_LIBRARY_FILENAMES
// replaces the manifest folders, __EGL_VENDOR_LIBRARY_DIRS the default ones), then Mesa's DRI
// driver from LIBGL_DRIVERS_PATH or the `dri` folder beside Mesa's EGL vendor library. The
// surfaceless display without a render node runs llvmpipe from swrast_dri.so; Mesa's DRI drivers
// are one library under several names, so a GPU's driver of the same Mesa is that library too.
#include <dlfcn.h>
#include <link.h>

#include <climits>
#include <filesystem>
#include <string>
#include <vector>

#include "rhi/backends.h"
#include "rhi/driver_libraries.h"

namespace fs = std::filesystem;

namespace parity::rhi {

std::vector<std::string> preloadGlDriverLibraries() {
  std::vector<std::string> vendorManifests = envPathList("__EGL_VENDOR_LIBRARY_FILENAMES");
  if (vendorManifests.empty()) {
    std::vector<std::string> dirs = envPathList("__EGL_VENDOR_LIBRARY_DIRS");
    if (dirs.empty()) dirs = {"/etc/glvnd/egl_vendor.d", "/usr/share/glvnd/egl_vendor.d"};
    vendorManifests = jsonManifestsIn(dirs);
  }
  std::vector<std::string> vendors;
  for (const std::string& m : vendorManifests)
    for (const std::string& l : manifestLibraries(m)) vendors.push_back(l);
  std::vector<std::string> libs = {"libEGL.so.1"};
  libs.insert(libs.end(), vendors.begin(), vendors.end());
  std::vector<std::string> loaded = loadLibraries(libs);

  std::vector<std::string> driverDirs = envPathList("LIBGL_DRIVERS_PATH");
  if (driverDirs.empty())
    for (const std::string& v : vendors) {
      if (v.find("mesa") == std::string::npos) continue;
      void* handle = ::dlopen(v.c_str(), RTLD_LAZY | RTLD_NOLOAD);
      char origin[PATH_MAX] = {};
      if (handle && ::dlinfo(handle, RTLD_DI_ORIGIN, origin) == 0) driverDirs.push_back(std::string(origin) + "/dri");
      if (handle) ::dlclose(handle);  // the reference RTLD_NOLOAD took, not the load's own
    }
  std::vector<std::string> drivers;
  for (const std::string& d : driverDirs)
    if (std::error_code ec; fs::exists(fs::path(d) / "swrast_dri.so", ec)) drivers.push_back((fs::path(d) / "swrast_dri.so").string());
  for (const std::string& l : loadLibraries(drivers)) loaded.push_back(l);
  return loaded;
}

}  // namespace parity::rhi
