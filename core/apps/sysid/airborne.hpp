// core/apps/sysid/airborne.hpp: where a flight series is in the air, for `tern sysid` and
// `tern validate` alike (issue 76: logs tern did not write).
//
// Never from height above the estimator's origin: its origin is the first fix, and many logs start
// in the air (a log trimmed to the flight, a logging switch, a hand launch).
//  * The log's own word first: sensor_log.yaml's `airborne: [start_s, end_s]` (s, the log's t;
//    docs/sensor-log.md), which FlightSeries::declared_airborne carries. A sample inside it counts
//    where the estimate is valid.
//  * Else from the data: the ground is where the aircraft stood still. The samples where the estimate
//    is valid and the ground speed is below `still_speed` (standing, taxiing, held in the hand before
//    a launch, stopped after a landing) give the ground's height, the median of their -p_d; a sample
//    counts where the estimate is valid and it is more than `min_height` above that ground. A log
//    that never stands still (one that starts and ends in the air) has no ground in it: every
//    valid sample counts. Ground speed below 2 m/s in flight would need a headwind equal to the
//    airspeed; the few such samples only move the median of the still ones.
// What counts as flight for a regression or a score (airspeed, flow angles) is the caller's filter
// on top of this one (aero_samples.hpp, validate.hpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sysid/flight_data.hpp"

namespace tern::core::sysid {

struct AirborneRule {
  double min_height = 10.0;  ///< m above the ground where the aircraft stood still (no still stretch: not used)
  double still_speed = 2.0;  ///< m/s, ground speed below which the aircraft counts as standing on the ground
  double min_still_s = 1.0;  ///< s of still samples needed to take the ground's height from them
};

struct AirborneMask {
  std::vector<unsigned char> up;  ///< 1 where the sample counts as airborne, one per series sample
  std::string rule;               ///< which rule produced it, with its figures (one line, for tables and errors)
};

/// Seconds of the series where `flag` holds (each sample counts its interval to the next).
double seconds_where(const FlightSeries& s, const std::vector<unsigned char>& flag);

/// m above the estimator's origin: the ground where the aircraft stood still (the median height of
/// those samples, header); none when the log never stands still.
std::optional<double> ground_height(const FlightSeries& s, const AirborneRule& rule);

/// The series' p_d moved so that the ground is at p_d = 0, where the uavbook model's gear touches
/// (tern/aero/model.hpp): by ground_height, or, for a log that never stood still (one that starts
/// in the air and ends there), 1000 m below its lowest sample. The estimator's origin is the first
/// fix: 50 m up for a log that starts in the air, and there its ground would be.
void put_ground_at_zero(FlightSeries& s, const AirborneRule& rule);

/// The airborne samples of `s` (header). Never throws; `up` is all 0 when the estimate is never valid.
AirborneMask airborne_mask(const FlightSeries& s, const AirborneRule& rule);

}  // namespace tern::core::sysid
