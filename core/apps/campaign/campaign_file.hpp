// core/apps/campaign/campaign_file.hpp: a campaign file (configs/campaigns/*.yaml), loaded.
//
//   name: hourglass_dispersion          # names the output directory, one folder name (default: the file's stem)
//   base: ../missions/default.yaml      # the mission every flight flies (relative to this file)
//   seed: 2026                          # campaign seed, 0 .. 2^64-1
//   flights: 200                        # default: the number of grid points (1 without a grid); at most kMaxFlights
//   duration: 300                       # s, optional: overrides the base mission's
//   log: summary                        # log level of each flight: summary | decimated | full
//   dispersions:                        # drawn per flight; units are the parameter's own
//     sim.turbulence: {dist: choice, values: [light, moderate]}
//     ekf.gyro_noise: {dist: normal, mean: 0.002, sd: 0.0005, clip: [0.0005, 0.004]}
//     slc.roll_kp:    {dist: uniform, low: -0.2, high: 0.2, relative: true}   # x (1 + draw)
//     phase_machine.alt_toz: {dist: grid, values: [5, 10]}
//     sim.wind: {dist: polar, speed: [0, 8], from_deg: [0, 360], into_wind: sim.init_heading}
//     aircraft.mass: {dist: uniform, low: -0.1, high: 0.1}        # relative, always
//     aircraft.aero.*: {dist: uniform, low: -0.15, high: 0.15}    # each coefficient on its own
//   criteria:                           # every one must hold for a flight to pass
//     - end_reason == duration
//     - metrics.max_cross_track_m < 15
//   worst_by: metrics.max_cross_track_m # ranks the worst flights (default: first numeric criterion)
//
// Distributions: uniform {low, high}; normal {mean, sd, clip: [lo, hi] optional}; choice
// {values, weights optional}; grid {values} (flights walk the grid's points in order, the last
// grid dispersion fastest); polar {speed: [lo, hi], from_deg: [lo, hi]} (a horizontal NED vector
// blowing *from* a uniform direction at a uniform speed; `into_wind` names a heading parameter
// set to that direction, rad). uniform/normal bounds may be lists for vector parameters (one
// draw per component). `aircraft.<path>` perturbs a number of the aircraft file by a relative
// amount (value x (1 + draw)); `*` as the last part takes every number under the map. The
// perturbed aircraft is the simulator's (the world's): the mission's `aircraft:`, the
// estimator's belief, stays nominal.
//
// Errors: ConfigError, one line "file:line:col: field: what".
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace tern::campaign {

namespace fs = std::filesystem;

enum class Dist { uniform, normal, choice, grid, polar };

struct Dispersion {
  std::string target;  ///< "sim.wind", "aircraft.mass", "aircraft.aero.*"
  Dist dist = Dist::uniform;
  std::vector<double> low, high;                            ///< uniform (size 1, or the vector's size)
  std::vector<double> mean, sd;                             ///< normal
  std::optional<std::pair<double, double>> clip;            ///< normal
  std::vector<YAML::Node> values;                           ///< choice, grid
  std::vector<double> weights;                              ///< choice (empty: equal)
  std::pair<double, double> speed{0, 0}, from_deg{0, 360};  ///< polar: m/s (the parameter's unit), deg
  std::optional<std::string> into_wind;                     ///< polar: heading parameter set to the direction
  bool relative = false;                                    ///< drawn value v: parameter = nominal x (1 + v)
  YAML::Node node;                                          ///< for error locations
  bool aircraft() const { return target.rfind("aircraft.", 0) == 0; }
};

struct Criterion {
  std::string figure;  ///< flattened summary.json key, e.g. "metrics.max_cross_track_m"
  std::string op;      ///< < <= > >= == !=
  std::string value;   ///< as written (a number, true/false, or text)
  std::string text;    ///< the whole criterion as written
};

struct CampaignFile {
  fs::path file;  ///< absolute
  std::string name;
  fs::path base;  ///< absolute path of the base mission
  std::uint64_t seed = 1;
  std::size_t flights = 1;
  std::optional<double> duration;  ///< s
  std::string log_level = "summary";
  std::vector<Dispersion> dispersions;
  std::vector<Criterion> criteria;
  std::string worst_by;         ///< "" when no numeric criterion and none given
  std::size_t grid_points = 1;  ///< product of the grid dispersions' sizes
};

/// The most flights a campaign may ask for, by `flights:` or by its grid's points.
inline constexpr std::size_t kMaxFlights = 1000000000;

/// Loads and checks the file's own shape (parameters are checked against the base mission by
/// validate_dispersions, dispersion.hpp). Throws core::ConfigError.
CampaignFile load_campaign(const fs::path& file);

}  // namespace tern::campaign
