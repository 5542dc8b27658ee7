#include "harness/cli/cli.h"

#include <CLI/CLI.hpp>

#include <cstdio>

#include "harness/cli/commands.h"
#include "harness/io/text.h"

namespace parity::harness {

// Every error the user sees is one line: "parity: error: <what>".
int reportError(const std::string& message, int code) {
  std::fprintf(stderr, "parity: error: %s\n", oneLine(message).c_str());
  return code;
}

int runCli(int argc, char** argv) {
  CLI::App app{"parity: renders techniques on OpenGL and Vulkan (and emulated console platforms) and compares the images"};
  app.require_subcommand(1);
  CommandSet commands;
  // In the order `parity --help` lists them; a new subcommand adds its file and one line here.
  registerListCommands(app, commands);
  registerRenderCommand(app, commands);
  registerDiffCommand(app, commands);
  registerExplainCommand(app, commands);
  registerRunCommands(app, commands);
  registerTestCommand(app, commands);
  registerBenchCommand(app, commands);
  registerViewCommand(app, commands);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string what = e.what();
    return reportError(what.empty() ? "invalid command line" : what);
  }
  for (auto& [subcommand, run] : commands.commands)
    if (subcommand->parsed()) return run();
  return reportError("no command");
}

}  // namespace parity::harness

