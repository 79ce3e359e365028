// core/apps/commands/command_line.hpp: what every command of `tern` (main.cpp) shares: where the
// binary and its default mission are, the one-line error, the mission checks' report, and the
// shape of a command (its CLI11 subcommand and what runs when it is the one parsed).
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "commands/mission_check.hpp"

namespace tern::core {

/// A command of the command line: its subcommand and its run (the process's exit status). The run
/// may throw std::exception; main prints what() as one "tern: error: ..." line and exits 1.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

/// The directory of the running binary (empty when /proc/self/exe cannot be read).
std::filesystem::path exe_dir();

/// The default mission: <prefix>/share/tern/configs/missions/default.yaml for an installed tern,
/// the source tree's for a build tree's, else configs/missions/default.yaml (relative).
std::filesystem::path default_config();

/// `msg` for one line of the terminal: control characters escaped (tern/input_file.hpp's printable)
/// and every word (a run without a space: a name, a value) cut to kMaxEchoChars characters, then "...".
std::string terminal_line(const std::string& msg);
/// `text` of several lines for the terminal: each line's control characters escaped (printable),
/// its line ends kept, nothing cut. For what another process sent (a vehicle's samples over DDS).
std::string terminal_text(const std::string& text);
/// Prints "tern: error: MSG" (terminal_line) on stderr; returns 1 (the exit status).
int fail(const std::string& msg);

/// Prints the warnings and errors of `r` (and its notes, with `notes`: `tern check`) on stderr;
/// true when there are no errors.
bool report_missions(const MissionReport& r, bool notes = false);

}  // namespace tern::core
