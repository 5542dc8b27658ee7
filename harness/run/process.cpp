#include <filesystem>
#include <sstream>
#include "harness/run/process.h"

#include <fcntl.h>
#include <malloc.h>
#include <poll.h>
#include <signal.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__)
#define PARITY_HAS_LSAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PARITY_HAS_LSAN 1
#endif
#endif
#ifndef PARITY_HAS_LSAN
#define PARITY_HAS_LSAN 0
#endif
#if PARITY_HAS_LSAN
#include <sanitizer/lsan_interface.h>
#endif

#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <mutex>
#include <vector>

namespace parity::harness {

std::string findInPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream s(path ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(s, dir, ':')) {
    std::filesystem::path p = std::filesystem::path(dir) / name;
    if (::access(p.c_str(), X_OK) == 0) return p.string();
  }
  return "";
}

std::vector<nlohmann::json> resultLines(const std::string& out, const char* field) {
  std::vector<nlohmann::json> lines;
  std::istringstream in(out);
  for (std::string l; std::getline(in, l);)
    if (!l.empty() && l[0] == '{') {
      nlohmann::json j = nlohmann::json::parse(l, nullptr, false);
      if (j.is_object() && j.contains(field) && j[field].is_string()) lines.push_back(std::move(j));
    }
  return lines;
}

std::string selfExecutable() {
  char buf[PATH_MAX];
  ssize_t n = ::readlink("/proc/self/exe", buf, sizeof(buf) - 1);
  if (n <= 0) return "parity";
  buf[n] = '\0';
  return buf;
}

namespace {

// The fork server of this process (startForkServer): a socket to it, and the lock that keeps
// the requests of several threads apart.
struct ForkServer {
  int socket = -1;
  std::mutex mutex;
};
ForkServer& forkServer() {
  static ForkServer server;
  return server;
}

// A request carries the child's arguments (NUL-separated) and three descriptors: the write ends
// of its stdout and stderr pipes and of a status pipe, on which the child's pid and then its wait
// status come back.
constexpr size_t kMaxRequest = 256 * 1024;
constexpr int kRequestFds = 3;

// The message of one request, sent or received: the arguments' buffer and room for the
// descriptors.
struct RequestMessage {
  iovec iov;
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int) * kRequestFds)] = {};
  msghdr msg{};
  RequestMessage(void* data, size_t size) : iov{data, size} {
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof(control);
  }
  RequestMessage(const RequestMessage&) = delete;
  RequestMessage& operator=(const RequestMessage&) = delete;
  // The descriptors' header when the message carries exactly kRequestFds of them.
  cmsghdr* descriptors() {
    cmsghdr* c = CMSG_FIRSTHDR(&msg);
    bool ok = c && c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_RIGHTS &&
              c->cmsg_len == CMSG_LEN(sizeof(int) * kRequestFds);
    return ok ? c : nullptr;
  }
};

bool sendRequest(int socket, const std::vector<std::string>& argv, const int (&fds)[kRequestFds]) {
  std::string payload;
  for (const std::string& a : argv) payload.append(a).push_back('\0');
  if (payload.size() > kMaxRequest) return false;
  RequestMessage m(payload.data(), payload.size());
  cmsghdr* c = CMSG_FIRSTHDR(&m.msg);
  c->cmsg_level = SOL_SOCKET;
  c->cmsg_type = SCM_RIGHTS;
  c->cmsg_len = CMSG_LEN(sizeof(int) * kRequestFds);
  std::memcpy(CMSG_DATA(c), fds, sizeof(int) * kRequestFds);
  // MSG_NOSIGNAL: a server that is gone is an error here, not a SIGPIPE.
  return ::sendmsg(socket, &m.msg, MSG_NOSIGNAL) == static_cast<ssize_t>(payload.size());
}

// How a forked child ends. Not exit(): the libraries' exit handlers would run, and some wait for
// threads that exist only in the process that loaded them (log4cplus, under OpenImageIO, starts a
// pool while the libraries load, before main(), and joins it at exit: a forked child would wait
// forever). What must happen at exit happens here: buffered output is written, and in a sanitizer
// build LeakSanitizer's check runs (a finding aborts the child, as at a normal exit).
[[noreturn]] void quickExit(int code) {
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
#if PARITY_HAS_LSAN
  __lsan_do_leak_check();
#endif
  ::_exit(code);
}

// The server's loop: one request at a time, each forked once. The server writes the child's pid
// on the request's status pipe at once, and its wait status when it ends: SIGCHLD is blocked and
// read from a signalfd beside the socket, so the server never blocks in a wait. (It used to fork a
// waiter that forked the child: two copies of a process that holds the drivers, not one.)
[[noreturn]] void serveForks(int socket, int (*entry)(int, char**)) {
  sigset_t childSignal, previousMask;
  sigemptyset(&childSignal);
  sigaddset(&childSignal, SIGCHLD);
  ::sigprocmask(SIG_BLOCK, &childSignal, &previousMask);
  const int childEnded = ::signalfd(-1, &childSignal, SFD_CLOEXEC | SFD_NONBLOCK);
  if (childEnded < 0) ::_exit(1);  // the parent then starts its processes itself
  // The server and its children must not hold the parent's stdout and stderr open: whoever reads
  // the parent's output would wait for them too. The children get their own pipes.
  int devNull = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (devNull >= 0) {
    ::dup2(devNull, 1);
    ::dup2(devNull, 2);
    ::close(devNull);
  }
  std::map<pid_t, int> statusPipes;  // running children
  std::vector<char> buffer(kMaxRequest);
  for (;;) {
    pollfd ready[2] = {{socket, POLLIN, 0}, {childEnded, POLLIN, 0}};
    if (::poll(ready, 2, -1) < 0) {
      if (errno == EINTR) continue;
      ::_exit(1);
    }
    if (ready[1].revents & POLLIN) {
      signalfd_siginfo info;
      while (::read(childEnded, &info, sizeof(info)) > 0) {
      }
      int status = 0;
      for (pid_t ended; (ended = ::waitpid(-1, &status, WNOHANG)) > 0;) {
        auto it = statusPipes.find(ended);
        if (it == statusPipes.end()) continue;
        if (::write(it->second, &status, sizeof(status)) != sizeof(status)) {
          // the parent stopped waiting for it
        }
        ::close(it->second);
        statusPipes.erase(it);
      }
    }
    if (!(ready[0].revents & (POLLIN | POLLHUP | POLLERR))) continue;
    RequestMessage m(buffer.data(), buffer.size());
    ssize_t got = ::recvmsg(socket, &m.msg, MSG_CMSG_CLOEXEC);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) ::_exit(0);  // the parent is gone
    cmsghdr* c = m.descriptors();
    if (!c) continue;
    int fds[kRequestFds];
    std::memcpy(fds, CMSG_DATA(c), sizeof(fds));
    pid_t child = ::fork();
    if (child == 0) {
      ::setpgid(0, 0);  // own process group: a timeout kills the child and anything it started
      ::close(socket);
      ::close(childEnded);
      for (const auto& [pid, fd] : statusPipes) ::close(fd);
      ::sigprocmask(SIG_SETMASK, &previousMask, nullptr);
      ::dup2(fds[0], 1);
      ::dup2(fds[1], 2);
      for (int fd : fds) ::close(fd);
      std::vector<char*> args;
      for (ssize_t i = 0; i < got; i += static_cast<ssize_t>(std::strlen(buffer.data() + i)) + 1)
        args.push_back(buffer.data() + i);
      args.push_back(nullptr);
      int code = entry(static_cast<int>(args.size()) - 1, args.data());
      quickExit(code);
    }
    if (child > 0) ::setpgid(child, child);  // before the parent can kill the group on a timeout
    ::close(fds[0]);
    ::close(fds[1]);
    const bool told = ::write(fds[2], &child, sizeof(child)) == sizeof(child);
    if (child > 0 && told) {
      statusPipes[child] = fds[2];
    } else {
      ::close(fds[2]);  // no child, or nobody to tell: the parent reads a short status
    }
  }
}

bool readFully(int fd, void* data, size_t size) {
  char* p = static_cast<char*>(data);
  while (size > 0) {
    ssize_t n = ::read(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= static_cast<size_t>(n);
  }
  return true;
}

// Reads the child's stdout and stderr until both close, or until the timeout, when the child's
// process group is killed.
void collectOutput(pid_t pid, int outFd, int errFd, double timeoutSeconds, TimeoutScope scope, ProcessResult& r) {
  auto start = std::chrono::steady_clock::now();  // of the run, or of the wait for the next line
  pollfd fds[2] = {{outFd, POLLIN, 0}, {errFd, POLLIN, 0}};
  int open = 2;
  char buf[4096];
  while (open > 0) {
    int waitMs = 200;
    if (timeoutSeconds > 0) {
      double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (elapsed > timeoutSeconds) {
        r.timedOut = true;
        ::kill(-pid, SIGKILL);
        break;
      }
    }
    int n = ::poll(fds, 2, waitMs);
    if (n < 0 && errno != EINTR) break;
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      ssize_t got = ::read(fds[i].fd, buf, sizeof(buf));
      if (got > 0) {
        (i == 0 ? r.out : r.err).append(buf, static_cast<size_t>(got));
        if (i == 0 && scope == TimeoutScope::EachLine && std::memchr(buf, '\n', static_cast<size_t>(got)))
          start = std::chrono::steady_clock::now();
      } else {
        ::close(fds[i].fd);
        fds[i].fd = -1;
        --open;
      }
    }
  }
  for (auto& f : fds)
    if (f.fd >= 0) ::close(f.fd);
}

void decodeStatus(int status, ProcessResult& r) {
  if (r.timedOut) return;
  if (WIFSIGNALED(status)) {
    r.crashed = true;
    r.signal = WTERMSIG(status);
  } else if (WIFEXITED(status)) {
    r.exitCode = WEXITSTATUS(status);
  }
}

// runProcess through the fork server. False when the server cannot take the request (then the
// caller starts the process itself).
bool runThroughForkServer(const std::vector<std::string>& argv, double timeoutSeconds, TimeoutScope scope, ProcessResult& r) {
  ForkServer& server = forkServer();
  int pipes[3][2];  // stdout, stderr, status
  for (int i = 0; i < 3; ++i)
    if (::pipe2(pipes[i], O_CLOEXEC) != 0) {
      for (int k = 0; k < i; ++k)
        for (int fd : pipes[k]) ::close(fd);
      return false;
    }
  int(&outPipe)[2] = pipes[0];
  int(&errPipe)[2] = pipes[1];
  int(&statusPipe)[2] = pipes[2];
  const int sent[kRequestFds] = {outPipe[1], errPipe[1], statusPipe[1]};
  bool ok;
  {
    std::lock_guard<std::mutex> lock(server.mutex);
    ok = server.socket >= 0 && sendRequest(server.socket, argv, sent);
  }
  for (int fd : sent) ::close(fd);
  pid_t pid = -1;
  if (ok) ok = readFully(statusPipe[0], &pid, sizeof(pid)) && pid > 0;
  if (!ok) {
    for (int fd : {outPipe[0], errPipe[0], statusPipe[0]}) ::close(fd);
    return false;
  }
  collectOutput(pid, outPipe[0], errPipe[0], timeoutSeconds, scope, r);
  int status = 0;
  if (!readFully(statusPipe[0], &status, sizeof(status))) r.startError = "the fork server lost the child";
  ::close(statusPipe[0]);
  decodeStatus(status, r);
  return true;
}

}  // namespace

void fixAllocatorThresholds() {
  // Blocks up to 32 MiB (glibc's largest mmap threshold on 64-bit) come from the heap, and the
  // heap shrinks only when 128 MiB at its top are free. Setting either disables the adjustment.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 128 << 20);
}

void startForkServer(int (*entry)(int, char**), void (*warm)()) {
  ForkServer& server = forkServer();
  if (server.socket >= 0) return;
  int sv[2];
  if (::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, sv) != 0) return;
  std::fflush(nullptr);  // nothing buffered is written twice
  pid_t pid = ::fork();
  if (pid == 0) {
    ::close(sv[0]);
    if (warm) warm();
    serveForks(sv[1], entry);
  }
  ::close(sv[1]);
  if (pid < 0) {
    ::close(sv[0]);
    return;
  }
  server.socket = sv[0];
}

ProcessResult runProcess(const std::vector<std::string>& argv, double timeoutSeconds, TimeoutScope scope) {
  ProcessResult r;
  if (!argv.empty() && forkServer().socket >= 0 && argv[0] == selfExecutable() &&
      runThroughForkServer(argv, timeoutSeconds, scope, r))
    return r;
  int outPipe[2], errPipe[2];
  if (::pipe2(outPipe, O_CLOEXEC) != 0 || ::pipe2(errPipe, O_CLOEXEC) != 0) {
    r.startError = std::string("pipe: ") + std::strerror(errno);
    return r;
  }
  pid_t pid = ::fork();
  if (pid < 0) {
    r.startError = std::string("fork: ") + std::strerror(errno);
    return r;
  }
  if (pid == 0) {
    ::setpgid(0, 0);  // own process group: a timeout kills the child and anything it started
    ::dup2(outPipe[1], 1);
    ::dup2(errPipe[1], 2);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    std::fprintf(stderr, "cannot start %s: %s\n", args[0], std::strerror(errno));
    ::_exit(127);
  }
  ::setpgid(pid, pid);
  ::close(outPipe[1]);
  ::close(errPipe[1]);
  collectOutput(pid, outPipe[0], errPipe[0], timeoutSeconds, scope, r);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  decodeStatus(status, r);
  return r;
}

}  // namespace parity::harness
