// core/src/commands/tune_command.hpp: the `tern tune` subcommand's options and its run (tune.hpp does the work).
#pragma once

#include <filesystem>

#include <CLI/CLI.hpp>

#include "commands/tune.hpp"

namespace tern::core {

struct TuneCommand {
  CLI::App* app = nullptr;
  TuneOptions options;
  std::string seed_text;
  bool no_plot = false;
};

/// Adds `tune` to the command line; `tc` receives the options when it is parsed.
void add_tune_command(CLI::App& app, TuneCommand& tc);
/// Runs the test, prints the table, draws tune.png with `plot_program` (tern-plot); the exit
/// status: 0 with at least one measured step, 1 otherwise (one error line on stderr).
int run_tune_command(TuneCommand& tc, const std::filesystem::path& default_config, const std::filesystem::path& plot_program);

}  // namespace tern::core
