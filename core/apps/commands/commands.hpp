// core/apps/commands/commands.hpp: the commands of `tern` (main.cpp adds them in this order, which
// is the order of `tern --help`). Each adds its subcommand and options to `app` and returns its
// run (command_line.hpp); one file per command, named after it.
#pragma once

#include <vector>

#include "commands/command_line.hpp"

namespace tern::core {

Command add_fly_command(CLI::App& app);      ///< fly_command.cpp: fly a mission, write its flight log
Command add_check_command(CLI::App& app);    ///< check_command.cpp: validate a config, print its port graph
Command add_plugins_command(CLI::App& app);  ///< plugins_command.cpp: the plugins in the search path
Command add_replay_command(CLI::App& app);   ///< replay_command.cpp: an estimator over a flight log's sensors
Command add_import_command(CLI::App& app);   ///< import_command.cpp: another project's flight log into a sensor log
Command add_sysid_command(CLI::App& app);    ///< sysid_command.cpp: the aircraft's coefficients from a flight log
Command add_export_command(CLI::App& app);   ///< export_command.cpp: a flight's MCAP log as CSV, or recovered
Command add_tune_command(CLI::App& app);     ///< tune_command.cpp: a step-response test of one loop
Command add_params_command(CLI::App& app);   ///< params_command.cpp: every parameter of a mission
Command add_serve_command(CLI::App& app);    ///< serve_command.cpp: a host kept alive across flights
/// validate_command.cpp: aircraft files scored against a flight log (sysid/validate.hpp).
Command add_validate_command(CLI::App& app);
/// control_commands.cpp: swap, phases, console and remote, which drive a `tern serve` over its socket.
std::vector<Command> add_control_commands(CLI::App& app);
#if defined(TERN_WITH_DDS)
/// vehicle_commands.cpp: topics, echo, hz, param and mission, against a vehicle's DDS bridge.
std::vector<Command> add_vehicle_commands(CLI::App& app);
Command add_dds_command(CLI::App& app);  ///< dds_command.cpp: `tern dds keystore ...`
#endif

}  // namespace tern::core
