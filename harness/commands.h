// The `parity` subcommands. Each file registers its own: it adds a subcommand to the app, binds
// options to state it owns (kept alive by the runner closure), and supplies the runner called
// when that subcommand was given. runCli() (cli.cpp) lists every registration function.
#pragma once

#include <CLI/CLI.hpp>

#include "harness/report_error.h"

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace parity::harness {

using CommandRunner = std::function<int()>;

struct CommandSet {
  std::vector<std::pair<CLI::App*, CommandRunner>> commands;
  void add(CLI::App* subcommand, CommandRunner run) { commands.emplace_back(subcommand, std::move(run)); }
};

// list, render, diff and the hidden probe (cli.cpp).
void registerCoreCommands(CLI::App& app, CommandSet& commands);

// run, bless, merge and the hidden run-case child (cmd_run.cpp).
void registerRunCommands(CLI::App& app, CommandSet& commands);

// explain (cmd_explain.cpp).
void registerExplainCommand(CLI::App& app, CommandSet& commands);

// test: shader-test scripts (cmd_test.cpp).
void registerTestCommand(CLI::App& app, CommandSet& commands);

}  // namespace parity::harness
