// core/apps/campaign/flight_plan.hpp: the files of one campaign flight, and the command that
// flies it.
//
//   <out>/flights/<k, 5 digits>/config.yaml    the base mission with flight k's seed, duration,
//                                              log level and drawn parameters; every path absolute
//                                              and parameter files inlined, so it flies alone
//   <out>/flights/<k>/aircraft.yaml            the perturbed airframe (when the campaign perturbs
//                                              it), given to the simulator's `aircraft` parameter
//   <out>/flights/<k>/run/<time>-<mission>/    the flight log `tern fly` writes
//   <out>/flights/<k>/fly.log                  tern's console output
// The command: `<tern> fly <config.yaml> --log-dir <run> -q`. Run again, it writes a second
// flight log with the same summary.json.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "campaign_file.hpp"
#include "config/config.hpp"
#include "dispersion.hpp"

namespace tern::campaign {

struct FlightFiles {
  std::size_t index = 0;
  fs::path dir, config, aircraft, run_dir, console;
  std::vector<std::string> argv;  ///< the command, argv[0] the tern binary
  std::string command;            ///< the same, quoted for a POSIX shell
};

/// Where flight k's files go under the campaign's output directory `out`.
FlightFiles flight_files(const fs::path& out, std::size_t k, const fs::path& tern_bin);

/// Writes flight k's config.yaml (and aircraft.yaml). `aircraft` is the base mission's aircraft
/// document (null if none). Throws core::ConfigError when it cannot write, or when the airframe
/// is perturbed and no instance has an `aircraft` file parameter.
void write_flight(const CampaignFile& c, const core::MissionConfig& base, const ParamCatalogue& params, const YAML::Node& aircraft,
                  const FlightDraw& draw, const FlightFiles& files);

/// The summary.json of the flight's log, empty if there is none that is complete (written by a
/// flight that ended by its duration or by itself, not by a signal).
fs::path finished_summary(const FlightFiles& files);
/// `s` as one POSIX shell word (single-quoted unless it is plain), for recorded commands.
std::string shell_quote(const std::string& s);

}  // namespace tern::campaign
