#include "harness/cli/cli.h"
#include "harness/run/process.h"

int main(int argc, char** argv) {
  // Before anything else: the children of `parity run` and `parity test` are forked from this
  // state (harness/run/process.h).
  parity::harness::startForkServer(&parity::harness::runCli);
  return parity::harness::runCli(argc, argv);
}
