// rhi::preloadDriverLibraries: after it, creating a device loads no library. The fork servers of
// `parity run` and `parity test` rely on that (every child would otherwise load and relocate the
// drivers again). And the manifest reading it shares with the loaders' rules, on planted files.
#include <gtest/gtest.h>
#include <link.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "rhi/driver_libraries.h"
#include "rhi/rhi.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace parity::rhi {
namespace {

using parity::test::allBackends;
using parity::test::BackendName;

std::set<std::string> loadedObjects() {
  std::set<std::string> names;
  ::dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* out) {
        if (info->dlpi_name && *info->dlpi_name)
          static_cast<std::set<std::string>*>(out)->insert(fs::weakly_canonical(info->dlpi_name).string());
        return 0;
      },
      &names);
  return names;
}

class DriverLibrariesTest : public ::testing::TestWithParam<std::string> {};

TEST_P(DriverLibrariesTest, AfterThePreloadCreatingADeviceLoadsNoLibrary) {
  const std::vector<std::string> preloaded = preloadDriverLibraries();
  EXPECT_FALSE(preloaded.empty());
  const std::set<std::string> before = loadedObjects();
  std::unique_ptr<Device> dev = parity::test::makeDevice(GetParam());  // validation and debug on, as the tests run
  if (!dev) return;
  // While the device lives: the loaders unload what they loaded when it is destroyed.
  std::vector<std::string> added;
  for (const std::string& name : loadedObjects())
    if (!before.count(name)) added.push_back(name);
  EXPECT_TRUE(added.empty()) << "loaded by device creation, not by the preload: " << ::testing::PrintToString(added);
}

INSTANTIATE_TEST_SUITE_P(Backends, DriverLibrariesTest, ::testing::ValuesIn(allBackends()), BackendName());

// The loaders' rules for a manifest's library_path and for a layer's name.
TEST(DriverManifests, LibraryPathsResolveAsTheLoadersResolveThem) {
  const fs::path dir = fs::temp_directory_path() / ("parity-manifests-" + std::to_string(::getpid()));
  fs::create_directories(dir / "icd.d");
  auto write = [&](const std::string& name, const std::string& text) { std::ofstream(dir / "icd.d" / name) << text; };
  write("a.json", R"({"file_format_version": "1.0.0", "ICD": {"library_path": "libbare.so.1"}})");
  write("b.json", R"({"file_format_version": "1.0.0", "ICD": {"library_path": "./sub/librel.so"}})");
  write("c.json", R"({"file_format_version": "1.0.0", "ICD": {"library_path": "/opt/abs/libabs.so"}})");
  write("d.json", R"({"file_format_version": "1.2.0", "layers": [{"name": "VK_LAYER_A", "library_path": "liba.so"},
                     {"name": "VK_LAYER_B", "library_path": "libb.so"}]})");
  write("e.json", "{ not json");
  write("notes.txt", R"({"ICD": {"library_path": "libnot_a_manifest.so"}})");
  const std::vector<std::string> manifests = jsonManifestsIn({(dir / "icd.d").string(), (dir / "missing").string()});
  ASSERT_EQ(manifests.size(), 5u);  // *.json only, by name; the missing folder is skipped
  EXPECT_EQ(fs::path(manifests[0]).filename(), "a.json");
  EXPECT_EQ(manifestLibraries(manifests[0]), std::vector<std::string>{"libbare.so.1"});
  EXPECT_EQ(manifestLibraries(manifests[1]), std::vector<std::string>{(dir / "icd.d" / "sub" / "librel.so").string()});
  EXPECT_EQ(manifestLibraries(manifests[2]), std::vector<std::string>{"/opt/abs/libabs.so"});
  EXPECT_EQ(manifestLibraries(manifests[3]), (std::vector<std::string>{"liba.so", "libb.so"}));
  EXPECT_EQ(manifestLibraries(manifests[3], "VK_LAYER_B"), std::vector<std::string>{"libb.so"});
  EXPECT_TRUE(manifestLibraries(manifests[4]).empty());
  ::setenv("PARITY_TEST_PATH_LIST", "/x::/y", 1);
  EXPECT_EQ(envPathList("PARITY_TEST_PATH_LIST"), (std::vector<std::string>{"/x", "/y"}));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace parity::rhi
