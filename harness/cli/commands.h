// The `parity` subcommands, one file each in harness/cli/. Each file registers its own: it adds a
// subcommand to the app, binds options to state it owns (kept alive by the runner closure), and
// supplies the runner called when that subcommand was given. runCli() (cli.cpp) calls every
// registration function.
#pragma once

#include <CLI/CLI.hpp>

#include "harness/cli/report_error.h"

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

// list and the hidden probe it runs per backend (list.cpp).
void registerListCommands(CLI::App& app, CommandSet& commands);
// render (render.cpp).
void registerRenderCommand(CLI::App& app, CommandSet& commands);
// diff (diff.cpp).
void registerDiffCommand(CLI::App& app, CommandSet& commands);
// explain (explain.cpp).
void registerExplainCommand(CLI::App& app, CommandSet& commands);
// run, bless, merge and the hidden run-case child (run.cpp).
void registerRunCommands(CLI::App& app, CommandSet& commands);
// test: shader-test scripts (test.cpp).
void registerTestCommand(CLI::App& app, CommandSet& commands);
// bench: the performance studies (bench.cpp).
void registerBenchCommand(CLI::App& app, CommandSet& commands);
// view: a window showing a technique live (view.cpp).
void registerViewCommand(CLI::App& app, CommandSet& commands);

}  // namespace parity::harness
