// The on-disk shader cache (rhi/shader_cache.h): what one process compiles the next one reads,
// and a damaged entry is never used: it is compiled again and replaced.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "harness/run/process.h"
#include "rhi/shader_cache.h"
#include "test_support.h"

using namespace parity;
namespace fs = std::filesystem;

namespace {

class ShaderCache : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("parity-shader-cache-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    const char* old = std::getenv("PARITY_SHADER_CACHE");
    if (old) old_ = old;
    hadOld_ = old != nullptr;
    ::setenv("PARITY_SHADER_CACHE", dir_.c_str(), 1);
  }
  void TearDown() override {
    if (hadOld_) ::setenv("PARITY_SHADER_CACHE", old_.c_str(), 1);
    else ::unsetenv("PARITY_SHADER_CACHE");
    fs::remove_all(dir_);
  }
  std::vector<fs::path> entries() const {
    std::vector<fs::path> out;
    if (fs::is_directory(dir_))
      for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path());
    return out;
  }

  // Across processes, on each backend: a render fills the cache, a second render of the same
  // technique adds nothing and gives the same image; entries damaged in between are compiled again
  // and rewritten. On GL the cache also holds SPIRV-Cross's GLSL, so a hit skips the translation too.
  void rendersShareItAcrossProcesses(const std::string& backend) {
    auto render = [&](const std::string& out) {
      return harness::runProcess({PARITY_BINARY, "render", "--backend", backend, "--technique", "deferred", "-o", out}, 120);
    };
    auto read = [](const fs::path& p) { return test::readFile(p.string()); };
    const fs::path first = dir_.string() + "-1.png", second = dir_.string() + "-2.png", third = dir_.string() + "-3.png";
    harness::ProcessResult r = render(first.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::vector<fs::path> filled = entries();
    ASSERT_GT(filled.size(), 3u) << "deferred compiles more than three shaders";
    const size_t translations = std::count_if(filled.begin(), filled.end(), [&](const fs::path& p) {
      return read(p).find("spirv-cross ") != std::string::npos;  // the producer, in the key
    });
    if (backend == "gl") EXPECT_GT(translations, 3u) << "each of deferred's shaders translated to GLSL once";
    else EXPECT_EQ(translations, 0u) << "Vulkan takes the SPIR-V itself";
    std::vector<fs::file_time_type> written;
    std::vector<uintmax_t> sizes;
    for (const fs::path& p : filled) {
      written.push_back(fs::last_write_time(p));
      sizes.push_back(fs::file_size(p));
    }
    r = render(second.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(entries().size(), filled.size());
    for (size_t i = 0; i < filled.size(); ++i) EXPECT_EQ(fs::last_write_time(filled[i]), written[i]) << "rewritten on a hit";
    EXPECT_EQ(read(first), read(second));
    for (const fs::path& p : filled) fs::resize_file(p, fs::file_size(p) - 4);  // every entry damaged
    r = render(third.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(read(first), read(third));
    for (size_t i = 0; i < filled.size(); ++i) EXPECT_EQ(fs::file_size(filled[i]), sizes[i]) << "not rewritten whole";
    for (const fs::path& p : {first, second, third}) fs::remove(p);
  }
  fs::path dir_;
  std::string old_;
  bool hadOld_ = false;
};

TEST_F(ShaderCache, StoresLoadsAndRejectsDamagedEntries) {
  const std::vector<uint32_t> words = {0x07230203u, 0x00010500u, 7, 11, 13};
  EXPECT_FALSE(rhi::loadCachedWords("key a").has_value());
  rhi::storeCachedWords("key a", words);
  ASSERT_EQ(entries().size(), 1u);
  EXPECT_EQ(rhi::loadCachedWords("key a"), words);
  EXPECT_FALSE(rhi::loadCachedWords("key b").has_value()) << "another key";
  // One bit of a word flipped: the checksum no longer matches.
  {
    std::fstream f(entries()[0], std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-12, std::ios::end);
    char c = 0;
    f.read(&c, 1);
    f.seekp(-12, std::ios::end);
    c ^= 1;
    f.write(&c, 1);
  }
  EXPECT_FALSE(rhi::loadCachedWords("key a").has_value());
  rhi::storeCachedWords("key a", words);  // what the compiler does after the miss
  EXPECT_EQ(rhi::loadCachedWords("key a"), words);
  fs::resize_file(entries()[0], 20);  // truncated
  EXPECT_FALSE(rhi::loadCachedWords("key a").has_value());
  rhi::storeCachedBytes("text", "#version 450\n");  // the GL backend's translations
  EXPECT_EQ(rhi::loadCachedBytes("text"), std::optional<std::string>("#version 450\n"));
  EXPECT_FALSE(rhi::loadCachedWords("text").has_value()) << "13 bytes are not SPIR-V words";
  ::setenv("PARITY_SHADER_CACHE", "off", 1);
  EXPECT_EQ(rhi::shaderCacheDirectory(), "");
  rhi::storeCachedWords("key c", words);
  EXPECT_FALSE(rhi::loadCachedWords("key c").has_value());
}

TEST_F(ShaderCache, VulkanRendersShareItAcrossProcesses) {
  if (!test::makeDevice("vk", false)) return;
  rendersShareItAcrossProcesses("vk");
}

TEST_F(ShaderCache, GlRendersShareItAndItsTranslationsAcrossProcesses) {
  if (!test::makeDevice("gl", false)) return;
  rendersShareItAcrossProcesses("gl");
}

}  // namespace
