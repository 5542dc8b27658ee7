#pragma once

namespace parity::harness {

// The `parity` command line: list, render, diff, run. Returns the process exit code.
int runCli(int argc, char** argv);

}  // namespace parity::harness
