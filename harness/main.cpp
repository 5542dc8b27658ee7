#include "harness/cli.h"

int main(int argc, char** argv) { return parity::harness::runCli(argc, argv); }
