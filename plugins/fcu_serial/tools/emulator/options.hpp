// emulator/options.hpp: the command-line options of the world behind a flight-control unit,
// shared by tern-fcu-emulator (the emulated firmware) and tern-fcu-sil (the real one): the
// aircraft and seed, the port, the pacing, wind, start, the pilot's transmitter and link faults.
#pragma once

#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "emulator.hpp"

namespace tern::fcu::emulator {

void add_world_options(CLI::App& app, Options& o);

/// What main() does once the options are parsed: SIGINT/SIGTERM end the loop
/// (g_emulator_stop), --exit-with-parent, the port opened; `make` builds the loop on it (a bad
/// aircraft or parameter file fails before the port is announced), then the port's line
/// ("pty: /dev/pts/N" or "udp: HOST:PORT") goes to stdout and the loop runs. An exception is
/// one line "<program>: <what>" and exit code 1.
int run_on_port(const Options& o, const std::string& program, const std::function<std::function<int()>(Port&)>& make);

}  // namespace tern::fcu::emulator
