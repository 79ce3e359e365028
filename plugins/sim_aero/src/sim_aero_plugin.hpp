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
#include "tern_sim_aero/trim.hpp"

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
  void configure() override {
    declare(actuators_in_, "actuators", "surface deflections (rad) and throttle (0..1)", tern::Need::optional);
    declare(imu_out_, "imu", "accelerometer and gyro");
    declare(gnss_out_, "gnss", "GNSS fix");
    declare(baro_out_, "baro", "static pressure");
    declare(diff_out_, "diff_pressure", "pitot differential pressure");
    declare(mag_out_, "mag", "magnetometer");
    declare(range_out_, "range", "downward range finder (lidar): distance to the ground along body +z");
    declare(truth_out_, "truth", "true state of the simulated aircraft");
    declare(pilot_in_, "pilot", "a pilot's sticks and switches (console, joystick), reported on rc", tern::Need::optional);
    declare(rc_out_, "rc", "RC receiver: the pilot input's sticks and switches, else centred, no override");
    declare(status_out_, "fcu_status", "simulated flight-control unit status");

    declare(aircraft_, "aircraft", "",
            ParamSpec("", 0, 0, "aircraft file (tern or ROSflight format); empty: the mission's aircraft").as_path().start_only());
    declare(sim_rate_, "sim_rate", 400.0, ParamSpec("Hz", 50, 20000, "integration rate (fixed RK4 sub-steps)").start_only());
    declare(init_mode_, "init_mode", "ground",
            ParamSpec("", 0, 0, "initial state: on the ground at rest, in the air level, or at trim")
                .one_of({"ground", "air", "trim"})
                .start_only());
    declare(init_position_, "init_position", std::vector<double>{0.0, 0.0},
            ParamSpec("m", -1e6, 1e6, "initial north, east position").of_size(2).start_only());
    declare(init_altitude_, "init_altitude", 100.0, ParamSpec("m", 0, 10000, "initial height above the ground (air, trim)").start_only());
    declare(init_airspeed_, "init_airspeed", 17.0, ParamSpec("m/s", 0, 100, "initial airspeed (air, trim)").start_only());
    declare(init_heading_, "init_heading", 0.0, ParamSpec("rad", -7, 7, "initial heading psi").start_only());
    declare(
        parking_brake_, "parking_brake", 1.0,
        ParamSpec("", 0.0, 1.0, "init_mode ground: the brakes set until the first actuator command (the aircraft parked)").start_only());
    declare(wind_, "wind", std::vector<double>{0.0, 0.0, 0.0},
            ParamSpec("m/s", -50, 50, "steady wind, NED (direction the air moves to)").of_size(3));
    declare(turbulence_, "turbulence", "none",
            ParamSpec("", 0, 0, "Dryden turbulence, MIL-F-8785C low altitude").one_of({"none", "light", "moderate"}));
    declare(gusts_, "gusts", std::vector<double>{},
            ParamSpec("", -1e6, 1e6, "scheduled 1-cosine gusts: groups of [start s, duration s, w_n, w_e, w_d m/s]").start_only());
    declare(gust_rate_, "gust_rate", 0.0, ParamSpec("1/s", 0, 10, "random 1-cosine gusts per second (0: none)").start_only());
    declare(gust_max_, "gust_max", 0.0, ParamSpec("m/s", 0, 30, "peak speed of random gusts, uniform in [0, max]").start_only());
    declare(gust_min_duration_, "gust_min_duration", 1.0, ParamSpec("s", 0.01, 100, "shortest random gust").start_only());
    declare(gust_max_duration_, "gust_max_duration", 3.0, ParamSpec("s", 0.01, 100, "longest random gust").start_only());

    declare(sensor_profile_, "sensor_profile", sim::sensor_profile_names().front(),
            ParamSpec("", 0, 0,
                      "sensor and actuator defaults: rosflight (ROSflight's simulator), realistic "
                      "(datasheets: u-blox M8N, ICM-20602, MS5611, MS4525DO), ideal (no errors)")
                .one_of(sim::sensor_profile_names())
                .start_only());
    declare_sensor(imu_, "imu", 400.0);
    declare_sensor(mag_, "mag", 50.0);
    declare_sensor(baro_, "baro", 100.0);
    declare_sensor(diff_, "diff_pressure", 100.0);
    declare_sensor(gnss_, "gnss", 10.0);
    declare_sensor(range_, "range", 50.0);
    declare(date_, "date", "2025-07-01",
            ParamSpec("", 0, 0,
                      "the world's date, ISO YYYY-MM-DD: the Earth's magnetic field is the World Magnetic Model's at the "
                      "origin on this day (2025-07-01: a fixed day in WMM2025's first year, so flights repeat)")
                .start_only());
    declare_error_model();
    declare(pitot_cover_, "pitot_cover", 0.0,
            ParamSpec("s", 0, 600,
                      "the pilot keeps the pitot covered until this flight time (the boot calibration then "
                      "zeroes the sensor, not the wind)"));
    declare(truth_rate_, "truth_rate", 400.0, ParamSpec("Hz", 1, 20000, "rate of the truth topic").start_only());
    declare(rc_rate_, "rc_rate", 50.0, ParamSpec("Hz", 0, 1000, "rate of the rc topic (0: off)").start_only());
    declare(status_rate_, "status_rate", 10.0, ParamSpec("Hz", 0, 1000, "rate of the fcu_status topic (0: off)").start_only());
    declare(armed_, "armed", true, ParamSpec("", 0, 0, "simulated FCU reports armed"));
    declare(offboard_, "offboard", true, ParamSpec("", 0, 0, "simulated FCU follows tern's commands"));

    // Check what can be checked without files.
    for (SensorSlot* s : slots()) (void)period_of(s->rate, s->rate.name());
    (void)period_of(sim_rate_, "sim_rate");
    (void)period_of(truth_rate_, "truth_rate");
    if (rc_rate_() > 0) (void)period_of(rc_rate_, "rc_rate");
    if (status_rate_() > 0) (void)period_of(status_rate_, "status_rate");
    for (SensorSlot* s : slots()) {
      (void)dropouts_of(*s);
      (void)windows_of(s->nan);
    }
    check_gusts();
    if (context().describing()) return;

    load_aircraft();
  }

  void start() override { initialise(); }
  void reset() override { initialise(); }

  void step(Nanos now) override {
    if (!f_.sim) initialise();
    sim::Deltas cmd = f_.default_cmd;
    if (actuators_in_.has_value()) {
      const msg::Actuators& a = actuators_in_.get();
      cmd.delta_a = a.delta_a;
      cmd.delta_e = a.delta_e;
      cmd.delta_r = a.delta_r;
      cmd.delta_t = a.delta_t;
      cmd.brake = a.brake;
    }
    f_.sim->set_command(cmd);  // throws on NaN: an error, not a NaN flight
    apply_live_params();
    if (!f_.stepped) {
      publish_due(f_.t);
      f_.stepped = true;
    }
    while (f_.t < now) {
      const Nanos dt = std::min(f_.sim_dt, now - f_.t);
      f_.sim->step(static_cast<double>(dt) * 1e-9);
      f_.t += dt;
      ++f_.steps;
      publish_due(f_.t);
    }
    if (f_.sim->crashed() && !f_.crash_reported) report_crash();
  }

  std::vector<std::pair<std::string, double>> summary() const override {
    std::vector<std::pair<std::string, double>> s = {{"sim_steps", static_cast<double>(f_.steps)},
                                                     {"sim_crashed", f_.sim && f_.sim->crashed() ? 1.0 : 0.0}};
    if (f_.sim && f_.sim->crashed()) {
      const ImpactFacts m = impact();
      s.insert(s.end(), {{"impact_t_s", m.t},
                         {"impact_p_n_m", m.p_ned.x()},
                         {"impact_p_e_m", m.p_ned.y()},
                         {"impact_ground_speed_mps", m.v_ned.head<2>().norm()},
                         {"impact_sink_rate_mps", m.v_ned.z()},
                         {"impact_airspeed_mps", m.Va},
                         {"impact_roll_deg", m.phi * 180.0 / tern::kPi},
                         {"impact_pitch_deg", m.theta * 180.0 / tern::kPi}});
      // what struck (end_detail names it): the gear's hard point or wheel, 1-based (0: none,
      // the CG), and how fast that point moved
      const auto& im = f_.sim->impact();
      s.insert(s.end(), {{"impact_hard_point", static_cast<double>(im.hard_point + 1)},
                         {"impact_wheel", static_cast<double>(im.wheel + 1)},
                         {"impact_point_speed_mps", im.point_speed},
                         {"impact_point_sink_mps", im.point_sink}});
    }
    return s;
  }

 private:
  void declare_sensor(SensorSlot& s, const std::string& name, double rate) {
    declare(s.rate, name + "_rate", rate, ParamSpec("Hz", 1, 20000, name + " sample rate").start_only());
    declare(s.enabled, name + "_enabled", true, ParamSpec("", 0, 0, name + " on (false: never published)").start_only());
    declare(s.dropout, name + "_dropout", std::vector<double>{},
            ParamSpec("s", 0, 1e9, name + " drop-out windows: pairs [start, end) of flight time").start_only());
    declare(s.nan, name + "_nan", std::vector<double>{},
            ParamSpec("s", 0, 1e9, name + " windows of NaN samples (a failing sensor): pairs [start, end) of flight time").start_only());
  }
  std::vector<SensorSlot*> slots() { return {&imu_, &mag_, &baro_, &diff_, &gnss_, &range_}; }

  Nanos period_of(double hz, const std::string& name) const {
    try {
      return tern::period_from_hz(hz);
    } catch (const std::invalid_argument& e) {
      throw ParamError("parameter '" + context().instance_name() + "." + name + "': " + e.what());
    }
  }
  std::vector<std::pair<Nanos, Nanos>> dropouts_of(const SensorSlot& s) const { return windows_of(s.dropout); }
  std::vector<std::pair<Nanos, Nanos>> windows_of(const tern::Param<std::vector<double>>& param) const {
    const auto& v = param();
    const std::string name = context().instance_name() + "." + param.name();
    if (v.size() % 2 != 0)
      throw ParamError("parameter '" + name + "': needs pairs [start, end], got " + std::to_string(v.size()) + " values");
    std::vector<std::pair<Nanos, Nanos>> out;
    for (std::size_t i = 0; i < v.size(); i += 2) {
      if (!(v[i + 1] > v[i])) throw ParamError("parameter '" + name + "': window " + std::to_string(i / 2) + " ends before it starts");
      out.emplace_back(tern::from_seconds(v[i]), tern::from_seconds(v[i + 1]));
    }
    return out;
  }
  void check_gusts() const {
    const auto& g = gusts_();
    if (g.size() % 5 != 0) {
      throw ParamError("parameter '" + context().instance_name() + ".gusts': needs groups of 5 [start, duration, w_n, w_e, w_d], got " +
                       std::to_string(g.size()) + " values");
    }
    for (std::size_t i = 0; i < g.size(); i += 5) {
      if (!(g[i + 1] > 0))
        throw ParamError("parameter '" + context().instance_name() + ".gusts': gust " + std::to_string(i / 5) + " has duration <= 0");
    }
  }

  // The profile's values are the defaults of every sensor and actuator parameter.
  void declare_error_model() {
    const sim::SensorParams d = profile_defaults();
    const sim::ActuatorParams da = sim::actuator_profile(sensor_profile_());
    for (std::size_t i = 0; i < std::size(kSensorReals); ++i) {
      const SensorReal& r = kSensorReals[i];
      declare(sensor_reals_[i], r.name, d.*r.field, ParamSpec(r.unit, r.min, r.max, r.description).start_only());
    }
    for (std::size_t i = 0; i < std::size(kSensorVectors); ++i) {
      const SensorVector& r = kSensorVectors[i];
      const Eigen::Vector3d& v = d.*r.field;
      declare(sensor_vectors_[i], r.name, std::vector<double>{v.x(), v.y(), v.z()},
              ParamSpec(r.unit, r.min, r.max, r.description).of_size(3).start_only());
    }
    for (std::size_t i = 0; i < std::size(kActuatorReals); ++i) {
      const ActuatorReal& r = kActuatorReals[i];
      declare(actuator_reals_[i], r.name, da.*r.field, ParamSpec(r.unit, r.min, r.max, r.description).start_only());
    }
    declare(gnss_start_steady_, "gnss_start_steady", d.gnss_start_steady,
            ParamSpec("", 0, 0, "GNSS position error starts in its steady state (false: at zero)").start_only());
    declare(calibrate_at_boot_, "calibrate_at_boot", d.calibrate_at_boot,
            ParamSpec("", 0, 0, "the FCU calibrates the gyro and zeroes the pitot at power-up, arming after (ROSflight sensors.cpp)")
                .start_only());
    declare(
        accel_calibrated_level_, "accel_calibrated_level", d.accel_calibrated_level,
        ParamSpec("", 0, 0, "the FCU's stored accelerometer offset was taken with the aircraft taken as level (ROSflight calibrate_accel)")
            .start_only());
    declare(gnss_num_sats_, "gnss_num_sats", std::int64_t{d.gnss_num_sats},
            ParamSpec("", 0, 64, "reported satellites in use").start_only());
    for (std::size_t i = 0; i < std::size(kSensorReals); ++i)
      track_explicit(sensor_reals_[i], is_origin_row(kSensorReals[i]) ? std::function<void()>([this] { sync_world_field(); }) : nullptr);
    for (auto& p : sensor_vectors_) track_explicit(p);
    for (auto& p : actuator_reals_) track_explicit(p);
    track_explicit(gnss_start_steady_);
    track_explicit(calibrate_at_boot_);
    track_explicit(accel_calibrated_level_);
    track_explicit(gnss_num_sats_);
    sensor_profile_.on_change([this](const std::string&) { apply_profile_defaults(); });
    date_.on_change([this](const std::string&) { sync_world_field(); });
    sync_world_field();  // the origin and date the mission sets
  }

  /// The profile's sensor and actuator values, the Earth's field being the model's at the
  /// profile's origin on `date`.
  sim::SensorParams profile_defaults() const {
    sim::SensorParams d = sim::sensor_profile(sensor_profile_());
    d.date = world_date();
    return sim::with_earth_field(d);
  }

  // ---- the world's magnetic field: mag_declination / _inclination / _intensity that nobody set
  // follow the World Magnetic Model at the origin on `date` (sim::earth_field); a set one overrides.
  static bool is_field_row(const SensorReal& r) {
    return r.field == &sim::SensorParams::mag_declination || r.field == &sim::SensorParams::mag_inclination ||
           r.field == &sim::SensorParams::mag_intensity;
  }
  static bool is_origin_row(const SensorReal& r) {
    return r.field == &sim::SensorParams::origin_lat || r.field == &sim::SensorParams::origin_lon ||
           r.field == &sim::SensorParams::origin_alt;
  }
  /// `date` as a decimal year; a bad date throws ParamError naming the parameter.
  double world_date() const {
    try {
      return tern::decimal_year(date_());
    } catch (const std::invalid_argument& e) {
      throw ParamError("parameter '" + context().instance_name() + ".date': " + e.what());
    }
  }
  /// The field parameters nobody set take the model's values at the current origin and date, so
  /// that they show what the world uses.
  void sync_world_field() {
    const sim::SensorParams p = sim::with_earth_field(sensor_params());
    const bool was_applying = std::exchange(applying_profile_, true);
    for (std::size_t i = 0; i < std::size(kSensorReals); ++i) {
      if (is_field_row(kSensorReals[i]) && !set_explicitly_.count(&sensor_reals_[i])) sensor_reals_[i].set(p.*kSensorReals[i].field);
    }
    applying_profile_ = was_applying;
  }

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
  void apply_profile_defaults() {
    const sim::SensorParams d = sim::sensor_profile(sensor_profile_());  // the field: NaN, from the model
    const sim::ActuatorParams da = sim::actuator_profile(sensor_profile_());
    applying_profile_ = true;
    const auto take = [this](tern::ParamBase& p, const tern::ParamValue& v) {
      if (!set_explicitly_.count(&p)) p.set(v);
    };
    try {
      for (std::size_t i = 0; i < std::size(kSensorReals); ++i)
        if (!is_field_row(kSensorReals[i])) take(sensor_reals_[i], d.*kSensorReals[i].field);
      for (std::size_t i = 0; i < std::size(kSensorVectors); ++i) {
        const Eigen::Vector3d& v = d.*kSensorVectors[i].field;
        take(sensor_vectors_[i], std::vector<double>{v.x(), v.y(), v.z()});
      }
      for (std::size_t i = 0; i < std::size(kActuatorReals); ++i) take(actuator_reals_[i], da.*kActuatorReals[i].field);
      take(gnss_start_steady_, d.gnss_start_steady);
      take(calibrate_at_boot_, d.calibrate_at_boot);
      take(accel_calibrated_level_, d.accel_calibrated_level);
      take(gnss_num_sats_, std::int64_t{d.gnss_num_sats});
    } catch (...) {
      applying_profile_ = false;
      throw;
    }
    applying_profile_ = false;
    sync_world_field();
  }

  sim::SensorParams sensor_params() const {
    sim::SensorParams p;
    for (std::size_t i = 0; i < std::size(kSensorReals); ++i) {
      const bool from_model = is_field_row(kSensorReals[i]) && !set_explicitly_.count(&sensor_reals_[i]);
      p.*kSensorReals[i].field = from_model ? sim::kFromMagneticModel : sensor_reals_[i]();
    }
    p.date = world_date();
    for (std::size_t i = 0; i < std::size(kSensorVectors); ++i) {
      const auto& v = sensor_vectors_[i]();
      p.*kSensorVectors[i].field = Eigen::Vector3d(v[0], v[1], v[2]);
    }
    p.gnss_start_steady = gnss_start_steady_();
    p.calibrate_at_boot = calibrate_at_boot_();
    p.accel_calibrated_level = accel_calibrated_level_();
    p.gnss_num_sats = static_cast<int>(gnss_num_sats_());
    return p;
  }
  sim::ActuatorParams actuator_params() const {
    sim::ActuatorParams a;
    for (std::size_t i = 0; i < std::size(kActuatorReals); ++i) a.*kActuatorReals[i].field = actuator_reals_[i]();
    return a;
  }
  /// Loads the aircraft file (again, when `aircraft` changed between flights).
  void load_aircraft() {
    std::string path = aircraft_();
    if (path.empty()) path = context().aircraft_file().string();
    if (path.empty()) {
      throw ParamError("parameter '" + context().instance_name() +
                       ".aircraft': no aircraft file (set it, or the mission config's aircraft: key)");
    }
    if (aircraft_data_ && path == aircraft_path_) return;
    aircraft_data_ = tern::load_aircraft(path);
    aircraft_path_ = path;
    log().info("aircraft {} from {}", aircraft_data_->name, path);
  }

  void initialise() {
    if (context().describing()) throw std::runtime_error("sim_aero: no aircraft loaded (configure() ran in describing mode)");
    load_aircraft();
    f_ = Flight{};
    const std::uint64_t seed = context().seed();
    f_.sim = std::make_unique<sim::Simulator>(*aircraft_data_, seed);
    f_.sensors = std::make_unique<sim::Sensors>(sensor_params(), seed ^ 0x9E3779B97F4A7C15ull);
    f_.rangefinder = std::make_unique<sim::RangeFinder>(f_.sensors->params(), seed ^ 0xD1B54A32D192ED03ull);
    f_.sim->set_actuators(actuator_params());
    report_earth_field();
    f_.gnss_latency = tern::from_seconds(f_.sensors->params().gnss_latency);
    f_.sim_dt = period_of(sim_rate_(), "sim_rate");
    for (SensorSlot* s : slots()) {
      s->schedule = sim::SensorSchedule{};
      s->schedule.period = period_of(s->rate(), s->rate.name());
      s->schedule.enabled = s->enabled();
      s->schedule.dropouts = dropouts_of(*s);
      s->nan_windows = windows_of(s->nan);
    }
    f_.truth_sched.period = period_of(truth_rate_(), "truth_rate");
    f_.rc_sched.period = rc_rate_() > 0 ? period_of(rc_rate_(), "rc_rate") : 0;
    f_.status_sched.period = status_rate_() > 0 ? period_of(status_rate_(), "status_rate") : 0;

    // Wind.
    f_.sim->set_turbulence(sim::dryden_preset(turbulence_()));
    f_.turbulence_applied = turbulence_();
    const auto& g = gusts_();
    for (std::size_t i = 0; i + 4 < g.size(); i += 5) {
      sim::CosineGust c;
      c.start = g[i];
      c.duration = g[i + 1];
      c.amplitude = Eigen::Vector3d(g[i + 2], g[i + 3], g[i + 4]);
      f_.sim->gusts().add(c);
    }
    f_.sim->gusts().freeze_schedule();
    f_.sim->gusts().set_random(gust_rate_(), gust_max_(), gust_min_duration_(), gust_max_duration_());
    f_.sim->set_steady_wind(Eigen::Vector3d(wind_()[0], wind_()[1], wind_()[2]));
    f_.sim->sync_wind();  // the samples at t = 0 see the wind

    // Initial state.
    const auto& ac = f_.sim->aircraft();
    const Eigen::Vector2d ne(init_position_()[0], init_position_()[1]);
    const std::string mode = init_mode_();
    if (mode == "ground") {
      f_.sim->set_state(sim::rest_state(ac, ne.x(), ne.y(), init_heading_()));
      f_.default_cmd.brake = parking_brake_();
    } else if (mode == "air") {
      f_.sensors->calibrated_before_start();
      f_.sim->set_state(sim::make_state({ne.x(), ne.y(), -init_altitude_()}, {init_airspeed_(), 0, 0}, 0, 0, init_heading_()));
    } else {
      f_.sensors->calibrated_before_start();
      sim::TrimRequest req;
      req.Va = init_airspeed_();
      req.altitude = init_altitude_();
      req.psi = init_heading_();
      const sim::TrimResult tr = sim::compute_trim(ac, req);
      sim::StateVector x = tr.x;
      x[sim::PN] = ne.x();
      x[sim::PE] = ne.y();
      f_.sim->set_state(x, tr.delta);
      f_.default_cmd = tr.delta;
      log().info("trim at {} m/s: alpha {:.4f} rad, delta_e {:.4f} rad, delta_t {:.3f}", req.Va, tr.alpha, tr.delta.delta_e,
                 tr.delta.delta_t);
    }
  }

  /// Says once per flight which field the world has (and which settings override the model), and
  /// warns when the model is extrapolated.
  void report_earth_field() {
    const tern::MagneticField& m = f_.sensors->earth_field();
    const auto& p = f_.sensors->params();
    std::string source = fmt::format("{} at {:.5f}, {:.5f} on {}", m.model, p.origin_lat, p.origin_lon, date_());
    for (std::size_t i = 0; i < std::size(kSensorReals); ++i)
      if (is_field_row(kSensorReals[i]) && set_explicitly_.count(&sensor_reals_[i]))
        source += fmt::format("; {} set", kSensorReals[i].name);
    if (m.model == "mag_* settings") source = "mag_declination, mag_inclination, mag_intensity set";
    log().info("Earth's field: declination {:.3f} deg, inclination {:.3f} deg, intensity {:.0f} nT ({})", m.declination / tern::kRadPerDeg,
               m.inclination / tern::kRadPerDeg, m.intensity * 1e9, source);
    if (m.extrapolated) log().warn("the world's date {} is outside {}'s span: its field is extrapolated", date_(), m.model);
  }

  // ---- ground impact
  // The simulator's crash: the CG below the ground, a hard point on it or a wheel touching down
  // faster than the gear's max_sink_rate (it freezes the aircraft there). A crash ends the
  // flight (end_reason "crash"): nothing after it is a flight worth logging.
  struct ImpactFacts {
    double t;                      // s, flight time (the simulator's clock starts with the flight)
    Eigen::Vector3d p_ned, v_ned;  // m, m/s (v_d > 0: sinking)
    double Va, phi, theta;         // m/s, rad, rad
  };
  ImpactFacts impact() const {
    const auto& m = f_.sim->impact();
    const Eigen::Quaterniond q = sim::attitude(m.x);
    const Eigen::Vector3d eul = tern::euler_from_quaternion(q);
    return {m.t, m.x.segment<3>(sim::PN), q * m.x.segment<3>(sim::U), m.Va, eul.x(), eul.y()};
  }
  void report_crash() {
    f_.crash_reported = true;
    const ImpactFacts m = impact();
    const std::string detail = fmt::format(
        "the aircraft hit the ground ({}) at t = {:.3f} s at p_n {:.1f} m, p_e {:.1f} m: ground speed {:.1f} m/s, sink rate {:.1f} m/s, "
        "airspeed {:.1f} m/s, roll {:.0f} deg, pitch {:.0f} deg",
        f_.sim->impact().what, m.t, m.p_ned.x(), m.p_ned.y(), m.v_ned.head<2>().norm(), m.v_ned.z(), m.Va, m.phi * 180.0 / tern::kPi,
        m.theta * 180.0 / tern::kPi);
    log().warn("{}", detail);
    context().end_flight("crash", detail);
  }

  void apply_live_params() {
    f_.sim->set_steady_wind(Eigen::Vector3d(wind_()[0], wind_()[1], wind_()[2]));
    if (turbulence_() != f_.turbulence_applied) {
      f_.sim->set_turbulence(sim::dryden_preset(turbulence_()));
      f_.turbulence_applied = turbulence_();
    }
  }

  void publish_due(Nanos t) {
    using Poll = sim::SensorSchedule::Poll;
    std::optional<sim::Truth> truth;
    auto get_truth = [&]() -> const sim::Truth& {
      if (!truth) {
        truth.emplace();
        truth->x = f_.sim->state();
        if (f_.sensors->params().imu_position.isZero()) {
          truth->fm = f_.sim->evaluate();
        } else {  // the lever arm needs the angular acceleration: one evaluation gives both
          truth->omega_dot =
              sim::derivative(f_.sim->aircraft(), truth->x, f_.sim->surfaces(), f_.sim->wind(), &truth->fm).segment<3>(sim::P);
        }
        truth->mass = f_.sim->aircraft().mass;
        truth->rho = f_.sim->aircraft().rho;
        truth->throttle = f_.sim->surfaces().delta_t;
      }
      return *truth;
    };
    auto run = [&](SensorSlot& s, auto&& sample) {
      const Poll p = s.schedule.poll(t);
      if (p == Poll::idle) return;
      sample(p == Poll::sample);
    };
    run(imu_, [&](bool ok) {
      if (!ok) return;
      const auto m = f_.sensors->imu(get_truth(), imu_.schedule.dt_since_last(t));
      imu_.schedule.last_sample = t;
      msg::Imu out;
      out.stamp = t;
      out.accel = m.accel;
      out.gyro = m.gyro;
      out.temperature = m.temperature;
      if (imu_.non_finite(t)) out.accel = out.gyro = Eigen::Vector3d::Constant(kNaN);
      imu_out_.publish(out);
    });
    run(mag_, [&](bool ok) {
      if (!ok) return;
      const auto m = f_.sensors->mag(get_truth(), mag_.schedule.dt_since_last(t));
      mag_.schedule.last_sample = t;
      msg::Mag out;
      out.stamp = t;
      out.field = mag_.non_finite(t) ? Eigen::Vector3d::Constant(kNaN) : m.field;
      mag_out_.publish(out);
    });
    run(baro_, [&](bool ok) {
      if (!ok) return;
      const auto m = f_.sensors->baro(get_truth(), baro_.schedule.dt_since_last(t));
      baro_.schedule.last_sample = t;
      msg::Baro out;
      out.stamp = t;
      out.pressure = baro_.non_finite(t) ? kNaN : m.pressure;
      out.temperature = m.temperature;
      baro_out_.publish(out);
    });
    run(range_, [&](bool ok) {
      if (!ok) return;
      range_.schedule.last_sample = t;
      msg::Range out;
      out.stamp = t;
      out.distance = range_.non_finite(t) ? kNaN : f_.rangefinder->distance(get_truth().x);
      out.min_range = f_.sensors->params().range_min;
      out.max_range = f_.sensors->params().range_max;
      range_out_.publish(out);
    });
    run(diff_, [&](bool ok) {
      if (!ok) return;
      const double dt = diff_.schedule.dt_since_last(t);
      const auto m = t < tern::from_seconds(pitot_cover_()) ? f_.sensors->diff_pressure(covered_pitot(get_truth()), dt)
                                                            : f_.sensors->diff_pressure(get_truth(), dt);
      diff_.schedule.last_sample = t;
      msg::DiffPressure out;
      out.stamp = t;
      out.pressure = diff_.non_finite(t) ? kNaN : m.pressure;
      out.temperature = m.temperature;
      diff_out_.publish(out);
    });
    run(gnss_, [&](bool ok) {
      msg::Gnss out;
      out.stamp = t;
      out.time_of_validity = t;
      if (ok) {
        const auto m = f_.sensors->gnss(get_truth(), gnss_.schedule.dt_since_last(t));
        gnss_.schedule.last_sample = t;
        out.fix_type = msg::FixType::fix_3d;
        out.num_sats = static_cast<std::uint8_t>(m.num_sats);
        out.lat = m.lat;
        out.lon = m.lon;
        out.alt = m.alt;
        out.vel = m.vel_ned;
        out.h_acc = m.h_acc;
        out.v_acc = m.v_acc;
        out.s_acc = m.s_acc;
        if (gnss_.non_finite(t)) out.lat = out.lon = out.alt = kNaN;
      } else if (!gnss_.schedule.enabled) {
        return;  // switched off: silent
      }
      // In a drop-out window the receiver still reports, without a fix. Every report leaves
      // the receiver gnss_latency after its time of validity.
      out.stamp = t + f_.gnss_latency;
      f_.gnss_pending.push_back(out);
    });
    while (!f_.gnss_pending.empty() && f_.gnss_pending.front().stamp <= t) {
      gnss_out_.publish(f_.gnss_pending.front());
      f_.gnss_pending.pop_front();
    }
    if (f_.truth_sched.poll(t) == Poll::sample) publish_truth(t, get_truth());
    if (f_.rc_sched.poll(t) == Poll::sample) {
      msg::Rc rc = pilot_in_.has_value() ? *pilot_in_ : msg::Rc{};
      rc.stamp = t;
      rc_out_.publish(rc);
    }
    if (f_.status_sched.poll(t) == Poll::sample) {
      msg::FcuStatus st;
      st.stamp = t;
      st.armed = armed_() && boot_calibrated(t);
      st.offboard = offboard_();
      const auto& ac = f_.sim->aircraft();
      const double V_in = ac.prop.V_max * f_.sim->surfaces().delta_t;
      st.battery_voltage = ac.prop.V_max;
      st.battery_current = std::max(0.0, (V_in - ac.prop.K_Q * get_truth().fm.prop.Omega) / ac.prop.R_motor);
      status_out_.publish(st);
    }
  }

  // The simulated FCU arms only after its power-up calibrations (boot_calibration.hpp); says
  // once what they found.
  // rad/s: 1 deg/s, the ICM-20602 turn-on tolerance: a calibration worse than none
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  static constexpr double kMovedDuringCalibration = 0.0175;
  bool boot_calibrated(Nanos t) {
    const sim::BootCalibration* cal = f_.sensors->boot_calibration();
    if (cal == nullptr) return true;
    if (!cal->gyro_done() || (diff_.enabled() && !cal->diff().done) || (baro_.enabled() && !cal->baro_ground().done)) return false;
    if (!f_.boot_reported) {
      f_.boot_reported = true;
      const Eigen::Vector3d b = cal->gyro_bias();
      log().info(
          "t={:.3f} s: FCU boot calibration done: gyro bias [{:.5f}, {:.5f}, {:.5f}] rad/s, pitot zero {:.2f} Pa, "
          "ground pressure {:.1f} Pa ({} restarts for movement)",
          tern::to_seconds(t), b.x(), b.y(), b.z(), cal->diff().offset, cal->baro_ground().offset,
          cal->gyro_restarts() + cal->diff().restarts + cal->baro_ground().restarts);
      // The world knows what the FCU cannot: whether the aircraft sat still while it averaged.
      const double off = (b - f_.sensors->gyro_bias()).norm();
      if (off > kMovedDuringCalibration)
        log().warn(
            "the aircraft moved during the FCU's gyro calibration: the bias it removes is {:.2f} deg/s off "
            "(weathervaning in the wind? point it into the wind, as for a takeoff)",
            off * 180.0 / tern::kPi);
    }
    return true;
  }

  /// The truth a covered pitot sees: still air.
  static sim::Truth covered_pitot(sim::Truth t) {
    t.fm.air.v_air.setZero();
    t.fm.air.Va = 0.0;
    return t;
  }

  void publish_truth(Nanos t, const sim::Truth& tr) {
    const sim::StateVector& x = tr.x;
    msg::State s;
    s.stamp = t;
    s.p_n = x[sim::PN];
    s.p_e = x[sim::PE];
    s.p_d = x[sim::PD];
    s.u = x[sim::U];
    s.v = x[sim::V];
    s.w = x[sim::W];
    const Eigen::Quaterniond q = sim::attitude(x);
    const Eigen::Vector3d v_ned = q * Eigen::Vector3d(x[sim::U], x[sim::V], x[sim::W]);
    s.v_n = v_ned.x();
    s.v_e = v_ned.y();
    s.v_d = v_ned.z();
    const Eigen::Vector3d eul = tern::euler_from_quaternion(q);
    s.phi = eul.x();
    s.theta = eul.y();
    s.psi = eul.z();
    s.quat = q;
    s.p = x[sim::P];
    s.q = x[sim::Q];
    s.r = x[sim::R];
    s.Va = tr.fm.air.Va;
    s.alpha = tr.fm.air.alpha;
    s.beta = tr.fm.air.beta;
    s.Vg = v_ned.norm();
    s.chi = tern::wrap_pi(std::atan2(v_ned.y(), v_ned.x()));
    s.gamma = s.Vg > 1e-6 ? std::asin(std::clamp(-v_ned.z() / s.Vg, -1.0, 1.0)) : 0.0;
    const Eigen::Vector3d w = f_.sim->wind_ned();
    s.w_n = w.x();
    s.w_e = w.y();
    s.w_d = w.z();
    s.b_x = f_.sensors->gyro_bias().x();
    s.b_y = f_.sensors->gyro_bias().y();
    s.b_z = f_.sensors->gyro_bias().z();
    s.origin_lat = f_.sensors->params().origin_lat;
    s.origin_lon = f_.sensors->params().origin_lon;
    s.origin_alt = f_.sensors->params().origin_alt;
    s.origin_valid = true;
    s.valid = true;
    truth_out_.publish(s);
  }

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
  tern::Param<bool> calibrate_at_boot_;
  tern::Param<bool> accel_calibrated_level_;
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
