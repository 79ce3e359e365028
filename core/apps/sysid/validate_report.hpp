// core/apps/sysid/validate_report.hpp: `tern validate`'s results as it prints and writes them: the
// side-by-side table (one column per aircraft file), DIR/validate.json and DIR/index.html (the
// table and, per channel, the measured series against each file's prediction as inline SVG).
// Definitions of every figure: validate.hpp. JSON and the page in SI (the page's plots and the
// printed RMS columns in deg, deg/s for angles and rates); non-finite numbers are JSON null.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sysid/flight_data.hpp"
#include "sysid/validate.hpp"

namespace tern::core::sysid {

/// One `tern validate` run: the log, how its estimate was made, the windows, and every file's score.
struct ValidationRun {
  std::string log;       ///< the log directory as given
  std::string estimate;  ///< one line: what produced the estimate (e.g. "tern replay of the log ...")
  ValidateOptions options;
  FlightSeriesOptions series;  ///< filter and rate of the series (each file's own servo lag: AircraftScore)
  std::vector<Window> windows;
  std::string airborne;                                 ///< the airborne rule that held (airborne.hpp), one line
  std::vector<double> t;                                ///< s, the series' time
  std::array<std::vector<double>, kChannels> measured;  ///< the measured channels (kChannelSpecs)
  std::vector<AircraftScore> files;
};

/// A channel as the table's RMS column and the plots show it: angles in deg, rates in deg/s,
/// airspeed in m/s (scale times the SI value; the unit's name).
double display_scale(const ChannelSpec& c);
std::string display_unit(const ChannelSpec& c);

/// Scored samples in all (every window's samples but its first) and their seconds.
std::size_t scored_samples(const std::vector<Window>& windows);
double scored_seconds(const ValidationRun& run);

/// The table `tern validate` prints.
std::string format_validate_table(const ValidationRun& run);

/// validate.json's document.
nlohmann::ordered_json validate_json(const ValidationRun& run);

/// index.html: self-contained (no script, no external file).
std::string validate_html(const ValidationRun& run);

}  // namespace tern::core::sysid
