// tern/msg/estimator.hpp: the estimator's innovation test ratios, topic `innovations`.
// Like PX4 EKF2's estimator_innovation_test_ratios: for each measurement, the normalised
// innovation squared (NIS = y^T S^-1 y) of its last update divided by its chi-square gate, so
// 1.0 is the edge of rejection and a ratio above 1 was rejected. A sensor not fused since the
// last message reports -1 (`none`; flight logs stay free of NaN). The run's summary carries the mean NIS of each (summary.json).
#pragma once

#include <cstdint>
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

}  // namespace tern::msg
