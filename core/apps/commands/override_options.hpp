// core/apps/commands/override_options.hpp: --set, --phases and --fallback on a command (cli_overrides.hpp),
// worded once for every command that takes them (fly, check, params, serve, tune).
#pragma once

#include <CLI/CLI.hpp>

#include "config/cli_overrides.hpp"

namespace tern::core {

inline void add_override_options(CLI::App* cmd, CliOverrides& o) {
  cmd->add_option("--set", o.sets,
                  "INSTANCE.PARAM=VALUE: a parameter for this run, checked as in the config (VALUE in YAML: 0.5, true, "
                  "text, [1, 2, 3]); repeatable")
      ->type_name("INSTANCE.PARAM=VALUE");
  cmd->add_option("--phases", o.phases,
                  "PHASE=INSTANCE,...: replaces the phase -> controller table (takeoff, climb, cruise required; "
                  "landing, loiter optional)")
      ->type_name("PHASE=INSTANCE,...");
  cmd->add_option("--fallback", o.fallback, "the controller that takes over when the active one fails (replaces fallback:)")
      ->type_name("INSTANCE");
}

}  // namespace tern::core
