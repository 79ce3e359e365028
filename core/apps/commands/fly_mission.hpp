// core/apps/commands/fly_mission.hpp: one mission (not a fleet) flown as `tern fly` flies it, for
// the command line and for Python's tern.fly (core/apps/python): the config prepared with the
// command line's changes (host_preparation.hpp), its missions checked before anything flies, the
// host built, the tick observers asked for attached, one flight flown.
#pragma once

#include <optional>
#include <string>

#include "commands/host_preparation.hpp"
#include "flight/host.hpp"

namespace tern::core {

/// Flies `config_file` with `prep` applied and `options` (seed, duration, log directory, ...).
/// nullopt when the mission check refused it (its errors printed on stderr, nothing flown);
/// `signals`: SIGINT/SIGTERM/SIGHUP end the flight cleanly (install_signal_handlers). Throws
/// ConfigError as prepare_mission() and Host::build() do.
std::optional<FlightResult> fly_mission(const std::string& config_file, const HostPreparation& prep, const HostOptions& options,
                                        bool signals);

}  // namespace tern::core
