// core/apps/campaign/dispersion.hpp: a campaign's dispersions checked against the base mission,
// and the values flight k draws.
//
// Units are the parameter's own (`tern params MISSION` lists them). A relative dispersion
// draws a fraction v and sets nominal x (1 + v), nominal being the base mission's effective
// value (instance parameters) or the aircraft file's number. Integer parameters take the draw
// rounded to the nearest integer. A normal draw is clipped to `clip`, else to the parameter's
// range. Draws follow counter_rng.hpp: a pure function of (campaign seed, flight index, column).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "campaign_file.hpp"
#include "tern/param.hpp"

namespace tern::campaign {

/// The base mission's parameters ("instance.param" -> parameter, alive while the draws are made).
using ParamCatalogue = std::map<std::string, const ParamBase*>;

/// A dispersion with a concrete target (`aircraft.aero.*` expanded to one per coefficient).
struct Resolved {
  Dispersion d;
  const ParamBase* param = nullptr;        ///< instance parameter (nullptr: aircraft)
  std::vector<std::string> aircraft_path;  ///< aircraft number: keys from the file's root
  double aircraft_nominal = 0;
  const ParamBase* into_wind = nullptr;  ///< polar's heading parameter
};

/// One value a flight drew: a column of its table row.
struct Drawn {
  std::string column;  ///< "sim.turbulence", "sim.wind.speed", "aircraft.mass", "ekf.imu_position[1]"
  std::string unit;    ///< the parameter's; "rel" for a relative draw's fraction
  std::string text;    ///< the value as written in the table (numbers: shortest round-trip)
  double number = 0;   ///< for numeric values (NaN for text)
};

struct FlightDraw {
  std::size_t index = 0;
  std::uint64_t seed = 0;  ///< the flight's mission seed
  std::vector<Drawn> columns;
  std::map<std::string, ParamValue> params;  ///< "instance.param" -> value to fly
  std::map<std::string, double> aircraft;    ///< "aero.C_L_0" -> perturbed number
};

/// Checks every dispersion against the parameters and the aircraft document (the base
/// mission's `aircraft:`, loaded; null if none): names exist, kinds fit, every value a
/// dispersion can produce lies in the parameter's range. Throws core::ConfigError naming the
/// campaign file, the field and the value.
std::vector<Resolved> resolve_dispersions(const CampaignFile& c, const ParamCatalogue& params, const YAML::Node& aircraft);

/// What flight `index` draws.
FlightDraw draw_flight(const CampaignFile& c, const std::vector<Resolved>& dispersions, std::size_t index);

/// The number as the table writes it: shortest text that reads back to the same double.
std::string number_text(double v);

}  // namespace tern::campaign
