// Child processes with a timeout: the harness runs each backend in its own process so that a
// crash or a hang becomes a result, and GL and Vulkan never share a process.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace parity::harness {

struct ProcessResult {
  int exitCode = -1;     // valid when !crashed && !timedOut
  bool crashed = false;  // killed by a signal
  int signal = 0;
  bool timedOut = false;
  std::string out, err;  // captured stdout / stderr
  std::string startError;  // non-empty when the process could not be started

  // It could not start, ran past the timeout or died from a signal.
  bool died() const { return !startError.empty() || timedOut || crashed; }
};

// What a timeout limits: the whole run, or each wait for the next line of standard output (a
// child that prints a result per line as it goes, however many it has to give).
enum class TimeoutScope { WholeRun, EachLine };

// Runs argv[0] with the arguments; the environment is inherited. timeoutSeconds <= 0: none.
// When argv[0] is this executable and its fork server runs, the child is forked from the server
// instead of executed: the same command in a fresh process, without the dynamic linker's 0.3 s
// (OpenImageIO brings in over 250 shared libraries, relocated at every exec).
ProcessResult runProcess(const std::vector<std::string>& argv, double timeoutSeconds,
                         TimeoutScope scope = TimeoutScope::WholeRun);

// Forks the fork server: a process that stays as this one is now, with no device, no thread and
// no file of a command yet, and forks a child for each runProcess of this executable, which then
// runs entry(argc, argv) and exits with its result. Call it first thing in main(), before the
// program starts threads or opens anything: a fork copies only the calling thread, and a lock
// another thread holds stays locked in the copy. (Some libraries start idle threads while they
// load, before main(); the server has none of them, so its own forks are of a single thread.)
// Without it, runProcess executes the file. `warm`, when given, runs once in the server before its
// first fork: what it computes (with no device and no thread) every child inherits.
void startForkServer(int (*entry)(int, char**), void (*warm)() = nullptr);

// Fixes glibc's thresholds for handing freed memory back to the system, which glibc otherwise
// adjusts from the order of a process's earlier frees. Mesa's GL draw path on llvmpipe mallocs
// and frees a block per draw; in some processes (about one in eight `parity bench` GL children,
// depending on thread timing) the adjusted thresholds made every such free shrink the heap and
// the next draw fault its pages back in, and a frame of 255 light volumes took twice as long as
// in the next process (docs/BENCH.md, "Why some GL processes were twice as slow"). Call it
// first thing in main(): every process then keeps freed blocks below 128 MiB of free heap.
void fixAllocatorThresholds();

// A child's result lines: the JSON objects of its standard output that carry the string `field`
// (`parity run-case`: "case", one per case; `parity test --in-process`: "result", one per script
// and platform). Anything else it printed is not a result.
std::vector<nlohmann::json> resultLines(const std::string& out, const char* field);

// Path of the running executable (to run parity itself as a child).
std::string selfExecutable();
// The executable `name` on PATH (runProcess executes a file, it does not search); empty if none.
std::string findInPath(const std::string& name);

}  // namespace parity::harness
