// tern/msg/estimator.hpp: the estimator's innovation test ratios, topic `innovations`.
// Like PX4 EKF2's estimator_innovation_test_ratios: for each measurement, the normalised
// innovation squared (NIS = y^T S^-1 y) of its last update divided by its chi-square gate, so
// 1.0 is the edge of rejection and a ratio above 1 was rejected. A sensor not fused since the
// last message reports -1 (`none`; flight logs stay free of NaN). The run's summary carries the mean NIS of each (summary.json).
#pragma once

#include <cstdint>
#include <limits>
#include <string_view>

#include "tern/time.hpp"

namespace tern::msg {

struct Innovations {
  static constexpr std::string_view type_name = "tern/Innovations";
  static constexpr double none = -1.0;
  Nanos stamp = 0;
  double gnss_pos = none;       ///< GNSS position, 3 dof
  double gnss_vel = none;       ///< GNSS velocity, 3 dof
  double baro = none;           ///< barometric altitude, 1 dof
  double diff_pressure = none;  ///< pitot differential pressure, 1 dof
  double mag = none;            ///< magnetometer (heading, 1 dof, or direction, 3 dof)
  double sideslip = none;       ///< side force or zero-sideslip pseudo-measurement, 1 dof
  double normal_force = none;   ///< normal force (the lift model), 1 dof
  template <class V>
  static constexpr void describe(V& v) {
    v(&Innovations::stamp, "stamp", "ns");
    v(&Innovations::gnss_pos, "gnss_pos", "");
    v(&Innovations::gnss_vel, "gnss_vel", "");
    v(&Innovations::baro, "baro", "");
    v(&Innovations::diff_pressure, "diff_pressure", "");
    v(&Innovations::mag, "mag", "");
    v(&Innovations::sideslip, "sideslip", "");
    v(&Innovations::normal_force, "normal_force", "");
  }
};

/// Another estimator's solution recorded with real sensor data, topic `reference`: the onboard
/// autopilot's attitude, position and velocity in a sensor log (docs/sensor-log.md), which
/// `tern replay` compares tern's estimate with when there is no truth. A field the source does not
/// give is NaN (its CSV cell may be empty or `nan`).
struct Reference {
  static constexpr std::string_view type_name = "tern/Reference";
  Nanos stamp = 0;
  double phi = kNaN;    ///< roll, rad (3-2-1 Euler angles of body FRD against NED)
  double theta = kNaN;  ///< pitch, rad
  double psi = kNaN;    ///< yaw (heading), rad, from true north
  double lat = kNaN;    ///< WGS-84 latitude, deg
  double lon = kNaN;    ///< WGS-84 longitude, deg
  double alt = kNaN;    ///< altitude above mean sea level, m
  double v_n = kNaN;    ///< ground velocity north, m/s
  double v_e = kNaN;    ///< m/s
  double v_d = kNaN;    ///< m/s
  double w_n = kNaN;    ///< wind north (the air's velocity over the ground), m/s
  double w_e = kNaN;    ///< m/s
  template <class V>
  static constexpr void describe(V& v) {
    v(&Reference::stamp, "stamp", "ns");
    v(&Reference::phi, "phi", "rad");
    v(&Reference::theta, "theta", "rad");
    v(&Reference::psi, "psi", "rad");
    v(&Reference::lat, "lat", "deg");
    v(&Reference::lon, "lon", "deg");
    v(&Reference::alt, "alt", "m");
    v(&Reference::v_n, "v_n", "m/s");
    v(&Reference::v_e, "v_e", "m/s");
    v(&Reference::v_d, "v_d", "m/s");
    v(&Reference::w_n, "w_n", "m/s");
    v(&Reference::w_e, "w_e", "m/s");
  }

 private:
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace tern::msg
