// sim_aero_plugin.hpp: the tern plugin around the simulator (tern_sim_aero/*.hpp). It integrates the
// aircraft from the previous step time to `now` in fixed sub-steps of 1/sim_rate, and publishes
// each sensor when due on its own integer-nanosecond schedule (k * period), plus the true state
// on `truth`. Input `actuators` is optional: without it the surfaces stay at zero (or at the
// trim inputs when init_mode is "trim") and the throttle at 0 (or trim). Input `pilot` is
// optional too: the sticks and switches of a pilot flying the simulation by hand (the console's
// keyboard or gamepad, a joystick plugin), which the receiver reports on `rc` as a real one
// would; without it the simulated pilot holds the sticks centred, override off.
#pragma once

#include <algorithm>
#include <array>
#include <deque>
#include <functional>
#include <iterator>
#include <cmath>
#include <memory>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>

#include "tern/math.hpp"
#include "tern/plugin.hpp"
#include "sensor_params.hpp"
#include "tern/aircraft.hpp"
#include "tern/magnetic_model.hpp"
#include "tern_sim_aero/earth_field.hpp"
#include "tern_sim_aero/rangefinder.hpp"
#include "tern_sim_aero/profiles.hpp"
#include "tern_sim_aero/sensors.hpp"
#include "tern_sim_aero/simulator.hpp"
#include "tern/aero/trim.hpp"

namespace tern::sim_aero {

using tern::Nanos;
using tern::ParamError;
using tern::ParamSpec;
namespace sim = tern::sim;
namespace msg = tern::msg;

struct SensorSlot {
  tern::Param<double> rate;
  tern::Param<bool> enabled;
  tern::Param<std::vector<double>> dropout;
  tern::Param<std::vector<double>> nan;  ///< windows of non-finite samples (a failing sensor or driver)
  sim::SensorSchedule schedule;
  std::vector<std::pair<Nanos, Nanos>> nan_windows;
  bool non_finite(Nanos t) const {
    for (const auto& [a, b] : nan_windows)
      if (t >= a && t < b) return true;
    return false;
  }
};

/// The sim_aero plugin (registered in plugin.cpp; the tests construct it directly).
class SimAero final : public tern::Plugin {
 public:
  void configure() override;

  void start() override { initialise(); }
  void reset() override { initialise(); }

  void step(Nanos now) override;

  std::vector<std::pair<std::string, double>> summary() const override;

 private:
  void declare_sensor(SensorSlot& s, const std::string& name, double rate);
  std::vector<SensorSlot*> slots() { return {&imu_, &mag_, &baro_, &diff_, &gnss_, &range_}; }

  Nanos period_of(double hz, const std::string& name) const;
  std::vector<std::pair<Nanos, Nanos>> dropouts_of(const SensorSlot& s) const { return windows_of(s.dropout); }
  std::vector<std::pair<Nanos, Nanos>> windows_of(const tern::Param<std::vector<double>>& param) const;
  void check_gusts() const;

  // The profile's values are the defaults of every sensor and actuator parameter.
  void declare_error_model();

  /// The profile's sensor and actuator values, the Earth's field being the model's at the
  /// profile's origin on `date`.
  sim::SensorParams profile_defaults() const;

  // ---- the world's magnetic field: mag_declination / _inclination / _intensity that nobody set
  // follow the World Magnetic Model at the origin on `date` (sim::earth_field); a set one overrides.
  static bool is_field_row(const SensorReal& r);
  static bool is_origin_row(const SensorReal& r);
  /// `date` as a decimal year; a bad date throws ParamError naming the parameter.
  double world_date() const;
  /// The field parameters nobody set take the model's values at the current origin and date, so
  /// that they show what the world uses.
  void sync_world_field();

  /// Remembers whether the mission sets `p`, and any later change, so that a new sensor_profile
  /// (between flights) moves only the parameters nobody set.
  template <class T>
  void track_explicit(tern::Param<T>& p, std::function<void()> then = nullptr) {
    if (context().configured_value(p.name(), p.spec())) set_explicitly_.insert(&p);
    p.on_change([this, &p, then](const T&) {
      if (!applying_profile_) set_explicitly_.insert(&p);
      if (then) then();
    });
  }

  /// sensor_profile changed (a start-only parameter: between flights): every sensor and
  /// actuator parameter nobody set takes the new profile's default; the next start() uses them.
  void apply_profile_defaults();

  sim::SensorParams sensor_params() const;
  sim::ActuatorParams actuator_params() const;
  /// Loads the aircraft file (again, when `aircraft` changed between flights).
  void load_aircraft();

  void initialise();

  /// Says once per flight which field the world has (and which settings override the model), and
  /// warns when the model is extrapolated.
  void report_earth_field();

  // ---- ground impact
  // The simulator's crash: the CG below the ground, a hard point on it or a wheel touching down
  // faster than the gear's max_sink_rate (it freezes the aircraft there). A crash ends the
  // flight (end_reason "crash"): nothing after it is a flight worth logging.
  struct ImpactFacts {
    double t;                      // s, flight time (the simulator's clock starts with the flight)
    Eigen::Vector3d p_ned, v_ned;  // m, m/s (v_d > 0: sinking)
    double Va, phi, theta;         // m/s, rad, rad
  };
  ImpactFacts impact() const;
  void report_crash();

  void apply_live_params();

  void publish_due(Nanos t);

  // The simulated FCU arms only after its power-up calibrations (boot_calibration.hpp); says
  // once what they found.
  // rad/s: 1 deg/s, the ICM-20602 turn-on tolerance: a calibration worse than none
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  static constexpr double kMovedDuringCalibration = 0.0175;
  bool boot_calibrated(Nanos t);

  /// The truth a covered pitot sees: still air.
  static sim::Truth covered_pitot(sim::Truth t);

  void publish_truth(Nanos t, const sim::Truth& tr);

  tern::Input<msg::Actuators> actuators_in_;
  tern::Output<msg::Imu> imu_out_;
  tern::Output<msg::Gnss> gnss_out_;
  tern::Output<msg::Baro> baro_out_;
  tern::Output<msg::Range> range_out_;
  tern::Output<msg::DiffPressure> diff_out_;
  tern::Output<msg::Mag> mag_out_;
  tern::Output<msg::State> truth_out_;
  tern::Input<msg::Rc> pilot_in_;
  tern::Output<msg::Rc> rc_out_;
  tern::Output<msg::FcuStatus> status_out_;

  tern::Param<std::string> aircraft_, init_mode_, turbulence_;
  tern::Param<double> sim_rate_, init_altitude_, init_airspeed_, init_heading_, parking_brake_;
  tern::Param<std::vector<double>> init_position_, wind_, gusts_;
  tern::Param<double> gust_rate_, gust_max_, gust_min_duration_, gust_max_duration_;
  SensorSlot imu_, mag_, baro_, diff_, gnss_, range_;
  tern::Param<std::string> sensor_profile_, date_;
  std::array<tern::Param<double>, std::size(kSensorReals)> sensor_reals_;
  std::array<tern::Param<std::vector<double>>, std::size(kSensorVectors)> sensor_vectors_;
  std::array<tern::Param<double>, std::size(kActuatorReals)> actuator_reals_;
  tern::Param<double> truth_rate_, rc_rate_, status_rate_;
  tern::Param<bool> gnss_start_steady_;
  tern::Param<bool> gnss_sky_;
  tern::Param<bool> calibrate_at_boot_;
  tern::Param<bool> accel_calibrated_level_;
  tern::Param<bool> accel_calibrated_at_power_up_;
  tern::Param<double> pitot_cover_;
  tern::Param<std::int64_t> gnss_num_sats_;
  tern::Param<bool> armed_, offboard_;

  std::optional<tern::Aircraft> aircraft_data_;
  std::string aircraft_path_;  ///< the file aircraft_data_ came from
  /// Everything one flight changes: initialise() (start(), reset()) replaces it wholesale. The
  /// sensor slots' schedules are rebuilt there too, from their start-only parameters.
  struct Flight {
    std::unique_ptr<sim::Simulator> sim;
    std::unique_ptr<sim::Sensors> sensors;
    std::unique_ptr<sim::RangeFinder> rangefinder;
    sim::SensorSchedule truth_sched, rc_sched, status_sched;
    std::deque<msg::Gnss> gnss_pending;  ///< fixes taken, not yet delivered (latency)
    Nanos gnss_latency = 0;
    sim::Deltas default_cmd;
    std::string turbulence_applied;
    Nanos sim_dt = 2'500'000;
    Nanos t = 0;
    std::uint64_t steps = 0;
    bool stepped = false;
    bool crash_reported = false;
    bool boot_reported = false;
  } f_;
  /// The sensor and actuator parameters a mission or a user set (they keep their value when
  /// sensor_profile changes; the others take the new profile's defaults).
  std::set<const tern::ParamBase*> set_explicitly_;
  bool applying_profile_ = false;
};

}  // namespace tern::sim_aero
