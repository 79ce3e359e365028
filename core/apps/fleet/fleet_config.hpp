// core/apps/fleet/fleet_config.hpp: a multi-vehicle mission (`vehicles:`), loaded and validated.
//
// One file names a team of aircraft in one world (docs/multi-vehicle.md):
//
//   name, seed, duration, log, plugin_path, watchdog, dds   the flight's, shared
//   world: {wind, turbulence, origin}                       the one world: every vehicle's simulator
//                                                           (its sim_aero instance) gets these
//   plugins, phases, fallback, phase_machine, metrics,      the stack every vehicle flies, as in a
//   failsafes, aircraft, mission, check, base_rate          one-vehicle mission (config.hpp)
//   vehicles: [{name, aircraft, initial, mission, phases,   each vehicle: a name (an identifier) and
//               fallback, failsafes, params, system_id}]    what differs from the shared stack
//   coordination: [plugin instances]                        coordination plugins (kind coordination)
//   separation: {min_distance, response, hold_climb}        the separation monitor (separation.hpp)
//
// Each vehicle's own config (VehicleConfig::config) is the shared stack with the vehicle's keys
// put over it, checked as a one-vehicle mission is (config_from_yaml); its `initial:` and the
// world go to its sim_aero instance's parameters (init_*, wind, turbulence, origin_lat/lon/alt),
// `params:` ("instance.param": value) to any instance's. Its DDS namespace is the vehicle's name
// (under the mission's dds.namespace when that is given); its MAVLink system id on the ground-station
// port (--gcs, docs/ground-station.md) is `system_id:` (1-255, unique), by default its place in
// `vehicles:` counted from 1. Errors are one line naming the file,
// the vehicle and the field (ConfigError).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "config/config.hpp"

namespace tern::core {

/// `separation:`: the minimum-distance monitor every multi-vehicle flight runs (separation.hpp).
struct SeparationConfig {
  double min_distance = 20.0;  ///< m, 3-D: closer than this (estimated) is a conflict, > 0
  /// What a conflict does: report (a warning and the count) or hold: the later vehicle of the
  /// pair (in `vehicles:` order) is sent a loiter over its estimated position, `hold_climb` higher.
  enum class Response { report, hold } response = Response::report;
  double hold_climb = 20.0;  ///< m, >= 0: how much higher the held vehicle orbits
};

struct VehicleConfig {
  std::string name;            ///< an identifier: names its log directory, DDS namespace and topics
  MissionConfig config;        ///< its own mission: the shared stack with its keys put over it
  std::string field;           ///< "vehicles[2]" (with the name: error messages)
  std::uint8_t system_id = 1;  ///< MAVLink system id with --gcs: `system_id:`, or its place in `vehicles:` from 1
};

struct FleetConfig {
  fs::path file;  ///< absolute
  std::string name;
  std::uint64_t seed = 1;
  double duration = 60.0;  ///< s
  LogConfig log;           ///< the run directory's parent (each vehicle's level and topics: its config's)
  std::vector<VehicleConfig> vehicles;
  std::optional<MissionConfig> coordination;  ///< `coordination:` as a mission of its own (vehicles set)
  SeparationConfig separation;
  YAML::Node root;
};

/// Whether `root` is a multi-vehicle mission (has `vehicles:`).
bool is_fleet(const YAML::Node& root);
/// Whether the file at `file` is one (false when it cannot be read: load_config then says why).
bool is_fleet_file(const fs::path& file);
/// Loads and validates a multi-vehicle mission. Throws ConfigError (one line).
FleetConfig load_fleet(const fs::path& file);
/// The stack every vehicle shares (plugins, phases, mission, ... without the vehicles' own keys,
/// the world or the coordination) as a one-vehicle mission whose `root` is the whole file: what
/// `tern campaign` reads parameters from and writes each flight's copy of. Throws ConfigError.
MissionConfig fleet_stack(const fs::path& file);
/// One part of it as a one-host mission: a vehicle's config (`part` its name) or the
/// coordination's ("coordination"); what an isolated instance's child process loads. Throws
/// ConfigError.
MissionConfig load_fleet_part(const fs::path& file, const std::string& part);

}  // namespace tern::core
