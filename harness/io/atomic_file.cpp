#include "harness/io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>

#include "harness/run/expectations.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

constexpr const char* kPrefix = ".parity-tmp-";

// The pid in a temporary sibling's name, or 0 when the name is not one.
pid_t writerOf(const std::string& name) {
  if (name.rfind(kPrefix, 0) != 0) return 0;
  const char* digits = name.c_str() + std::strlen(kPrefix);
  char* end = nullptr;
  long pid = std::strtol(digits, &end, 10);
  if (end == digits || *end != '-' || pid <= 0) return 0;
  return static_cast<pid_t>(pid);
}

bool processExists(pid_t pid) {
  // EPERM: it exists but belongs to someone else, so it may still be writing.
  return ::kill(pid, 0) == 0 || errno != ESRCH;
}

}  // namespace

void atomicWriteStep() {
  static const long killAt = [] {
    const char* v = std::getenv("PARITY_KILL_AT_WRITE_STEP");
    return v ? std::atol(v) : 0L;
  }();
  static std::atomic<long> steps{0};
  if (killAt > 0 && ++steps == killAt) ::raise(SIGKILL);
}

std::string temporarySibling(const std::string& target) {
  fs::path t(target);
  std::random_device rd;
  fs::path dir = t.has_parent_path() ? t.parent_path() : fs::path(".");
  return (dir / (kPrefix + std::to_string(::getpid()) + "-" + std::to_string(rd()) + "-" + t.filename().string())).string();
}

bool writeFileAtomic(const std::string& path, const std::string& text, std::string* error) {
  fs::path target(path);
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  std::string tmp = temporarySibling(path);
  // O_EXCL | O_NOFOLLOW: never write through a file or link someone planted under that name.
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) {
    *error = path + ": cannot write (" + std::strerror(errno) + ")";
    return false;
  }
  atomicWriteStep();
  auto writeAll = [fd](const char* data, size_t size) {
    while (size > 0) {
      ssize_t n = ::write(fd, data, size);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        if (n == 0) errno = ENOSPC;
        return false;
      }
      data += n;
      size -= static_cast<size_t>(n);
    }
    return true;
  };
  // Half, then the rest: a kill between them leaves a truncated temporary, never a target.
  size_t half = text.size() / 2;
  bool ok = writeAll(text.data(), half);
  if (ok) atomicWriteStep();
  ok = ok && writeAll(text.data() + half, text.size() - half) && ::fsync(fd) == 0;
  int why = ok ? 0 : errno;
  if (::close(fd) != 0 && ok) {
    ok = false;
    why = errno;
  }
  if (ok) {
    atomicWriteStep();
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
      ok = false;
      why = errno;
    }
  }
  if (!ok) {
    std::remove(tmp.c_str());
    *error = path + ": cannot write (" + std::strerror(why) + ")";
    return false;
  }
  atomicWriteStep();
  return true;
}

bool copyFileAtomic(const std::string& from, const std::string& to, std::string* error) {
  std::string text;
  if (!readTextFile(from, &text, error)) return false;
  return writeFileAtomic(to, text, error);
}

int removeStaleTemporaries(const std::string& folder, bool recursive) {
  int removed = 0;
  std::error_code ec;
  auto consider = [&](const fs::directory_entry& e) {
    std::error_code ec2;
    if (!e.is_regular_file(ec2) || e.is_symlink(ec2)) return;
    pid_t pid = writerOf(e.path().filename().string());
    if (pid == 0 || processExists(pid)) return;
    if (fs::remove(e.path(), ec2)) ++removed;
  };
  if (recursive) {
    // Symlinked folders are not followed: cleaning never reaches outside the folder.
    for (fs::recursive_directory_iterator it(folder, fs::directory_options::skip_permission_denied, ec), end;
         !ec && it != end; it.increment(ec))
      consider(*it);
  } else {
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) consider(*it);
  }
  return removed;
}

}  // namespace parity::harness
