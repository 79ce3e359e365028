// core/apps/commands/fleet_command.hpp: what `tern fly` and `tern check` do with a multi-vehicle
// mission (a config with `vehicles:`, fleet_config.hpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "commands/command_line.hpp"
#include "commands/host_preparation.hpp"
#include "fleet/fleet.hpp"

namespace tern::core {

struct FleetFlyOptions {
  FleetOptions fleet;
  HostPreparation prep;
  std::string console_vehicle;  ///< --console-vehicle: the vehicle the console follows ("": the first)
};

/// Applies the command line (`p`) to every part of `fc` (see fleet_command.cpp for --set) and
/// returns each vehicle's prepared mission, in `vehicles:` order. Throws ConfigError.
std::vector<PreparedMission> prepare_fleet(FleetConfig& fc, const HostPreparation& p);
/// `tern fly FLEET`: flies it, prints each vehicle's end and the closest approach; exit status
/// 0 when every vehicle's flight is ok, else 1. Throws ConfigError before anything flies.
int fly_fleet(const std::string& file, const FleetFlyOptions& o);
/// `tern check FLEET`: every vehicle's port graph and mission check, and the coordination's graph.
int check_fleet(const std::string& file, const HostPreparation& p);

}  // namespace tern::core
