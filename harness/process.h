// Child processes with a timeout: the harness runs each backend in its own process so that a
// crash or a hang becomes a result, and GL and Vulkan never share a process.
#pragma once

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
};

// Runs argv[0] with the arguments; the environment is inherited. timeoutSeconds <= 0: none.
ProcessResult runProcess(const std::vector<std::string>& argv, double timeoutSeconds);

// Path of the running executable (to run parity itself as a child).
std::string selfExecutable();

}  // namespace parity::harness
