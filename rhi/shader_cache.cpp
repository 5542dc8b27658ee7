#include "rhi/shader_cache.h"

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string_view>

namespace fs = std::filesystem;

namespace parity::rhi {

namespace {

constexpr char kMagic[8] = {'P', 'S', 'H', 'C', 'A', 'C', 'H', '2'};

uint64_t hashBytes(const void* data, size_t size) {
  return std::hash<std::string_view>{}(std::string_view(static_cast<const char*>(data), size));
}

fs::path entryPath(const std::string& dir, const std::string& key) {
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.entry", static_cast<unsigned long long>(hashBytes(key.data(), key.size())));
  return fs::path(dir) / name;
}

void append(std::string& out, uint64_t v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); }

}  // namespace

std::string shaderCacheDirectory() {
  if (const char* d = std::getenv("PARITY_SHADER_CACHE")) return std::string(d) == "off" ? "" : d;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return (fs::path(x) / "parity" / "shaders").string();
  if (const char* h = std::getenv("HOME"); h && *h) return (fs::path(h) / ".cache" / "parity" / "shaders").string();
  return "";
}

std::optional<std::string> loadCachedBytes(const std::string& key) {
  const std::string dir = shaderCacheDirectory();
  if (dir.empty()) return std::nullopt;
  std::ifstream in(entryPath(dir, key), std::ios::binary);
  if (!in) return std::nullopt;
  const std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // magic | key size | key | byte count | bytes | checksum of the bytes
  size_t at = 0;
  auto take = [&](void* out, size_t n) {
    if (file.size() - at < n) return false;
    std::memcpy(out, file.data() + at, n);
    at += n;
    return true;
  };
  char magic[sizeof kMagic];
  uint64_t keySize = 0, byteCount = 0, checksum = 0;
  if (!take(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof kMagic) != 0) return std::nullopt;
  if (!take(&keySize, sizeof keySize) || keySize != key.size() || file.size() - at < keySize ||
      file.compare(at, keySize, key) != 0)
    return std::nullopt;
  at += keySize;
  if (!take(&byteCount, sizeof byteCount) || byteCount == 0 || file.size() - at < byteCount) return std::nullopt;
  std::string bytes = file.substr(at, byteCount);
  at += byteCount;
  if (!take(&checksum, sizeof checksum) || at != file.size() || checksum != hashBytes(bytes.data(), bytes.size()))
    return std::nullopt;
  return bytes;
}

void storeCachedBytes(const std::string& key, const std::string& bytes) {
  const std::string dir = shaderCacheDirectory();
  if (dir.empty() || bytes.empty()) return;
  std::error_code ec;
  fs::create_directories(dir, ec);
  std::string file(kMagic, sizeof kMagic);
  append(file, key.size());
  file += key;
  append(file, bytes.size());
  file += bytes;
  append(file, hashBytes(bytes.data(), bytes.size()));
  static std::atomic<unsigned> counter{0};
  const fs::path target = entryPath(dir, key);
  const fs::path temp = target.string() + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out || !out.write(file.data(), std::streamsize(file.size())) || !out.flush()) {
      out.close();
      fs::remove(temp, ec);
      return;
    }
  }
  fs::rename(temp, target, ec);  // atomic: a reader sees the old entry, none, or this one
  if (ec) fs::remove(temp, ec);
}

std::optional<std::vector<uint32_t>> loadCachedWords(const std::string& key) {
  std::optional<std::string> bytes = loadCachedBytes(key);
  if (!bytes || bytes->size() % 4 != 0) return std::nullopt;
  std::vector<uint32_t> words(bytes->size() / 4);
  std::memcpy(words.data(), bytes->data(), bytes->size());
  return words;
}

void storeCachedWords(const std::string& key, const std::vector<uint32_t>& words) {
  storeCachedBytes(key, std::string(reinterpret_cast<const char*>(words.data()), words.size() * 4));
}

}  // namespace parity::rhi
