// SimAero: its parameters and ports declared (configure), the sensor profiles and error models, the
// aircraft loaded and a flight initialised (see sim_aero_plugin.hpp).
#include "sim_aero_plugin.hpp"

namespace tern::sim_aero {

void SimAero::configure() {
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
  declare(parking_brake_, "parking_brake", 1.0,
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

void SimAero::declare_sensor(SensorSlot& s, const std::string& name, double rate) {
  declare(s.rate, name + "_rate", rate, ParamSpec("Hz", 1, 20000, name + " sample rate").start_only());
  declare(s.enabled, name + "_enabled", true, ParamSpec("", 0, 0, name + " on (false: never published)").start_only());
  declare(s.dropout, name + "_dropout", std::vector<double>{},
          ParamSpec("s", 0, 1e9, name + " drop-out windows: pairs [start, end) of flight time").start_only());
  declare(s.nan, name + "_nan", std::vector<double>{},
          ParamSpec("s", 0, 1e9, name + " windows of NaN samples (a failing sensor): pairs [start, end) of flight time").start_only());
}

Nanos SimAero::period_of(double hz, const std::string& name) const {
  try {
    return tern::period_from_hz(hz);
  } catch (const std::invalid_argument& e) {
    throw ParamError("parameter '" + context().instance_name() + "." + name + "': " + e.what());
  }
}

std::vector<std::pair<Nanos, Nanos>> SimAero::windows_of(const tern::Param<std::vector<double>>& param) const {
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

void SimAero::check_gusts() const {
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

void SimAero::declare_error_model() {
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
  declare(gnss_sky_, "gnss_sky", d.gnss_sky,
          ParamSpec("", 0, 0, "the GNSS antenna's sky view: satellites lost when it faces away from them (gnss_sky.hpp)").start_only());
  declare(calibrate_at_boot_, "calibrate_at_boot", d.calibrate_at_boot,
          ParamSpec("", 0, 0, "the FCU calibrates the gyro and zeroes the pitot at power-up, arming after (ROSflight sensors.cpp)")
              .start_only());
  declare(
      accel_calibrated_level_, "accel_calibrated_level", d.accel_calibrated_level,
      ParamSpec("", 0, 0, "the FCU's stored accelerometer offset was taken with the aircraft taken as level (ROSflight calibrate_accel)")
          .start_only());
  declare(
      accel_calibrated_at_power_up_, "accel_calibrated_at_power_up", d.accel_calibrated_at_power_up,
      ParamSpec("", 0, 0, "that offset was taken after this power-up (ROSflight's calibrate_imu before arming): it holds the turn-on bias")
          .start_only());
  declare(gnss_num_sats_, "gnss_num_sats", std::int64_t{d.gnss_num_sats}, ParamSpec("", 0, 64, "reported satellites in use").start_only());
  for (std::size_t i = 0; i < std::size(kSensorReals); ++i)
    track_explicit(sensor_reals_[i], is_origin_row(kSensorReals[i]) ? std::function<void()>([this] { sync_world_field(); }) : nullptr);
  for (auto& p : sensor_vectors_) track_explicit(p);
  for (auto& p : actuator_reals_) track_explicit(p);
  track_explicit(gnss_start_steady_);
  track_explicit(gnss_sky_);
  track_explicit(calibrate_at_boot_);
  track_explicit(accel_calibrated_level_);
  track_explicit(accel_calibrated_at_power_up_);
  track_explicit(gnss_num_sats_);
  sensor_profile_.on_change([this](const std::string&) { apply_profile_defaults(); });
  date_.on_change([this](const std::string&) { sync_world_field(); });
  sync_world_field();  // the origin and date the mission sets
}

sim::SensorParams SimAero::profile_defaults() const {
  sim::SensorParams d = sim::sensor_profile(sensor_profile_());
  d.date = world_date();
  return sim::with_earth_field(d);
}

void SimAero::apply_profile_defaults() {
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
    take(gnss_sky_, d.gnss_sky);
    take(calibrate_at_boot_, d.calibrate_at_boot);
    take(accel_calibrated_level_, d.accel_calibrated_level);
    take(accel_calibrated_at_power_up_, d.accel_calibrated_at_power_up);
    take(gnss_num_sats_, std::int64_t{d.gnss_num_sats});
  } catch (...) {
    applying_profile_ = false;
    throw;
  }
  applying_profile_ = false;
  sync_world_field();
}

sim::SensorParams SimAero::sensor_params() const {
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
  p.gnss_sky = gnss_sky_();
  p.calibrate_at_boot = calibrate_at_boot_();
  p.accel_calibrated_level = accel_calibrated_level_();
  p.accel_calibrated_at_power_up = accel_calibrated_at_power_up_();
  p.gnss_num_sats = static_cast<int>(gnss_num_sats_());
  return p;
}

sim::ActuatorParams SimAero::actuator_params() const {
  sim::ActuatorParams a;
  for (std::size_t i = 0; i < std::size(kActuatorReals); ++i) a.*kActuatorReals[i].field = actuator_reals_[i]();
  return a;
}

void SimAero::load_aircraft() {
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

void SimAero::initialise() {
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

}  // namespace tern::sim_aero
